// The 3D view shared by every workspace: a z-up three.js scene (mm), one renderer, camera and
// controls, named layers that a workspace fills, picking and highlighting of pickable meshes.
// A workspace puts its objects into `layer(name)` and marks meshes pickable with `pickable()`;
// the view reports clicks and hovers by key and styles meshes from the states it is given.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

export type Vec3 = [number, number, number];
/** Position (mm) and rotation (degrees, R = Rz·Ry·Rx) — the frame of every kit's files. */
export interface Frame { pos: Vec3; rot: Vec3 }
export interface MeshData { vertices: number[]; faces: number[] }

export function frameMatrix(f: Frame): THREE.Matrix4 {
  const d = Math.PI / 180;
  const q = new THREE.Quaternion().setFromEuler(new THREE.Euler(f.rot[0] * d, f.rot[1] * d, f.rot[2] * d, 'ZYX'));
  return new THREE.Matrix4().compose(new THREE.Vector3(...f.pos), q, new THREE.Vector3(1, 1, 1));
}

/** The frame (mm, degrees ZYX) of a rigid matrix. */
export function matrixFrame(m: THREE.Matrix4): Frame {
  const e = new THREE.Euler().setFromRotationMatrix(m, 'ZYX');
  const p = new THREE.Vector3().setFromMatrixPosition(m);
  const d = 180 / Math.PI;
  return { pos: [p.x, p.y, p.z], rot: [e.x * d, e.y * d, e.z * d] };
}

export function geometryOf(m: MeshData): THREE.BufferGeometry {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(m.vertices, 3));
  g.setIndex(m.faces);
  g.computeVertexNormals();
  g.computeBoundingSphere();
  return g;
}

/** How a pickable mesh is drawn; set by the workspace, applied by restyle(). */
export interface PickState { dim?: boolean; selected?: boolean; bad?: boolean; picked?: boolean }
export type ViewName = 'top' | 'front' | 'side' | 'iso';

