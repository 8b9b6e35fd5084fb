// The 3D view: z-up three.js scene, parts placed at frames, primitives as separately pickable meshes.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import type { Frame, MeshData, PartMesh } from './api';

export const PRIM_COLORS: Record<string, number> = {
  rod: 0x2f7dd1, hook: 0xe07b00, ring: 0x8e44ad, clip: 0x16a085, tube: 0x2c3e50,
  edge: 0x7f8c8d, surface: 0x95a5a6, hemisphere: 0xc0392b,
};

export function frameMatrix(f: Frame): THREE.Matrix4 {
  const d = Math.PI / 180;
  const q = new THREE.Quaternion().setFromEuler(new THREE.Euler(f.rot[0] * d, f.rot[1] * d, f.rot[2] * d, 'ZYX'));
  return new THREE.Matrix4().compose(new THREE.Vector3(...f.pos), q, new THREE.Vector3(1, 1, 1));
}

export function geometryOf(m: MeshData): THREE.BufferGeometry {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(m.vertices, 3));
  g.setIndex(m.faces);
  g.computeVertexNormals();
  g.computeBoundingSphere();
  return g;
}

export interface ScenePart { name: string; type: string; frame: Frame; mesh: PartMesh; primTypes: Record<string, string>; ghost?: boolean }
export type PrimKey = string; // "instance.primitive"

