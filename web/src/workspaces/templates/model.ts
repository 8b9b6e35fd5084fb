// The templates workspace's document: a working model file (`fabkit: templates/1`, `model:`,
// docs/templates.md) — which templates are composed, what is removed, which controls are set.
// The server composes it (snapping, connecting) every time it changes; a drag is recorded as an
// `adjust` entry at the value the library's QP reached.
import YAML from 'yaml';
import type { Vec3 } from '../../shell/scene';

export interface Step { use: string; as: string; at?: Vec3; set?: Record<string, number>; snap?: boolean; connect?: boolean }
export interface Adjust { node: string; control: string; to: number }
export interface LoadSpec { part: string; at: Vec3; force: Vec3 }
export interface TemplatesModel {
  name: string;
  description?: string;
  steps: Step[];
  remove: string[];
  adjust: Adjust[];
  loads: LoadSpec[];
  friction?: number;
}

export const CONTROLS = ['center_x', 'center_y', 'center_z', 'size_x', 'size_y', 'size_z'] as const;

export const emptyModel = (): TemplatesModel => ({ name: 'untitled', steps: [], remove: [], adjust: [], loads: [] });

const vec = (v: any, what: string): Vec3 => {
  if (!Array.isArray(v) || v.length !== 3 || v.some((x) => typeof x !== 'number' || !Number.isFinite(x))) throw new Error(`${what} must be three numbers (mm)`);
  return [v[0], v[1], v[2]];
};

/** Reads a model file; throws an Error saying what is wrong (the server checks the rest, with lines). */
export function parseModel(text: string): TemplatesModel {
  let y: any;
  try { y = YAML.parse(text) ?? {}; } catch (e) { throw new Error(`not YAML: ${(e as Error).message}`); }
  if (typeof y !== 'object' || y.fabkit !== 'templates/1') throw new Error("the file's first line must be 'fabkit: templates/1'");
  if (y.design && !y.model) {
    // A source design on its own opens as a model of that one template (as `fabkit check` does).
    return { ...emptyModel(), name: String(y.title ?? y.design), steps: [{ use: String(y.design), as: String(y.design) }] };
  }
  if (!Array.isArray(y.model)) throw new Error("a model needs a list 'model:' of templates to compose");
  const steps: Step[] = y.model.map((s: any, i: number) => {
    if (!s || typeof s.use !== 'string') throw new Error(`model step ${i + 1} needs 'use:' (a template: design or design/path)`);
    const st: Step = { use: s.use, as: typeof s.as === 'string' ? s.as : s.use.split('/').pop() };
    if (s.at !== undefined) st.at = vec(s.at, `${st.as}: at`);
    if (s.set && typeof s.set === 'object') st.set = Object.fromEntries(Object.entries(s.set).map(([k, v]) => [k, Number(v)]));
    if (s.snap === false) st.snap = false;
    if (s.connect === false) st.connect = false;
    return st;
  });
  return {
    name: typeof y.name === 'string' ? y.name : 'untitled',
    description: typeof y.description === 'string' ? y.description : undefined,
    steps,
    remove: Array.isArray(y.remove) ? y.remove.map(String) : [],
    adjust: Array.isArray(y.adjust) ? y.adjust.map((a: any) => ({ node: String(a.node), control: String(a.control), to: Number(a.to) })) : [],
    loads: Array.isArray(y.loads) ? y.loads.map((l: any) => ({ part: String(l.part), at: vec(l.at, 'a load: at'), force: vec(l.force, 'a load: force') })) : [],
    friction: typeof y.friction === 'number' ? y.friction : undefined,
  };
}

const r3 = (x: number) => Math.round(x * 1000) / 1000;

/** The model file (what Save YAML writes and the server composes). */
export function modelToYaml(m: TemplatesModel): string {
  const doc: any = { fabkit: 'templates/1', name: m.name };
  if (m.description) doc.description = m.description;
  doc.model = m.steps.map((s) => {
    const o: any = { use: s.use, as: s.as };
    if (s.at) o.at = s.at.map(r3);
    if (s.set && Object.keys(s.set).length) o.set = s.set;
    if (s.snap === false) o.snap = false;
    if (s.connect === false) o.connect = false;
    return o;
  });
  if (m.remove.length) doc.remove = m.remove;
  if (m.adjust.length) doc.adjust = m.adjust.map((a) => ({ node: a.node, control: a.control, to: r3(a.to) }));
  if (m.loads.length) doc.loads = m.loads;
  if (m.friction !== undefined) doc.friction = m.friction;
  const y = new YAML.Document(doc);
  YAML.visit(y, {
    Map(_, node) { if (node.items.every((p: any) => YAML.isScalar(p.value) || (YAML.isSeq(p.value) && p.value.items.every((i: any) => YAML.isScalar(i))))) node.flow = true; },
    Seq(_, node) { if (node.items.every((i: any) => YAML.isScalar(i))) node.flow = true; },
  });
  // the document itself stays in block style
  (y.contents as any).flow = false;
  return y.toString();
}

/** A composition name not yet used ("bottom_shelf", "bottom_shelf2"). */
export function freshName(m: TemplatesModel, base: string): string {
  const clean = base.replace(/[^A-Za-z0-9_]/g, '_').replace(/^[^A-Za-z_]/, 't') || 'part';
  const used = new Set(m.steps.map((s) => s.as));
  if (!used.has(clean)) return clean;
  for (let i = 2; ; ++i) if (!used.has(`${clean}${i}`)) return `${clean}${i}`;
}

/** The model with one more adjustment; a repeat of the last one (same node and control) replaces it. */
export function withAdjust(m: TemplatesModel, a: Adjust): TemplatesModel {
  const last = m.adjust[m.adjust.length - 1];
  const adjust = last && last.node === a.node && last.control === a.control ? [...m.adjust.slice(0, -1), a] : [...m.adjust, a];
  return { ...m, adjust };
}
