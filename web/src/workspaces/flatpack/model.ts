// The Flat-pack workspace's document: a flat-pack design as the editor holds it, close to its
// file (fabkit: flatpack/1, docs/flatpack.md). Values are numbers or expressions (text) over the
// design's parameters; the server solves them. Plain JSON data: undo/redo snapshots it.

/** A number, or an expression over parameters ("length", "(width - leg_width) / 2"). */
export type Num = number | string;
export type Vec3N = [Num, Num, Num];

export interface FpParam { name: string; value: number | null; type: 'length' | 'angle' | 'count' | 'number'; meta: boolean; description?: string }
export interface FpMaterial { name: string; thickness: number; kerf: number; interference: number }
export interface FpComponent {
  name: string; type: string;
  /** Inline values of its parameters (constraints `name.param = value`). */
  params: Record<string, Num>;
  /** A named material of the design; absent: the design's material. */
  material?: string;
  /** Keys the editor does not edit (points, edges, cutouts), kept as read. */
  extra?: Record<string, unknown>;
}
export interface FpConnection {
  /** "A.t": A's edge t is laid on b's edge (A moves). */
  a: string; b: string;
  alignment: 'front-front' | 'front-back';
  offset: Vec3N; rotation: Vec3N;
  /** 'none': places A only, no joint expected. */
  joint?: 'none';
  name?: string;
}
export interface FpDesign {
  name: string; description?: string;
  parameters: FpParam[];
  material: FpMaterial;
  materials: FpMaterial[];
  components: FpComponent[];
  constraints: string[];
  connections: FpConnection[];
  interfaces: Record<string, string>;
  /** Other top-level keys (joints, labels, sheet, uses), kept as read. */
  extra: Record<string, unknown>;
}

export const DEFAULT_MATERIAL: FpMaterial = { name: 'plywood-3mm', thickness: 3, kerf: 0.1, interference: 0.1 };

export function emptyDesign(): FpDesign {
  return { name: 'untitled', parameters: [], material: { ...DEFAULT_MATERIAL }, materials: [], components: [], constraints: [], connections: [], interfaces: {}, extra: {} };
}

export const clone = <T>(x: T): T => JSON.parse(JSON.stringify(x));

/** A name not yet used: "A", "B", … for the first 26, then "p27". */
export function freshComponentName(d: FpDesign): string {
  const used = new Set(d.components.map((c) => c.name));
  for (let i = 0; i < 26; ++i) { const n = String.fromCharCode(65 + i); if (!used.has(n)) return n; }
  for (let i = 27; ; ++i) if (!used.has(`p${i}`)) return `p${i}`;
}

export function freshName(used: string[], stem: string): string {
  for (let i = 1; ; ++i) if (!used.includes(`${stem}${i}`)) return `${stem}${i}`;
}

/** The name of a connection as the library calls it ("c1" unless named). */
export const connectionName = (c: FpConnection, i: number) => c.name ?? `c${i + 1}`;

/** Whether a value is a plain number (a slider can move it) or an expression. */
export const isNumber = (v: Num | undefined): v is number => typeof v === 'number' && Number.isFinite(v);

/** Reads a field's text: a number when it is one, else the expression as typed. */
export function parseNum(text: string): Num | null {
  const t = text.trim();
  if (!t) return null;
  const n = Number(t);
  return Number.isFinite(n) ? n : t;
}

/** Renames a component everywhere it is referred to (connections, constraints, interfaces). */
export function renameComponent(d: FpDesign, from: string, to: string): FpDesign {
  const n = clone(d);
  const re = new RegExp(`(^|[^A-Za-z0-9_.])${from.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}\\.`, 'g');
  const fix = (s: string) => s.replace(re, `$1${to}.`);
  for (const c of n.components) {
    if (c.name === from) c.name = to;
    for (const [k, v] of Object.entries(c.params)) if (typeof v === 'string') c.params[k] = fix(v);
  }
  for (const c of n.connections) { c.a = fix(c.a); c.b = fix(c.b); c.offset = c.offset.map((v) => (typeof v === 'string' ? fix(v) : v)) as Vec3N; }
  n.constraints = n.constraints.map(fix);
  for (const [k, v] of Object.entries(n.interfaces)) n.interfaces[k] = fix(v);
  return n;
}

/** Removes a component and the connections and interfaces that name it. */
export function removeComponent(d: FpDesign, name: string): FpDesign {
  const n = clone(d);
  const of = (ref: string) => ref.split('.')[0];
  n.components = n.components.filter((c) => c.name !== name);
  n.connections = n.connections.filter((c) => of(c.a) !== name && of(c.b) !== name);
  n.constraints = n.constraints.filter((c) => !new RegExp(`(^|[^A-Za-z0-9_.])${name}\\.`).test(c));
  for (const [k, v] of Object.entries(n.interfaces)) if (of(v) === name) delete n.interfaces[k];
  return n;
}

export const JOINT_COLORS: Record<string, number> = { 'finger-finger': 0x8e24aa, 'finger-hole': 0x00897b, 'slot-slot': 0xc77800 };

/** "A.t" → ["A", "t"]. */
export function splitRef(ref: string): [string, string] {
  const i = ref.lastIndexOf('.');
  return i < 0 ? [ref, ''] : [ref.slice(0, i), ref.slice(i + 1)];
}
