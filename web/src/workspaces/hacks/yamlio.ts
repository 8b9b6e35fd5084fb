// Design <-> YAML (fabkit: hacks/1, docs/design-format.md).
import YAML from 'yaml';
import type { Design, Connection } from './model';
import type { Frame, Vec3 } from '../../shell/scene';

const frameOf = (f: any): Frame => ({ pos: (f?.pos ?? [0, 0, 0]).map(Number) as Vec3, rot: (f?.rot ?? [0, 0, 0]).map(Number) as Vec3 });

export function parseDesign(text: string): Design {
  const y = YAML.parse(text) ?? {};
  // One name for one primitive: the library's "ring" (files may use the paper's "hole", which
  // the server reads as the same primitive).
  const ownHole = new Set((y.environment ?? []).filter((e: any) => e?.primitives && 'hole' in e.primitives).map((e: any) => String(e.name)));
  const ring = (ref: string) => (ownHole.has(ref.split('.')[0]) ? ref : ref.replace(/\.hole$/, '.ring'));
  const conns: Connection[] = (y.connections ?? []).map((c: any) => {
    const out: Connection = { a: ring(String(c.connect[0])), b: ring(String(c.connect[1])) };
    if (c.alignment === 'flip') out.alignment = 'flip';
    if (c.fixed) out.fixed = true;
    return out;
  });
  return {
    name: y.name ?? 'untitled', description: y.description,
    environment: (y.environment ?? []).map((e: any) => ({ name: e.name, part: e.part, primitives: e.primitives, frame: frameOf(e.frame) })),
    parts: (y.parts ?? []).map((p: any) => (p.params ? { name: p.name, part: p.part, params: p.params } : { name: p.name, part: p.part })),
    target: y.target ? { name: y.target.name, part: y.target.part, primitive: y.target.primitive === 'hole' ? 'ring' : y.target.primitive, frame: frameOf(y.target.frame) } : null,
    connections: conns,
  };
}

const num = (x: number) => Math.round(x * 1e6) / 1e6;
const fr = (f: Frame) => ({ pos: f.pos.map(num), rot: f.rot.map(num) });

/** Writes the design as YAML; `exclude` lists connection indices left out (e.g. rejected ones). */
export function designToYaml(d: Design): string {
  const doc: any = { fabkit: 'hacks/1', name: d.name };
  if (d.description) doc.description = d.description;
  doc.environment = d.environment.map((e) => {
    const o: any = { name: e.name };
    if (e.part) o.part = e.part; else o.primitives = e.primitives;
    o.frame = fr(e.frame);
    return o;
  });
  doc.parts = d.parts.map((p) => (p.params && Object.keys(p.params).length ? { name: p.name, part: p.part, params: p.params } : { name: p.name, part: p.part }));
  if (d.target) {
    const t: any = { name: d.target.name, part: d.target.part };
    if (d.target.primitive) t.primitive = d.target.primitive;
    t.frame = fr(d.target.frame);
    doc.target = t;
  }
  doc.connections = d.connections.map((c) => {
    const o: any = { connect: [c.a, c.b] };
    if (c.alignment === 'flip') o.alignment = 'flip';
    if (c.fixed) o.fixed = true;
    return o;
  });
  const y = new YAML.Document(doc);
  // numbers and names in short lists stay on one line: pos: [0, 0, 200], connect: [a.x, b.y]
  YAML.visit(y, { Seq(_, node) { if (node.items.every((i: any) => YAML.isScalar(i))) node.flow = true; } });
  return y.toString();
}
