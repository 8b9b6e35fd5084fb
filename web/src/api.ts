// Thin client for the fabkit serve JSON API (see server/src/editor_server.cpp).
export type Vec3 = [number, number, number];
export interface Frame { pos: Vec3; rot: Vec3 }
export interface PrimInfo {
  name: string; type: string; connector: string; description: string;
  shape: Record<string, number>; frame: Frame; closed: boolean; single_connection: boolean;
  connects_to: string[];
}
export interface ParamInfo { name: string; default: number; min: number; max: number; unit: string; doc: string }
export interface PartInfo {
  name: string; aliases: string[]; description: string; category: string; mass: number;
  params: ParamInfo[]; primitives: PrimInfo[];
}
export interface MeshData { vertices: number[]; faces: number[] }
export interface PartMesh { name: string; body: MeshData; primitives: Record<string, MeshData> }
export interface Diagnostic { severity: string; code?: string; message: string; line?: number; column?: number; text: string }
export interface CheckStep {
  text: string; line: number; accepted: boolean; skipped: boolean; closes_cycle: boolean;
  cycles: string[]; milliseconds: number; diagnostics: Diagnostic[]; best_part_frames?: Frame[];
}
export interface PlacedPart { name: string; type: string; role?: string; frame: Frame }
export interface CheckResult { valid: boolean; steps: CheckStep[]; parts: PlacedPart[]; diagnostics: Diagnostic[] }
export interface SolveResult {
  stable: boolean; feasible: boolean; termination: string; message: string;
  target: { pos_error_mm: number; rot_error_deg: number; primitive: string; goal: Frame };
  parts: PlacedPart[]; slipping: string[];
}
export interface PrimRef { part: string; primitive: string; params?: Record<string, number> }
export interface Compat { ok: boolean; reason: string }

export class ApiError extends Error {
  constructor(public status: number, message: string, public diagnostics: Diagnostic[] = []) { super(message); }
}

async function json<T>(res: Response): Promise<T> {
  const text = await res.text();
  let body: any = null;
  try { body = JSON.parse(text); } catch { /* not JSON */ }
  if (!res.ok) {
    const diags: Diagnostic[] = body?.diagnostics ?? [];
    const msg = body?.error ?? (diags.map((d) => d.message).join('; ') || text || res.statusText);
    throw new ApiError(res.status, msg, diags);
  }
  return body as T;
}

const base = 'api';
// The server reads design bodies only with a YAML (or JSON) type: a plain-text POST is what any
// web page may send to 127.0.0.1 without asking (docs/security.md).
const yamlBody = (yaml: string): RequestInit => ({ method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: yaml });
export const api = {
  parts: async (): Promise<PartInfo[]> => json(await fetch(`${base}/parts`)),
  mesh: async (part: string, params?: Record<string, number>): Promise<PartMesh> => {
    const q = params && Object.keys(params).length ? '?' + new URLSearchParams(Object.entries(params).map(([k, v]) => [k, String(v)])) : '';
    return json(await fetch(`${base}/parts/${encodeURIComponent(part)}/mesh${q}`));
  },
  /** Geometry of a loose primitive in its own coordinates (GET /api/primitives/{type}/mesh). */
  primMesh: async (type: string, sizes: Record<string, number>): Promise<MeshData> => {
    const q = new URLSearchParams(Object.entries(sizes).map(([k, v]) => [k, String(v)]));
    const r: { type: string; mesh: MeshData } = await json(await fetch(`${base}/primitives/${encodeURIComponent(type)}/mesh?${q}`));
    return r.mesh;
  },
  design: async (): Promise<string | null> => {
    const res = await fetch(`${base}/design`);
    return res.ok ? res.text() : null;
  },
  check: async (yaml: string): Promise<CheckResult> => json(await fetch(`${base}/check`, yamlBody(yaml))),
  solve: async (yaml: string): Promise<SolveResult> => json(await fetch(`${base}/solve`, yamlBody(yaml))),
  solveGlb: async (yaml: string): Promise<Blob> => {
    const res = await fetch(`${base}/solve?format=glb`, yamlBody(yaml));
    if (!res.ok) await json(res);
    return res.blob();
  },
  compatible: async (a: PrimRef, b: PrimRef[]): Promise<Compat[]> =>
    json(await fetch(`${base}/compatible`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ a, b }) })),
};
