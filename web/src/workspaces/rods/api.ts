// The rods kit's routes (server/src/rods_api.cpp) and what they answer.
import type { KitClient, Diagnostic } from '../../shell/server';
import type { MeshData, Vec3 } from '../../shell/scene';

export interface Finding extends Diagnostic { class?: string; rods: number[]; joints: number[] }

export interface PreviewJoint {
  name: string; label: string; position: Vec3; rods: number[];
  max_offset: number; smallest_angle: number; mass: number; red: boolean; mesh: MeshData;
}
export interface PreviewRod {
  name: string; a: number; b: number; edge_length: number; length: number; offsets: [number, number];
  red: boolean; mesh: MeshData;
  utilisation?: number; axial?: number; moment?: number; stress?: number; governing?: string;
}
export interface AssemblyStep {
  kind: 'joint' | 'rod'; text: string;
  joint?: number; label?: string;            // joint steps
  rod?: number; from?: number; to?: number; length?: number; // rod steps
}
export interface Preview {
  name: string;
  parameters: { radius: number; sides: number; wall: number; socket: number; tolerance: number };
  joints: PreviewJoint[];
  rods: PreviewRod[];
  intersections: { rods: [number, number]; distance: number; clearance: number; point: Vec3 }[];
  balance: { checked: boolean; mass: number; center_of_mass: Vec3; ground_z: number; ground_nodes: number[]; support_polygon: [number, number][]; margin: number; stands: boolean };
  frame: { solved: boolean; max_utilisation: number; critical_rod: number; max_deflection: number; max_deflection_node: number; total_load: number };
  assembly: AssemblyStep[];
  passed: boolean;
  findings: Finding[];
  timings: Record<string, number>;
}

export interface BuildResult {
  termination: string; message: string; error?: string;
  diagnostics: Finding[];
  timings: Record<string, number>;
  joints?: { joint: number; label: string; closed: boolean; manifold: boolean; self_intersecting: boolean; volume: number; text_height: number }[];
  cut_plan?: {
    stock_count: number; proven_optimal: boolean; summary: string; stock_length: number; end_padding: number;
    stock: { pieces: { label: string; start: number; length: number }[]; remainder: number }[];
  };
  files: { name: string; bytes: number }[];
}
export interface BuildJob { job: number; state: 'running' | 'done' | 'failed'; done: number; total: number; seconds: number; status?: number; result?: BuildResult }

export const rodsApi = (c: KitClient) => ({
  preview: (yaml: string, signal?: AbortSignal) => c.post<Preview>('preview', yaml, undefined, signal),
  importObj: (obj: string) => c.post<{ nodes: Vec3[]; edges: [number, number][]; diagnostics: Diagnostic[] }>('import-obj', obj),
  startBuild: (yaml: string) => c.post<BuildJob>('build', yaml),
  job: (id: number) => c.get<BuildJob>(`build/${id}`),
  fileUrl: (id: number, name: string) => c.url(`build/${id}/files/${encodeURIComponent(name)}`),
});
export type RodsApi = ReturnType<typeof rodsApi>;
