// The templates kit's routes (server/src/templates_api.cpp) as typed calls on the shell's KitClient.
import type { KitClient } from '../../shell/server';
import type { MeshData } from '../../shell/scene';
import type { Diagnostic } from '../../shell/server';

export type { Diagnostic };
export { ApiError } from '../../shell/server';

export interface BoxData { min: [number, number, number]; max: [number, number, number] }
export interface LibraryNode { path: string; name: string; depth: number; elements: number; leaf: boolean; box: BoxData }
export interface LibraryDesign { name: string; title: string; category: string; description: string; parts: number; box: BoxData; nodes: LibraryNode[] }
export interface Library { designs: LibraryDesign[]; categories: string[] }
export interface PartData {
  name: string; element: string; node: string; item: string; role: 'principal' | 'connecting';
  stable: boolean; color: [number, number, number]; box: BoxData; mesh: MeshData;
}
export interface NodeData { path: string; name: string; parent: string | null; children: string[]; element: string | null; principal: boolean; connection: boolean; box: BoxData }
export interface BodyData { elements: string[]; verdict: string; stable: boolean; anchored: boolean; mass_kg: number }
export interface Stability { stable: boolean; bodies: BodyData[]; milliseconds: number; diagnostics: Diagnostic[] }
export interface BomLine { item: string; name: string; category: string; parts: number; units: number; unit: string; unit_price: number; total: number; buy: string; sizes: string; supplier: string; part_number: string }
export interface Bom { lines: BomLine[]; total: number | null; parts?: number; diagnostics: Diagnostic[] }
export interface Candidate { source: string; transferred: boolean; feasible: boolean; accepted: boolean; error_mm: number | null; descriptor_distance: number | null }
export interface LinkData { added: string; existing: string; connected: boolean; message: string; tried: Candidate[] }
export interface StepData { text: string; line: number; ok: boolean; outcome: string; snap?: { snapped: boolean; planes: number; combinations: number }; links?: LinkData[]; all_connected?: boolean }
export interface ConnectionData { name: string; principal: string[]; connecting: string[]; source: string }
export interface ModelState { parts: PartData[]; nodes: NodeData[]; stability: Stability | null; max_violation: number; bom?: Bom }
export interface Composed extends ModelState {
  stability: Stability;
  name: string; steps: StepData[]; compositions: { name: string; source: string; node: string }[];
  connections: ConnectionData[]; bom: Bom; verdict: string; diagnostics: Diagnostic[];
  compose_milliseconds: number; milliseconds: number;
}
export interface ControlData { control: string; value: number; hidden: boolean; axis: number; size: boolean }
export interface Controls { node: string; box: BoxData; controls: ControlData[] }
export interface DragAnswer extends ModelState {
  node: string; control: string; start: number; requested: number; achieved: number; reached: boolean;
  message: string; used_solver: boolean; qp_milliseconds: number; milliseconds: number;
}
export interface BuildFile { name: string; type: string; bytes: number; text?: string; base64?: string }
export interface BuildAnswer { message: string; termination: string; files: BuildFile[]; diagnostics: Diagnostic[] }

export function templatesApi(c: KitClient) {
  return {
    library: (): Promise<Library> => c.get('library'),
    mesh: (design: string, node = ''): Promise<{ template: string; box: BoxData; parts: PartData[] }> =>
      c.get(`library/${encodeURIComponent(design)}/mesh`, node ? { node } : undefined),
    compose: (yaml: string, signal?: AbortSignal): Promise<Composed> => c.post('compose', yaml, undefined, signal),
    controls: (model: string, node: string): Promise<Controls> => c.post('controls', { model, node }),
    /** One drag step; `stability: false` skips the contact-force check (slow under loads). */
    drag: (model: string, node: string, control: string, delta: number, opts: { bom?: boolean; stability?: boolean } = {}): Promise<DragAnswer> =>
      c.post('drag', { model, node, control, delta, bom: !!opts.bom, stability: opts.stability ?? true }),
    build: (yaml: string): Promise<BuildAnswer> => c.post('build', yaml),
  };
}
export type TemplatesApi = ReturnType<typeof templatesApi>;
