// The flatpack kit's routes (server/src/flatpack_api.cpp) as typed calls on the shell's KitClient.
import type { KitClient, Diagnostic } from '../../shell/server';
import type { MeshData } from '../../shell/scene';

export type P3 = [number, number, number];
export interface ParamSchema { name: string; kind: string; description: string; default: number | null; min: number | null; exclusive_min: boolean; max: number | null }
export interface ComponentTypeInfo { name: string; description: string; params: ParamSchema[]; constraints: string[]; edges: string[]; takes_points: boolean }
export interface MaterialInfo { name: string; thickness: number; kerf: number; interference: number }
export interface EdgeInfo { name: string; start: P3; end: P3 }
export interface ComponentInfo {
  name: string; type: string; piece: string; frame: number[]; outline: [number, number][];
  values: Record<string, number>; material: MaterialInfo; normal: P3; edges: EdgeInfo[];
}
export interface PieceInfo {
  name: string; components: string[]; material: MaterialInfo; size_mm: [number, number]; area_mm2: number;
  centre: P3; normal: P3; mesh: MeshData; sheet?: number;
}
export interface JointInfo {
  id: number; kind: 'finger-finger' | 'finger-hole' | 'slot-slot'; pieces: [string, string]; automatic: boolean;
  connection: number; start: P3; end: P3; length_mm: number; angle_deg: number; fingers: number; finger_width_mm: number;
}
/** A cycle-closing connection's residual; `frame` is where it would put `component` (column-major). */
export interface Residual { connection: number; name: string; component: string; piece: string; position_mm: number; angle_deg: number; closes: boolean; frame: number[] }
export interface FpDiagnostic extends Diagnostic { class?: string; pieces: string[] }
export interface SheetPiece { piece: string; rotation_deg: number; rings: [number, number][][] }
export interface SheetLabel { text: string; at: [number, number]; height: number; rotation: number }
export interface SheetInfo { utilisation: number; pieces: SheetPiece[]; labels: SheetLabel[] }
export interface Assembly {
  name: string; placed: boolean; values: Record<string, number>; meta: { name: string; drives: string[] | null }[];
  components: ComponentInfo[]; pieces: PieceInfo[]; joints: JointInfo[]; merging_connections: number[];
  residuals: Residual[]; assembly_order: { piece: string; direction: P3; group: number }[];
  sheets: { count: number; width: number; height: number; utilisation: number; list: SheetInfo[] };
  diagnostics: FpDiagnostic[]; timings_ms: Record<string, number>;
}

export function flatpackApi(c: KitClient) {
  return {
    components: (): Promise<ComponentTypeInfo[]> => c.get('components'),
    assemble: (yaml: string, signal?: AbortSignal): Promise<Assembly> => c.post('assemble', yaml, undefined, signal),
    /** One build output: sheet-N.svg, sheet-N.dxf, model.stl, scene.glb or report.json. */
    file: (yaml: string, file: string): Promise<Blob> => c.postBlob('build', yaml, { file }),
  };
}
export type FlatpackApi = ReturnType<typeof flatpackApi>;
