// The rods workspace's document: a rod network (nodes in mm, z up; edges between them) and the
// parameters of RodSteward Appendix A. Plain JSON data: the shell's history snapshots it, and
// every edit below returns a new document (never mutates).
import type { Vec3 } from '../../shell/scene';

export interface RodParams {
  /** r, mm: the rod's radius (a polygon's circumradius). */
  radius: number;
  /** p: sides of a polygonal profile; 0 for a round rod. */
  sides: number;
  /** A preset name or the file's mapping, passed through. */
  material: unknown;
  /** Other keys of the file's `rod:` mapping (circle_sides), passed through. */
  extra: Record<string, unknown>;
}
export interface JointParams {
  wall: number;       // σ, mm
  socket: number;     // h, mm
  tolerance: number;  // ε, mm
  material: unknown;
  extra: Record<string, unknown>;
}
export interface Load { node: number; force: Vec3 }
export interface Support { node: number; fixed: boolean }

export interface RodsDesign {
  name: string;
  description: string;
  rod: RodParams;
  joint: JointParams;
  stock: Record<string, unknown> | null;
  nodes: Vec3[];
  /** Pairs of node indices (0-based here; 1-based in the file). */
  edges: [number, number][];
  loads: Load[];
  supports: Support[];
  /** 0-based node index, or null: the library picks a lowest joint. */
  assemblyStart: number | null;
  /** Other top-level keys of the file (min_rod_length, engrave, tolerance_board, ...), kept. */
  extra: Record<string, unknown>;
}

export const emptyDesign = (): RodsDesign => ({
  name: 'untitled', description: '',
  rod: { radius: 3.175, sides: 0, material: 'hardwood', extra: {} },
  joint: { wall: 2, socket: 15, tolerance: 0.15, material: 'pla', extra: {} },
  stock: null, nodes: [], edges: [], loads: [], supports: [], assemblyStart: null, extra: {},
});

export const clone = (d: RodsDesign): RodsDesign => JSON.parse(JSON.stringify(d));

/** Keys of the scene's pickables: joints by node index, rods by edge index. */
export const jointKey = (i: number) => `j${i}`;
export const rodKey = (e: number) => `r${e}`;
export function parseKey(key: string | null): { kind: 'joint' | 'rod'; index: number } | null {
  const m = key?.match(/^([jr])(\d+)$/);
  return m ? { kind: m[1] === 'j' ? 'joint' : 'rod', index: Number(m[2]) } : null;
}
/** The library's names: "joint 07", "rod 03-07" (two digits, three beyond 99 joints). */
export function jointLabel(d: RodsDesign, i: number): string {
  return String(i + 1).padStart(d.nodes.length > 99 ? 3 : 2, '0');
}
export const jointName = (d: RodsDesign, i: number) => `joint ${jointLabel(d, i)}`;
export const rodName = (d: RodsDesign, e: number) => `rod ${jointLabel(d, d.edges[e][0])}-${jointLabel(d, d.edges[e][1])}`;

export const hasEdge = (d: RodsDesign, a: number, b: number) => d.edges.some(([x, y]) => (x === a && y === b) || (x === b && y === a));

export function addNode(d: RodsDesign, p: Vec3, connectTo: number[] = []): RodsDesign {
  const n = clone(d);
  n.nodes.push([...p] as Vec3);
  const i = n.nodes.length - 1;
  for (const j of connectTo) if (j >= 0 && j < i) n.edges.push([j, i]);
  return n;
}

/** Rods from `from` to each of `to` that does not have one yet. */
export function connect(d: RodsDesign, from: number, to: number[]): RodsDesign {
  const n = clone(d);
  for (const j of to) if (j !== from && !hasEdge(n, from, j)) n.edges.push([from, j]);
  return n;
}

/** Splits rod `e` by a new joint at its midpoint (appended as the last node). */
export function splitRod(d: RodsDesign, e: number): RodsDesign {
  const n = clone(d);
  const [a, b] = n.edges[e];
  const pa = n.nodes[a], pb = n.nodes[b];
  n.nodes.push([(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2]);
  const m = n.nodes.length - 1;
  n.edges[e] = [a, m];
  n.edges.splice(e + 1, 0, [m, b]);
  return n;
}

/** Deletes nodes (with their rods) and rods; renumbers loads, supports and the assembly start. */
export function deleteParts(d: RodsDesign, nodes: Iterable<number>, rods: Iterable<number>): RodsDesign {
  const goneNodes = new Set(nodes), goneRods = new Set(rods);
  const n = clone(d);
  const map = new Map<number, number>();
  n.nodes = d.nodes.filter((_p, i) => { if (goneNodes.has(i)) return false; map.set(i, map.size); return true; });
  n.edges = d.edges.filter(([a, b], e) => !goneRods.has(e) && !goneNodes.has(a) && !goneNodes.has(b))
    .map(([a, b]) => [map.get(a)!, map.get(b)!] as [number, number]);
  n.loads = d.loads.filter((l) => map.has(l.node)).map((l) => ({ ...l, node: map.get(l.node)! }));
  n.supports = d.supports.filter((s) => map.has(s.node)).map((s) => ({ ...s, node: map.get(s.node)! }));
  n.assemblyStart = d.assemblyStart !== null && map.has(d.assemblyStart) ? map.get(d.assemblyStart)! : null;
  return n;
}

export function moveNodes(d: RodsDesign, positions: Map<number, Vec3>): RodsDesign {
  const n = clone(d);
  for (const [i, p] of positions) n.nodes[i] = [...p] as Vec3;
  return n;
}

/** Nodes that no rod touches: the library refuses them, so the editor holds them back. */
export function isolatedNodes(d: RodsDesign): Set<number> {
  const used = new Set<number>();
  for (const [a, b] of d.edges) { used.add(a); used.add(b); }
  const out = new Set<number>();
  d.nodes.forEach((_p, i) => { if (!used.has(i)) out.add(i); });
  return out;
}

/** Rounds to the grid (mm); 0 leaves the value. */
export const snap = (v: number, grid: number) => (grid > 0 ? Math.round(v / grid) * grid : Math.round(v * 1e4) / 1e4);

/**
 * Axis snapping: when the direction from `from` to `p` is within `degrees` of a world axis, moves
 * `p` onto that axis line through `from` (keeping its distance along it).
 */
export function snapToAxis(p: Vec3, from: Vec3, degrees: number): Vec3 {
  const d = [p[0] - from[0], p[1] - from[1], p[2] - from[2]];
  const len = Math.hypot(d[0], d[1], d[2]);
  if (len < 1e-9) return p;
  for (let k = 0; k < 3; ++k) {
    if (Math.abs(d[k]) / len >= Math.cos((degrees * Math.PI) / 180)) {
      const out: Vec3 = [...from] as Vec3;
      out[k] = from[k] + d[k];
      return out;
    }
  }
  return p;
}
