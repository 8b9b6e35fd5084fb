// The hacks design being edited (the document of the hacks workspace) and the inventory.
import type { Frame } from '../../shell/scene';

export interface EnvItem { name: string; part?: string; primitives?: Record<string, unknown>; frame: Frame }
export interface PartItem { name: string; part: string; params?: Record<string, number> }
export interface TargetItem { name: string; part: string; primitive?: string; frame: Frame }
export interface Connection { a: string; b: string; alignment?: 'flip'; fixed?: boolean }
export interface Design {
  name: string; description?: string;
  environment: EnvItem[]; parts: PartItem[]; target: TargetItem | null; connections: Connection[];
}

export const emptyDesign = (): Design => ({ name: 'untitled', environment: [], parts: [], target: null, connections: [] });
export const cloneDesign = (d: Design): Design => JSON.parse(JSON.stringify(d));

/** Every named instance in the design with its library part (type). */
export function instances(d: Design): { name: string; part: string; role: 'environment' | 'part' | 'target'; params?: Record<string, number> }[] {
  const out: { name: string; part: string; role: 'environment' | 'part' | 'target'; params?: Record<string, number> }[] = [];
  for (const e of d.environment) if (e.part) out.push({ name: e.name, part: e.part, role: 'environment' });
  for (const p of d.parts) out.push({ name: p.name, part: p.part, role: 'part', params: p.params });
  if (d.target && !d.parts.some((p) => p.name === d.target!.name)) out.push({ name: d.target.name, part: d.target.part, role: 'target' });
  return out;
}

export function countOf(d: Design, part: string): number {
  return instances(d).filter((i) => i.part === part).length;
}

export function freshName(d: Design, base: string): string {
  const taken = new Set(instances(d).map((i) => i.name).concat(d.environment.map((e) => e.name)));
  for (let n = 1; ; ++n) if (!taken.has(`${base}${n}`)) return `${base}${n}`;
}

/** Removes an instance and every connection that mentions it. */
export function removeInstance(d: Design, name: string): Design {
  const n = cloneDesign(d);
  n.environment = n.environment.filter((e) => e.name !== name);
  n.parts = n.parts.filter((p) => p.name !== name);
  if (n.target?.name === name) n.target = null;
  n.connections = n.connections.filter((c) => c.a.split('.')[0] !== name && c.b.split('.')[0] !== name);
  return n;
}

/** How many of each library part the user owns; absent = unlimited. */
export class Inventory {
  owned = new Map<string, number>();
  limit(part: string): number | undefined { return this.owned.get(part); }
  set(part: string, n: number | undefined): void { if (n === undefined || Number.isNaN(n)) this.owned.delete(part); else this.owned.set(part, n); }
}

/** A parametric part's default parameter values (its schema's defaults). */
export function defaultParams(info: { params: { name: string; default: number }[] }): Record<string, number> {
  return Object.fromEntries(info.params.map((p) => [p.name, p.default]));
}

/** Renames an instance in every connection that mentions it. */
export function renameRefs(d: Design, old: string, name: string): void {
  for (const c of d.connections) {
    if (c.a.split('.')[0] === old) c.a = name + c.a.slice(old.length);
    if (c.b.split('.')[0] === old) c.b = name + c.b.slice(old.length);
  }
}
