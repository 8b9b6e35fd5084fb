// RodsDesign <-> the kit's design file (`fabkit: rods/1`, docs/rods.md). The library reads and
// validates the file on the server (every preview posts it); this only maps it to the editor's
// document, keeping keys the editor does not edit.
import YAML from 'yaml';
import type { Vec3 } from '../../shell/scene';
import { emptyDesign } from './model';
import type { RodsDesign } from './model';

const PROFILES: Record<string, number> = { circle: 0, triangle: 3, square: 4, hexagon: 6, octagon: 8 };
const PROFILE_NAMES: Record<number, string> = { 0: 'circle', 3: 'triangle', 4: 'square', 6: 'hexagon', 8: 'octagon' };

function num(v: unknown, what: string): number {
  const x = Number(v);
  if (typeof v === 'boolean' || v === null || v === '' || !Number.isFinite(x)) throw new Error(`${what} must be a number, not ${JSON.stringify(v)}`);
  return x;
}
function vec(v: unknown, what: string): Vec3 {
  if (!Array.isArray(v) || v.length !== 3) throw new Error(`${what} must be [x, y, z] (mm), not ${JSON.stringify(v)}`);
  return v.map((x, k) => num(x, `${what}[${k}]`)) as Vec3;
}
const mapping = (v: unknown): Record<string, any> => (v && typeof v === 'object' && !Array.isArray(v) ? { ...(v as object) } : {});

export function parseRodsYaml(text: string): RodsDesign {
  let y: any;
  try { y = YAML.parse(text) ?? {}; } catch (e) { throw new Error((e as Error).message.split('\n')[0]); }
  if (typeof y !== 'object' || Array.isArray(y)) throw new Error('a rods design is a mapping (fabkit: rods/1, nodes, edges, ...)');
  const d = emptyDesign();
  const { fabkit: _tag, name, description, rod, joint, stock, nodes, edges, loads, supports, assembly_start, network, scale, ...extra } = y;
  if (network !== undefined) throw new Error(`this design reads its network from ${network}; the editor cannot open files a design names — use Import OBJ with that file instead`);
  d.name = name === undefined ? 'untitled' : String(name);
  d.description = description === undefined ? '' : String(description);
  const r = mapping(rod);
  if (r.diameter !== undefined) d.rod.radius = num(r.diameter, 'rod.diameter') / 2;
  if (r.radius !== undefined) d.rod.radius = num(r.radius, 'rod.radius');
  if (r.profile !== undefined) {
    const p = typeof r.profile === 'number' ? r.profile : PROFILES[String(r.profile)];
    if (p === undefined) throw new Error(`rod.profile must be circle, triangle, square, hexagon, octagon or a number of sides, not ${r.profile}`);
    d.rod.sides = p;
  }
  if (r.material !== undefined) d.rod.material = r.material;
  for (const k of ['diameter', 'radius', 'profile', 'material']) delete r[k];
  d.rod.extra = r;
  const j = mapping(joint);
  if (j.wall !== undefined) d.joint.wall = num(j.wall, 'joint.wall');
  if (j.socket !== undefined) d.joint.socket = num(j.socket, 'joint.socket');
  if (j.tolerance !== undefined) d.joint.tolerance = num(j.tolerance, 'joint.tolerance');
  if (j.material !== undefined) d.joint.material = j.material;
  for (const k of ['wall', 'socket', 'tolerance', 'material']) delete j[k];
  d.joint.extra = j;
  d.stock = stock === undefined ? null : mapping(stock);
  const factor = scale === undefined ? 1 : num(scale, 'scale');
  d.nodes = (Array.isArray(nodes) ? nodes : []).map((p: unknown, i: number) => vec(p, `node ${i + 1}`).map((x) => x * factor) as Vec3);
  const n = d.nodes.length;
  const nodeRef = (v: unknown, what: string) => {
    const k = num(v, what);
    if (!Number.isInteger(k) || k < 1 || k > n) throw new Error(`${what} names node ${v}, but the nodes are 1 to ${n}`);
    return k - 1;
  };
  d.edges = (Array.isArray(edges) ? edges : []).map((e: unknown, i: number) => {
    if (!Array.isArray(e) || e.length !== 2) throw new Error(`edge ${i + 1} must be [a, b] (node numbers), not ${JSON.stringify(e)}`);
    return [nodeRef(e[0], `edge ${i + 1}`), nodeRef(e[1], `edge ${i + 1}`)] as [number, number];
  });
  d.loads = (Array.isArray(loads) ? loads : []).map((l: any, i: number) => ({ node: nodeRef(l?.node, `load ${i + 1}`), force: vec(l?.force, `load ${i + 1} force`) }));
  d.supports = (Array.isArray(supports) ? supports : []).map((s: any, i: number) => ({ node: nodeRef(s?.node, `support ${i + 1}`), fixed: !!s?.fixed }));
  d.assemblyStart = assembly_start === undefined ? null : nodeRef(assembly_start, 'assembly_start');
  d.extra = extra;
  return d;
}

const r6 = (x: number) => { const v = Math.round(x * 1e6) / 1e6; return Object.is(v, -0) ? 0 : v; };
const flow = (v: unknown) => YAML.stringify(v, { collectionStyle: 'flow', lineWidth: 0 }).trim();

/** The design file: `fabkit: rods/1`, one node per line with its joint number. */
export function rodsToYaml(d: RodsDesign): string {
  const out: string[] = ['fabkit: rods/1', `name: ${flow(d.name)}`];
  if (d.description) out.push(`description: ${flow(d.description)}`);
  const rod: Record<string, unknown> = { diameter: r6(2 * d.rod.radius), profile: PROFILE_NAMES[d.rod.sides] ?? d.rod.sides, material: d.rod.material, ...d.rod.extra };
  out.push(`rod: ${flow(rod)}`);
  out.push(`joint: ${flow({ wall: r6(d.joint.wall), socket: r6(d.joint.socket), tolerance: r6(d.joint.tolerance), material: d.joint.material, ...d.joint.extra })}`);
  if (d.stock) out.push(`stock: ${flow(d.stock)}`);
  for (const [k, v] of Object.entries(d.extra)) out.push(YAML.stringify({ [k]: v }, { lineWidth: 0 }).trimEnd());
  if (d.assemblyStart !== null) out.push(`assembly_start: ${d.assemblyStart + 1}`);
  if (d.loads.length) {
    out.push('loads:');
    for (const l of d.loads) out.push(`  - {node: ${l.node + 1}, force: [${l.force.map(r6).join(', ')}]}`);
  }
  if (d.supports.length) {
    out.push('supports:');
    for (const s of d.supports) out.push(`  - {node: ${s.node + 1}, fixed: ${s.fixed}}`);
  }
  out.push(d.nodes.length ? 'nodes:' : 'nodes: []');
  d.nodes.forEach((p, i) => out.push(`  - [${p.map(r6).join(', ')}]   # ${i + 1}`));
  out.push(d.edges.length ? 'edges:' : 'edges: []');
  for (const [a, b] of d.edges) out.push(`  - [${a + 1}, ${b + 1}]`);
  return out.join('\n') + '\n';
}
