// FpDesign <-> YAML (fabkit: flatpack/1, docs/flatpack.md). Keys the editor does not edit
// (cutouts, points, joints, labels, sheet, uses) are kept as read and written back.
import YAML from 'yaml';
import { DEFAULT_MATERIAL } from './model';
import type { FpComponent, FpConnection, FpDesign, FpMaterial, FpParam, Num, Vec3N } from './model';

const KINDS = ['length', 'angle', 'count', 'number'];
const num = (v: unknown, what: string): Num => {
  if (typeof v === 'number') return v;
  if (typeof v === 'string' && v.trim()) { const n = Number(v); return Number.isFinite(n) ? n : v.trim(); }
  throw new Error(`${what} must be a number or an expression, not ${JSON.stringify(v)}`);
};
const vec3 = (v: unknown, what: string): Vec3N => {
  if (v === undefined || v === null) return [0, 0, 0];
  if (!Array.isArray(v) || v.length !== 3) throw new Error(`${what} must be a list of three values`);
  return v.map((x, i) => num(x, `${what}[${i}]`)) as Vec3N;
};
const material = (m: any, what: string): FpMaterial => {
  if (m === undefined || m === null) return { ...DEFAULT_MATERIAL };
  if (typeof m !== 'object') throw new Error(`${what} must be a map {name, thickness, kerf, interference}`);
  const n = (k: string, d: number) => (m[k] === undefined ? d : Number(m[k]));
  return { name: String(m.name ?? DEFAULT_MATERIAL.name), thickness: n('thickness', DEFAULT_MATERIAL.thickness), kerf: n('kerf', DEFAULT_MATERIAL.kerf), interference: n('interference', DEFAULT_MATERIAL.interference) };
};

const COMPONENT_KEYS = new Set(['name', 'type', 'material']);
const COMPONENT_EXTRA = new Set(['points', 'edges', 'cutouts']);
const TOP_KEYS = new Set(['fabkit', 'name', 'description', 'parameters', 'material', 'materials', 'components', 'constraints', 'connections', 'interfaces']);

export function parseDesign(text: string): FpDesign {
  let y: any;
  try { y = YAML.parse(text) ?? {}; } catch (e) { throw new Error((e as Error).message); }
  if (typeof y !== 'object' || Array.isArray(y)) throw new Error('a flat-pack design is a map (fabkit: flatpack/1, name:, components:, …)');
  if (y.fabkit !== undefined && !String(y.fabkit).startsWith('flatpack/')) throw new Error(`this is a ${y.fabkit} file, not a flat-pack design (fabkit: flatpack/1)`);
  const parameters: FpParam[] = Object.entries(y.parameters ?? {}).map(([name, v]: [string, any]) => {
    if (v !== null && typeof v === 'object') {
      const type = KINDS.includes(v.type) ? v.type : 'length';
      const p: FpParam = { name, value: v.value === undefined || v.value === null ? null : Number(v.value), type, meta: !!v.meta };
      if (v.description) p.description = String(v.description);
      return p;
    }
    return { name, value: Number(v), type: 'length', meta: false };
  });
  const components: FpComponent[] = (y.components ?? []).map((c: any, i: number) => {
    if (!c || typeof c !== 'object' || !c.name || !c.type) throw new Error(`components[${i}] needs a name and a type`);
    const out: FpComponent = { name: String(c.name), type: String(c.type), params: {} };
    if (c.material) out.material = String(c.material);
    for (const [k, v] of Object.entries(c)) {
      if (COMPONENT_KEYS.has(k)) continue;
      if (COMPONENT_EXTRA.has(k) || (v !== null && typeof v === 'object')) (out.extra ??= {})[k] = v;
      else out.params[k] = num(v, `${c.name}.${k}`);
    }
    return out;
  });
  const connections: FpConnection[] = (y.connections ?? []).map((c: any, i: number) => {
    if (!c || !Array.isArray(c.connect) || c.connect.length !== 2) throw new Error(`connections[${i}] needs connect: [A.edge, B.edge]`);
    const out: FpConnection = {
      a: String(c.connect[0]), b: String(c.connect[1]),
      alignment: c.alignment === 'front-back' ? 'front-back' : 'front-front',
      offset: vec3(c.offset, `connections[${i}].offset`), rotation: vec3(c.rotation, `connections[${i}].rotation`),
    };
    if (c.joint === 'none') out.joint = 'none';
    if (c.name) out.name = String(c.name);
    return out;
  });
  const extra: Record<string, unknown> = {};
  for (const [k, v] of Object.entries(y)) if (!TOP_KEYS.has(k)) extra[k] = v;
  const d: FpDesign = {
    name: String(y.name ?? 'untitled'), parameters, material: material(y.material, 'material'),
    materials: (y.materials ?? []).map((m: any, i: number) => material(m, `materials[${i}]`)),
    components, constraints: (y.constraints ?? []).map(String), connections,
    interfaces: Object.fromEntries(Object.entries(y.interfaces ?? {}).map(([k, v]) => [k, String(v)])), extra,
  };
  if (y.description) d.description = String(y.description);
  return d;
}

const tidy = (v: Num) => (typeof v === 'number' ? Math.round(v * 1e6) / 1e6 : v);

export function designToYaml(d: FpDesign): string {
  const doc: any = { fabkit: 'flatpack/1', name: d.name };
  if (d.description) doc.description = d.description;
  if (d.parameters.length) {
    doc.parameters = {};
    for (const p of d.parameters) {
      if (p.type === 'length' && !p.meta && !p.description && p.value !== null) { doc.parameters[p.name] = tidy(p.value); continue; }
      const o: any = {};
      if (p.value !== null) o.value = tidy(p.value);
      o.type = p.type;
      if (p.meta) o.meta = true;
      if (p.description) o.description = p.description;
      doc.parameters[p.name] = o;
    }
  }
  doc.material = { ...d.material };
  if (d.materials.length) doc.materials = d.materials.map((m) => ({ ...m }));
  doc.components = d.components.map((c) => {
    const o: any = { name: c.name, type: c.type };
    for (const [k, v] of Object.entries(c.params)) o[k] = tidy(v);
    if (c.material) o.material = c.material;
    Object.assign(o, c.extra ?? {});
    return o;
  });
  if (d.constraints.length) doc.constraints = [...d.constraints];
  doc.connections = d.connections.map((c) => {
    const o: any = { connect: [c.a, c.b], alignment: c.alignment, offset: c.offset.map(tidy), rotation: c.rotation.map(tidy) };
    if (c.joint) o.joint = c.joint;
    if (c.name) o.name = c.name;
    return o;
  });
  if (Object.keys(d.interfaces).length) doc.interfaces = { ...d.interfaces };
  Object.assign(doc, d.extra);
  const y = new YAML.Document(doc);
  // one line per component, connection, material and short list: {name: A, type: Rectangle, l: 30}
  YAML.visit(y, {
    Seq(_, node) { if (node.items.every((i: any) => YAML.isScalar(i))) node.flow = true; },
    Map(_, node, path) {
      const parent = path[path.length - 1];
      const small = node.items.every((p: any) => YAML.isScalar(p.value) || (YAML.isSeq(p.value) && p.value.items.every((i: any) => YAML.isScalar(i))));
      if (small && (YAML.isSeq(parent) || (YAML.isPair(parent) && ['material', 'joints', 'labels', 'sheet'].includes(String((parent.key as any)?.value))))) node.flow = true;
      if (YAML.isPair(parent) && path.length >= 3 && String(((path[path.length - 3] as any)?.key as any)?.value) === 'parameters') node.flow = true;
    },
  });
  return y.toString({ lineWidth: 0 });
}