export class SceneView {
  renderer: THREE.WebGLRenderer;
  scene = new THREE.Scene();
  camera: THREE.PerspectiveCamera;
  controls: OrbitControls;
  /** Everything workspaces draw lives under root (framing uses it). */
  readonly root = new THREE.Group();
  private layers = new Map<string, THREE.Group>();
  /** Pickable pieces by key ("eyehook1.hook") and pickable object bodies by object key ("eyehook1"). */
  pieces = new Map<string, THREE.Mesh>();
  bodies = new Map<string, THREE.Mesh>();
  private raycaster = new THREE.Raycaster();
  private state = new Map<string, PickState>();
  selectedObject: string | null = null;
  onPick: (piece: string | null, object: string | null) => void = () => {};
  onHover: (piece: string | null, x: number, y: number) => void = () => {};
  /** Called after every render (overlays that follow the camera). */
  onRender: (() => void)[] = [];
  /** HTML labels pinned to world points, by layer; repositioned after every render. */
  private labels: { layer: string; at: THREE.Vector3; el: HTMLElement }[] = [];
  private labelHost: HTMLElement;

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setClearColor(0xf4f6f8);
    host.appendChild(this.renderer.domElement);
    this.labelHost = document.createElement('div');
    this.labelHost.className = 'scene-labels';
    host.appendChild(this.labelHost);
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
        this.onPick(hit.piece, hit.object);
      }
      down = null;
    });
    el.addEventListener('pointerleave', (e) => { this.onHover(null, e.clientX, e.clientY); });
    el.addEventListener('pointermove', (e) => { this.onHover(this.pickAt(e.clientX, e.clientY).piece, e.clientX, e.clientY); });
  }

  resize(): void {
    const w = Math.max(1, this.host.clientWidth), h = Math.max(1, this.host.clientHeight);
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h; this.camera.updateProjectionMatrix();
    this.render();
  }

  render(): void {
    this.renderer.render(this.scene, this.camera);
    this.placeLabels();
    for (const f of this.onRender) f();
  }

  /**
   * An HTML label pinned to a world point (mm) of a layer; removed with the layer. It follows
   * the camera and hides when the point is behind it or outside the view.
   */
  addLabel(layer: string, at: THREE.Vector3, content: string | HTMLElement, attrs: Record<string, string> = {}): HTMLElement {
    const el = document.createElement('div');
    el.className = 'scene-label';
    for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, k === 'class' ? `scene-label ${v}` : v);
    if (typeof content === 'string') el.textContent = content; else el.append(content);
    this.labelHost.append(el);
    this.labels.push({ layer, at: at.clone(), el });
    this.placeLabels();
    return el;
  }

  private placeLabels(): void {
    if (!this.labels.length) return;
    const w = this.host.clientWidth, h = this.host.clientHeight;
    const v = new THREE.Vector3();
    for (const l of this.labels) {
      v.copy(l.at).project(this.camera);
      const inside = v.z < 1 && Math.abs(v.x) <= 1 && Math.abs(v.y) <= 1;
      l.el.style.display = inside ? '' : 'none';
      l.el.style.left = `${((v.x + 1) / 2) * w}px`;
      l.el.style.top = `${((1 - v.y) / 2) * h}px`;
    }
  }

  /** A named group under the root; created on first use. Workspaces own their layers. */
  layer(name: string): THREE.Group {
    let g = this.layers.get(name);
    if (!g) { g = new THREE.Group(); g.name = name; this.layers.set(name, g); this.root.add(g); }
    return g;
  }

  /** Empties a layer (disposing geometry) and forgets its pickables. */
  clearLayer(name: string): void {
    const g = this.layers.get(name); if (!g) return;
    for (const c of [...g.children]) {
      g.remove(c);
      c.traverse((o) => { if ((o as THREE.Mesh).geometry) (o as THREE.Mesh).geometry.dispose(); });
    }
    this.labels = this.labels.filter((l) => { if (l.layer !== name) return true; l.el.remove(); return false; });
    for (const [k, m] of [...this.pieces]) if (!this.inScene(m)) this.pieces.delete(k);
    for (const [k, m] of [...this.bodies]) if (!this.inScene(m)) this.bodies.delete(k);
  }

  /** Removes every layer (switching workspaces). */
  clearAll(): void {
    for (const name of [...this.layers.keys()]) { this.clearLayer(name); this.root.remove(this.layers.get(name)!); }
    this.layers.clear(); this.state.clear(); this.selectedObject = null;
    this.render();
  }

  private inScene(o: THREE.Object3D): boolean {
    for (let p: THREE.Object3D | null = o; p; p = p.parent) if (p === this.root) return true;
    return false;
  }

  /**
   * Makes a mesh pickable: `piece` is the key clicks report ("eyehook1.hook"; null for a body,
   * which picks its object), `object` the object it belongs to, `color` its normal colour.
   */
  pickable(mesh: THREE.Mesh, object: string, piece: string | null, color: number): void {
    mesh.userData = { ...mesh.userData, object, piece, color };
    if (piece) this.pieces.set(piece, mesh); else this.bodies.set(object, mesh);
  }

  setState(key: string, s: PickState): void { this.state.set(key, s); }
  clearStates(): void { this.state.clear(); }

  restyle(): void {
    for (const [key, mesh] of this.pieces) {
      const s = this.state.get(key) ?? {};
      const mat = mesh.material as THREE.MeshStandardMaterial;
      mat.color.setHex(s.bad ? 0xff0000 : mesh.userData.color);
      mat.emissive.setHex(s.bad ? 0x660000 : s.selected || s.picked ? 0xffcc00 : mesh.userData.object === this.selectedObject ? 0x665500 : 0x000000);
      if (!mesh.userData.ghost) mat.opacity = s.dim ? 0.15 : 1;
    }
    for (const [name, mesh] of this.bodies) {
      const mat = mesh.material as THREE.MeshStandardMaterial;
      mat.emissive.setHex(name === this.selectedObject ? 0x665500 : 0x000000);
    }
    this.render();
  }

  pickAt(clientX: number, clientY: number): { piece: string | null; object: string | null } {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const hits = this.raycaster.intersectObjects([...this.pieces.values()], false);
    if (hits.length) return { piece: hits[0].object.userData.piece, object: hits[0].object.userData.object };
    const bodies = this.raycaster.intersectObjects([...this.bodies.values()], false);
    if (bodies.length) return { piece: null, object: bodies[0].object.userData.object };
    return { piece: null, object: null };
  }

  /** Client coordinates of a point on the piece's surface that a click there would pick. */
  screenPointOf(key: string): { x: number; y: number } | null {
    const mesh = this.pieces.get(key); if (!mesh) return null;
    const pos = mesh.geometry.getAttribute('position');
    const r = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3();
    for (let i = 0; i < pos.count; i += Math.max(1, Math.floor(pos.count / 200))) {
      v.fromBufferAttribute(pos, i).applyMatrix4(mesh.matrixWorld).project(this.camera);
      const x = r.left + (v.x + 1) / 2 * r.width, y = r.top + (1 - v.y) / 2 * r.height;
      if (x < r.left + 2 || x > r.right - 2 || y < r.top + 2 || y > r.bottom - 2) continue;
      if (this.pickAt(x, y).piece === key) return { x, y };
    }
    return null;
  }

  frameAll(): void { this.frameBox(new THREE.Box3().setFromObject(this.root)); }

  /** Points the camera at a box (mm, world) from the current direction so that all of it is in view. */
  frameBox(box: THREE.Box3): void {
    if (box.isEmpty()) { this.render(); return; }
    const c = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    const dist = size / (2 * Math.tan((this.camera.fov * Math.PI) / 360)) * 1.1 + 10;
    this.controls.target.copy(c);
    this.camera.position.copy(c.clone().add(dir.multiplyScalar(dist)));
    this.camera.updateProjectionMatrix(); this.controls.update(); this.render();
  }

  view(name: ViewName): void {
    const dirs = { top: [0, -0.0001, 1], front: [0, -1, 0], side: [1, 0, 0], iso: [1, -1, 0.8] } as const;
    const t = this.controls.target;
    const dist = Math.max(100, this.camera.position.distanceTo(t));
    this.camera.position.copy(t.clone().add(new THREE.Vector3(...dirs[name]).normalize().multiplyScalar(dist)));
    this.controls.update();
    this.frameAll();
  }
}