export class SceneView {
  renderer: THREE.WebGLRenderer;
  scene = new THREE.Scene();
  camera: THREE.PerspectiveCamera;
  controls: OrbitControls;
  private root = new THREE.Group();
  primMeshes = new Map<PrimKey, THREE.Mesh>();
  bodyMeshes = new Map<string, THREE.Mesh>();
  private raycaster = new THREE.Raycaster();
  private state = new Map<PrimKey, { dim?: boolean; selected?: boolean; bad?: boolean; picked?: boolean }>();
  selectedPart: string | null = null;
  onPick: (key: PrimKey | null, part: string | null) => void = () => {};
  onHover: (key: PrimKey | null, x: number, y: number) => void = () => {};

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setClearColor(0xf4f6f8);
    host.appendChild(this.renderer.domElement);
    this.renderer.domElement.dataset.testid = 'scene-canvas';
    this.camera = new THREE.PerspectiveCamera(40, 1, 1, 20000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(800, -800, 600);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.render());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4); sun.position.set(1, -2, 3); this.scene.add(sun);
    const grid = new THREE.GridHelper(2000, 20, 0xbbbbbb, 0xdddddd); grid.rotation.x = Math.PI / 2; this.scene.add(grid);
    this.scene.add(new THREE.AxesHelper(100));
    this.scene.add(this.root);
    new ResizeObserver(() => this.resize()).observe(host);
    this.resize();
    const el = this.renderer.domElement;
    let down: [number, number] | null = null;
    el.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
    el.addEventListener('pointerup', (e) => {
      if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) {
        const hit = this.pickAt(e.clientX, e.clientY);
        this.onPick(hit.prim, hit.part);
      }
      down = null;
    });
    el.addEventListener('pointerleave', (e) => { this.onHover(null, e.clientX, e.clientY); });
    el.addEventListener('pointermove', (e) => { this.onHover(this.pickAt(e.clientX, e.clientY).prim, e.clientX, e.clientY); });
  }

  resize(): void {
    const w = Math.max(1, this.host.clientWidth), h = Math.max(1, this.host.clientHeight);
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h; this.camera.updateProjectionMatrix();
    this.render();
  }

  render(): void { this.renderer.render(this.scene, this.camera); }

  setParts(parts: ScenePart[]): void {
    for (const c of [...this.root.children]) { this.root.remove(c); c.traverse((o) => { if ((o as THREE.Mesh).geometry) (o as THREE.Mesh).geometry.dispose(); }); }
    this.primMeshes.clear(); this.bodyMeshes.clear();
    for (const p of parts) {
      const g = new THREE.Group();
      g.matrixAutoUpdate = false;
      g.matrix.copy(frameMatrix(p.frame));
      g.userData.part = p.name;
      if (p.mesh.body.faces.length) { // loose-primitive environments have no body
        const body = new THREE.Mesh(geometryOf(p.mesh.body), new THREE.MeshStandardMaterial({ color: 0xc8c8c8, transparent: !!p.ghost, opacity: p.ghost ? 0.35 : 1, roughness: 0.8, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2 }));
        body.userData = { part: p.name };
        g.add(body); this.bodyMeshes.set(p.name, body);
      }
      for (const [prim, m] of Object.entries(p.mesh.primitives)) {
        const color = PRIM_COLORS[p.primTypes[prim]] ?? 0x999999;
        const mesh = new THREE.Mesh(geometryOf(m), new THREE.MeshStandardMaterial({ color, transparent: true, opacity: p.ghost ? 0.5 : 1, roughness: 0.5 }));
        mesh.userData = { part: p.name, prim: `${p.name}.${prim}`, color };
        g.add(mesh); this.primMeshes.set(`${p.name}.${prim}`, mesh);
      }
      this.root.add(g);
    }
    this.root.updateMatrixWorld(true);
    this.restyle();
  }

  setPrimState(key: PrimKey, s: { dim?: boolean; selected?: boolean; bad?: boolean; picked?: boolean }): void { this.state.set(key, s); }
  clearPrimState(): void { this.state.clear(); }

  restyle(): void {
    for (const [key, mesh] of this.primMeshes) {
      const s = this.state.get(key) ?? {};
      const mat = mesh.material as THREE.MeshStandardMaterial;
      mat.color.setHex(s.bad ? 0xff0000 : mesh.userData.color);
      mat.emissive.setHex(s.bad ? 0x660000 : s.selected || s.picked ? 0xffcc00 : mesh.userData.part === this.selectedPart ? 0x665500 : 0x000000);
      mat.opacity = s.dim ? 0.15 : 1;
    }
    for (const [name, mesh] of this.bodyMeshes) {
      const mat = mesh.material as THREE.MeshStandardMaterial;
      mat.emissive.setHex(name === this.selectedPart ? 0x665500 : 0x000000);
    }
    this.render();
  }

  pickAt(clientX: number, clientY: number): { prim: PrimKey | null; part: string | null } {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const prims = this.raycaster.intersectObjects([...this.primMeshes.values()], false);
    if (prims.length) return { prim: prims[0].object.userData.prim, part: prims[0].object.userData.part };
    const bodies = this.raycaster.intersectObjects([...this.bodyMeshes.values()], false);
    if (bodies.length) return { prim: null, part: bodies[0].object.userData.part };
    return { prim: null, part: null };
  }

  /** Client coordinates of a point on the primitive's surface that a click there would pick. */
  screenPointOf(key: PrimKey): { x: number; y: number } | null {
    const mesh = this.primMeshes.get(key); if (!mesh) return null;
    const pos = mesh.geometry.getAttribute('position');
    const r = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3();
    for (let i = 0; i < pos.count; i += Math.max(1, Math.floor(pos.count / 200))) {
      v.fromBufferAttribute(pos, i).applyMatrix4(mesh.matrixWorld).project(this.camera);
      const x = r.left + (v.x + 1) / 2 * r.width, y = r.top + (1 - v.y) / 2 * r.height;
      if (x < r.left + 2 || x > r.right - 2 || y < r.top + 2 || y > r.bottom - 2) continue;
      // nudge towards the inside: check the ray hits this primitive
      if (this.pickAt(x, y).prim === key) return { x, y };
    }
    return null;
  }

  frameAll(): void {
    const box = new THREE.Box3().setFromObject(this.root);
    if (box.isEmpty()) { this.render(); return; }
    const c = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    const dist = size / (2 * Math.tan((this.camera.fov * Math.PI) / 360)) * 1.1 + 10;
    this.controls.target.copy(c);
    this.camera.position.copy(c.clone().add(dir.multiplyScalar(dist)));
    this.camera.updateProjectionMatrix(); this.controls.update(); this.render();
  }

  view(name: 'top' | 'front' | 'side' | 'iso'): void {
    const dirs = { top: [0, -0.0001, 1], front: [0, -1, 0], side: [1, 0, 0], iso: [1, -1, 0.8] } as const;
    const t = this.controls.target;
    const dist = Math.max(100, this.camera.position.distanceTo(t));
    this.camera.position.copy(t.clone().add(new THREE.Vector3(...dirs[name]).normalize().multiplyScalar(dist)));
    this.controls.update();
    this.frameAll();
  }
}
