// The hacks kit's routes (server/src/hacks_api.cpp) as typed calls on the shell's KitClient.
import type { KitClient } from '../../shell/server';
import type { Frame, MeshData, Vec3 } from '../../shell/scene';
import type { Diagnostic } from '../../shell/server';

export type { Frame, MeshData, Vec3, Diagnostic };
export { ApiError } from '../../shell/server';

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
export interface PartMesh { name: string; body: MeshData; primitives: Record<string, MeshData> }
export interface CheckStep {
  text: string; line: number; accepted: boolean; skipped: boolean; closes_cycle: boolean;
  cycles: string[]; milliseconds: number; diagnostics: Diagnostic[]; best_part_frames?: Frame[];
}
export interface PlacedPart { name: string; type: string; role?: string; frame: Frame }
export interface CheckResult { valid: boolean; steps: CheckStep[]; parts: PlacedPart[]; diagnostics: Diagnostic[] }
/** How far the target ended up from where it was asked to be (docs/result-format.md). */
export interface PoseError { pos_error_mm: number; rot_error_deg: number; tilt_deg: number; twist_deg: number; twist_free: boolean }
export interface SolveResult {
  stable: boolean; feasible: boolean; termination: string; message: string;
  /** The solve's verdict, decided by the solver for every front end (docs/result-format.md):
   *  STABLE | PARTS_PASS_THROUGH | INFEASIBLE | STOPPED | FALLS_APART | NOT_AT_REST. */
  verdict: string;
  target: PoseError & { step1?: PoseError; primitive?: string; goal?: Frame };
  parts: PlacedPart[]; slipping: string[];
  /** The verdict's checks (docs/result-format.md). */
  checks?: { max_penetration_mm: number; equilibrium_residual: number };
  /** For a design that falls apart: a change to it that holds, found by solving it (docs/result-format.md). */
  remedy?: string;
  /** Every part's frame after step 1 (before relaxing under gravity); added by the server for the editor. */
  step1_parts?: { name: string; frame: Frame }[];
}
export interface PrimRef { part: string; primitive: string; params?: Record<string, number> }
export interface Compat { ok: boolean; reason: string }

export function hacksApi(c: KitClient) {
  return {
    parts: (): Promise<PartInfo[]> => c.get('parts'),
    mesh: (part: string, params?: Record<string, number>): Promise<PartMesh> => c.get(`parts/${encodeURIComponent(part)}/mesh`, params),
    /** Geometry of a loose primitive in its own coordinates (GET primitives/{type}/mesh). */
    primMesh: async (type: string, sizes: Record<string, number>): Promise<MeshData> =>
      (await c.get<{ type: string; mesh: MeshData }>(`primitives/${encodeURIComponent(type)}/mesh`, sizes)).mesh,
    check: (yaml: string): Promise<CheckResult> => c.post('check', yaml),
    solve: (yaml: string, signal?: AbortSignal): Promise<SolveResult> => c.post('solve', yaml, undefined, signal),
    solveGlb: (yaml: string): Promise<Blob> => c.postBlob('solve', yaml, { format: 'glb' }),
    compatible: (a: PrimRef, b: PrimRef[]): Promise<Compat[]> => c.post('compatible', { a, b }),
  };
}
export type HacksApi = ReturnType<typeof hacksApi>;
