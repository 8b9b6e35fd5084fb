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

const SELECTED = 0xff9800, HOVER = 0x2f6fff;

/**
 * An outline drawn as an inverted hull: the mesh's back faces pushed out along the normals by a
 * fixed number of pixels, so it has the same screen width at any zoom. It marks the selection
 * and gives thin wires (2 mm S-hooks) a minimum visible width when zoomed out.
 */
export function outlineMaterial(color: number, widthPx: number): THREE.ShaderMaterial {
  return new THREE.ShaderMaterial({
    uniforms: { color: { value: new THREE.Color(color) }, width: { value: widthPx }, resolution: { value: new THREE.Vector2(1000, 1000) } },
    vertexShader: `
      uniform float width; uniform vec2 resolution;
      void main() {
        vec4 clip = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
        vec3 n = normalize(normalMatrix * normal);
        vec2 dir = (projectionMatrix * vec4(n, 0.0)).xy;
        float len = length(dir);
        if (len > 1e-6) clip.xy += dir / len * width * 2.0 / resolution * clip.w;
        gl_Position = clip;
      }`,
    fragmentShader: 'uniform vec3 color; void main() { gl_FragColor = vec4(color, 1.0); }',
    side: THREE.BackSide,
  });
}
export type ViewName = 'top' | 'front' | 'side' | 'iso';

export class SceneView {
  renderer: THREE.WebGLRenderer;
  scene = new THREE.Scene();
  /** The active camera: perspective (orbiting, Iso) or orthographic (the standard views). */
  camera: THREE.PerspectiveCamera | THREE.OrthographicCamera;
  readonly perspective: THREE.PerspectiveCamera;
  readonly orthographic: THREE.OrthographicCamera;
  /** How an object is shown: hidden and see-through objects are not picked. */
  private display = new Map<string, 'hidden' | 'xray'>();
  /** Objects shown alone ("isolate"); null: all. */
  private isolated: Set<string> | null = null;
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
  /** The piece (or object body) under the pointer: highlighted in blue. */
  hovered: string | null = null;
  /** Outline meshes by the key of the mesh they outline. */
  private outlines = new Map<THREE.Mesh, THREE.Mesh>();
  private sun = new THREE.DirectionalLight(0xffffff, 1.5);
  /** The floor: a grid and a shadow catcher, kept just below the lowest thing drawn. */
  private floor = new THREE.Group();
  private grid = new THREE.GridHelper(2000, 20, 0xbbbbbb, 0xdddddd);
  private shadowCatcher = new THREE.Mesh(new THREE.PlaneGeometry(1, 1), new THREE.ShadowMaterial({ opacity: 0.18 }));
  /** Set when layers change: the floor and the shadow camera are fitted again at the next restyle. */
  private boundsChanged = true;
  floorZ = 0;
  private legendEl: HTMLElement | null = null;
  onPick: (piece: string | null, object: string | null) => void = () => {};
  onHover: (piece: string | null, x: number, y: number) => void = () => {};
  /** Called after every render (overlays that follow the camera). */
  onRender: (() => void)[] = [];
  /** HTML labels pinned to world points, by layer; repositioned after every render. */
  private labels: { layer: string; at: THREE.Vector3; el: HTMLElement }[] = [];
  private labelHost: HTMLElement;

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setClearColor(0xf4f6f8);
    // soft shadows so contacts read (a hook on a rod, a basket on its handle)
    this.renderer.shadowMap.enabled = true;
    this.renderer.shadowMap.type = THREE.PCFSoftShadowMap;
    host.appendChild(this.renderer.domElement);
    this.labelHost = document.createElement('div');
    this.labelHost.className = 'scene-labels';
    host.appendChild(this.labelHost);
    this.renderer.domElement.dataset.testid = 'scene-canvas';
    this.perspective = new THREE.PerspectiveCamera(40, 1, 1, 20000);
    this.orthographic = new THREE.OrthographicCamera(-500, 500, 500, -500, -20000, 20000);
    for (const c of [this.perspective, this.orthographic]) { c.up.set(0, 0, 1); c.position.set(800, -800, 600); }
    this.camera = this.perspective;
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.zoomToCursor = true; // the wheel zooms towards the point under the pointer
    this.controls.addEventListener('change', () => this.render());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.5));
    this.sun.position.set(1, -2, 3);
    this.sun.castShadow = true;
    this.sun.shadow.mapSize.set(1024, 1024);
    this.sun.shadow.bias = -0.0004;
    this.sun.shadow.normalBias = 0.6;
    this.scene.add(this.sun, this.sun.target);
    this.grid.rotation.x = Math.PI / 2;
    this.floor.add(this.grid, this.shadowCatcher);
    this.shadowCatcher.receiveShadow = true;
    this.scene.add(this.floor);
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
    el.addEventListener('pointerleave', (e) => { this.setHover(null); this.onHover(null, e.clientX, e.clientY); });
    el.addEventListener('pointermove', (e) => {
      const hit = this.pickAt(e.clientX, e.clientY);
      this.setHover(hit.piece ?? hit.object);
      this.onHover(hit.piece, e.clientX, e.clientY);
    });
  }

  resize(): void {
    const w = Math.max(1, this.host.clientWidth), h = Math.max(1, this.host.clientHeight);
    this.renderer.setSize(w, h, true);
    this.perspective.aspect = w / h; this.perspective.updateProjectionMatrix();
    this.setOrthoHeight(this.orthoHalfHeight);
    for (const hull of this.outlines.values()) (hull.material as THREE.ShaderMaterial).uniforms.resolution.value.set(w, h);
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
    this.boundsChanged = true;
    for (const [m, hull] of [...this.outlines]) if (!this.inScene(m)) { (hull.material as THREE.Material).dispose(); this.outlines.delete(m); }
    for (const [k, m] of [...this.pieces]) if (!this.inScene(m)) this.pieces.delete(k);
    for (const [k, m] of [...this.bodies]) if (!this.inScene(m)) this.bodies.delete(k);
  }

  /** Removes every layer (switching workspaces). */
  clearAll(): void {
    for (const name of [...this.layers.keys()]) { this.clearLayer(name); this.root.remove(this.layers.get(name)!); }
    this.layers.clear(); this.state.clear(); this.selectedObject = null; this.hovered = null;
    this.setLegend([]);
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
    mesh.castShadow = true; mesh.receiveShadow = true;
    this.boundsChanged = true;
    if (piece) this.pieces.set(piece, mesh); else this.bodies.set(object, mesh);
    // every pickable gets a hull outline: thin and dark normally (thin wires stay visible),
    // wide and orange when selected, blue when hovered
    const hull = new THREE.Mesh(mesh.geometry, outlineMaterial(0x333333, 0.8));
    hull.userData.outline = true;
    hull.raycast = () => {};
    mesh.add(hull);
    this.outlines.set(mesh, hull);
  }

  /** Highlights the piece or object under the pointer (also from lists: hovering an item). */
  setHover(key: string | null): void {
    if (this.hovered === key) return;
    this.hovered = key;
    this.restyle();
  }

  setState(key: string, s: PickState): void { this.state.set(key, s); }
  clearStates(): void { this.state.clear(); }

  restyle(): void {
    if (this.boundsChanged) { this.boundsChanged = false; this.fitFloor(); }
    const size = this.renderer.getSize(new THREE.Vector2());
    const style = (mesh: THREE.Mesh, selected: boolean, hovered: boolean, dim: boolean) => {
      const hull = this.outlines.get(mesh); if (!hull) return;
      const m = hull.material as THREE.ShaderMaterial;
      m.uniforms.resolution.value.copy(size);
      m.uniforms.color.value.setHex(selected ? SELECTED : hovered ? HOVER : 0x333333);
      m.uniforms.width.value = selected ? 3 : hovered ? 2.5 : 0.8;
      hull.visible = !dim && !mesh.userData.ghost;
    };
    for (const [key, mesh] of this.pieces) {
      const s = this.state.get(key) ?? {};
      const mat = mesh.material as THREE.MeshStandardMaterial;
      const inSelected = mesh.userData.object === this.selectedObject;
      const hovered = this.hovered === key;
      mat.color.setHex(s.bad ? 0xff0000 : mesh.userData.color);
      mat.emissive.setHex(s.bad ? 0x660000 : s.selected || s.picked ? 0x886600 : hovered ? 0x1a3a88 : inSelected ? 0x443300 : 0x000000);
      if (!mesh.userData.ghost) mat.opacity = s.dim ? 0.15 : 1;
      style(mesh, !!(s.selected || s.picked || (inSelected && !this.pieceSelected())), hovered, !!s.dim);
      this.applyDisplay(mesh);
    }
    for (const [name, mesh] of this.bodies) {
      const mat = mesh.material as THREE.MeshStandardMaterial;
      const hovered = this.hovered === name;
      mat.emissive.setHex(name === this.selectedObject ? 0x443300 : hovered ? 0x1a3a88 : 0x000000);
      style(mesh, name === this.selectedObject && !this.pieceSelected(), hovered, false);
      this.applyDisplay(mesh);
    }
    this.render();
  }

  private applyDisplay(mesh: THREE.Mesh): void {
    const mode = this.displayOf(mesh.userData.object);
    const mat = mesh.material as THREE.MeshStandardMaterial;
    mesh.visible = mode !== 'hidden';
    const wasTransparent = mat.transparent;
    if (mode === 'xray') { mat.transparent = true; mat.opacity = 0.12; mat.depthWrite = false; }
    else {
      mat.depthWrite = true;
      if (mesh.userData.piece === null) { mat.transparent = !!mesh.userData.ghost; mat.opacity = mesh.userData.ghost ? 0.35 : 1; }
    }
    if (wasTransparent !== mat.transparent) mat.needsUpdate = true;
    const hull = this.outlines.get(mesh);
    if (hull && mode === 'xray') hull.visible = false;
  }

  /** True when a piece (not only an object) is selected or picked. */
  private pieceSelected(): boolean {
    for (const s of this.state.values()) if (s.selected || s.picked) return true;
    return false;
  }

  /** How a piece or body is drawn now (for tests): its emissive colour and outline. */
  styleOf(key: string): { emissive: number; outline: number; outlineWidth: number } | null {
    const mesh = this.pieces.get(key) ?? this.bodies.get(key); if (!mesh) return null;
    const hull = this.outlines.get(mesh)!;
    const u = (hull.material as THREE.ShaderMaterial).uniforms;
    return { emissive: (mesh.material as THREE.MeshStandardMaterial).emissive.getHex(), outline: u.color.value.getHex(), outlineWidth: hull.visible ? u.width.value : 0 };
  }

  pickAt(clientX: number, clientY: number): { piece: string | null; object: string | null } {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const shown = (m: THREE.Mesh) => this.displayOf(m.userData.object) === 'normal';
    const hits = this.raycaster.intersectObjects([...this.pieces.values()].filter(shown), false);
    const bodies = this.raycaster.intersectObjects([...this.bodies.values()].filter(shown), false);
    // A piece wins over its own object's body (pieces sit on or in their body), but another
    // object's body in front of it hides it (a wall in front of a hoop).
    const p = hits[0], b = bodies[0];
    if (p && !(b && b.distance < p.distance && b.object.userData.object !== p.object.userData.object)) return { piece: p.object.userData.piece, object: p.object.userData.object };
    if (b) return { piece: null, object: b.object.userData.object };
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

  frameAll(): void { this.frameBox(this.visibleBox()); }

  /** The box of everything shown (hidden objects left out). */
  visibleBox(filter: (mesh: THREE.Mesh) => boolean = () => true): THREE.Box3 {
    const box = new THREE.Box3();
    this.root.updateMatrixWorld(true);
    this.root.traverseVisible((o) => {
      const m = o as THREE.Mesh;
      if ((m.isMesh || (o as THREE.Line).isLine) && !m.userData.outline && filter(m)) box.expandByObject(m, false);
    });
    return box;
  }

  /**
   * Puts the floor (grid and shadow catcher) just below the lowest thing drawn, so the grid
   * never cuts through hanging parts, and fits the sun's shadow camera around the scene.
   */
  private fitFloor(): void {
    const box = this.visibleBox();
    if (box.isEmpty()) return;
    const c = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3());
    const extent = Math.max(size.x, size.y, 400);
    const cells = 100; // mm per grid cell
    const side = Math.ceil((extent * 1.6) / (cells * 2)) * cells * 2;
    this.floor.remove(this.grid); this.grid.geometry.dispose();
    this.grid = new THREE.GridHelper(side, side / cells, 0xbbbbbb, 0xdddddd);
    this.grid.rotation.x = Math.PI / 2;
    this.floor.add(this.grid);
    this.shadowCatcher.scale.set(side, side, 1);
    this.floorZ = box.min.z - 1;
    this.floor.position.set(Math.round(c.x / cells) * cells, Math.round(c.y / cells) * cells, this.floorZ);
    const r = Math.max(size.length() / 2, 50);
    this.sun.target.position.copy(c);
    this.sun.position.copy(c.clone().add(new THREE.Vector3(1, -2, 3).normalize().multiplyScalar(r * 3)));
    const cam = this.sun.shadow.camera;
    cam.left = -r * 1.3; cam.right = r * 1.3; cam.top = r * 1.3; cam.bottom = -r * 1.3;
    cam.near = r * 0.5; cam.far = r * 6; cam.updateProjectionMatrix();
    this.sun.target.updateMatrixWorld();
  }

  /** A legend of the view's colours (bottom right); empty hides it. */
  setLegend(entries: { color: number; label: string; title?: string }[]): void {
    this.legendEl?.remove();
    this.legendEl = null;
    if (!entries.length) return;
    const box = document.createElement('div');
    box.className = 'scene-legend';
    box.dataset.testid = 'legend';
    for (const e of entries) {
      const row = document.createElement('div');
      const sw = document.createElement('span');
      sw.className = 'swatch';
      sw.style.background = `#${e.color.toString(16).padStart(6, '0')}`;
      row.append(sw, e.label);
      if (e.title) row.title = e.title;
      box.append(row);
    }
    this.host.append(box);
    this.legendEl = box;
  }

  /**
   * Runs `step(t)` for t from 0 to 1 over `ms` milliseconds, rendering each frame (once with
   * t = 1 when the user prefers reduced motion). Resolves when done; a newer animation stops it.
   */
  animate(ms: number, step: (t: number) => void): Promise<void> {
    const id = ++this.animationId;
    if (matchMedia('(prefers-reduced-motion: reduce)').matches || ms <= 0) { step(1); this.render(); return Promise.resolve(); }
    const t0 = performance.now();
    return new Promise((resolve) => {
      const frame = () => {
        if (id !== this.animationId) { resolve(); return; }
        const t = Math.min(1, (performance.now() - t0) / ms);
        step(t); this.render();
        if (t < 1) requestAnimationFrame(frame); else resolve();
      };
      frame();
    });
  }
  private animationId = 0;

  /** What the renderer does, for tests: antialiasing, shadows, where the floor is. */
  renderInfo(): { antialias: boolean; shadows: boolean; floorZ: number; minZ: number; shadowCasters: number } {
    const box = this.visibleBox();
    let casters = 0;
    this.root.traverse((o) => { if ((o as THREE.Mesh).isMesh && o.castShadow) casters++; });
    return { antialias: !!this.renderer.getContext().getContextAttributes()?.antialias, shadows: this.renderer.shadowMap.enabled, floorZ: this.floorZ, minZ: box.min.z, shadowCasters: casters };
  }

  /** Client coordinates of the centre of the meshes of a piece or object key. */
  projectKey(key: string): { x: number; y: number } | null {
    const box = this.visibleBox((m) => m.userData.piece === key || m.userData.object === key);
    if (box.isEmpty()) return null;
    const v = box.getCenter(new THREE.Vector3()).project(this.camera);
    const r = this.renderer.domElement.getBoundingClientRect();
    return { x: r.left + (v.x + 1) / 2 * r.width, y: r.top + (1 - v.y) / 2 * r.height };
  }

  /** Frames the meshes of an object or piece key ("eyehook1", "eyehook1.hook"); false if there are none. */
  frameKeys(keys: string[]): boolean {
    const box = this.visibleBox((m) => keys.includes(m.userData.piece) || keys.includes(m.userData.object));
    if (box.isEmpty()) return false;
    this.frameBox(box);
    return true;
  }

  private orthoHalfHeight = 500;
  private setOrthoHeight(half: number): void {
    this.orthoHalfHeight = half;
    const w = Math.max(1, this.host.clientWidth), h = Math.max(1, this.host.clientHeight);
    const o = this.orthographic;
    o.left = -half * w / h; o.right = half * w / h; o.top = half; o.bottom = -half;
    o.updateProjectionMatrix();
  }

  /** Switches between the perspective and the orthographic camera, keeping the view. */
  setOrthographic(on: boolean): void {
    const next = on ? this.orthographic : this.perspective;
    if (next === this.camera) return;
    const t = this.controls.target;
    const dist = this.camera.position.distanceTo(t);
    if (on) { // same apparent size at the target
      this.setOrthoHeight((dist * Math.tan((this.perspective.fov * Math.PI) / 360)) / this.camera.zoom);
      this.orthographic.zoom = 1;
    } else {
      const half = this.orthoHalfHeight / this.orthographic.zoom;
      const d = half / Math.tan((this.perspective.fov * Math.PI) / 360);
      this.perspective.position.copy(t.clone().add(this.camera.position.clone().sub(t).normalize().multiplyScalar(d)));
    }
    next.position.copy(on ? this.camera.position : next.position);
    next.quaternion.copy(this.camera.quaternion);
    next.updateProjectionMatrix();
    this.camera = next;
    this.controls.object = next;
    this.controls.update();
    this.restyle();
  }

  /** Points the camera at a box (mm, world) from the current direction so that all of it is in view. */
  frameBox(box: THREE.Box3): void {
    if (box.isEmpty()) { this.render(); return; }
    const c = box.getCenter(new THREE.Vector3()), size = Math.max(1, box.getSize(new THREE.Vector3()).length());
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    if (this.camera === this.orthographic) {
      this.orthographic.zoom = 1;
      this.setOrthoHeight(size / 2 * 1.1 + 5);
      this.controls.target.copy(c);
      this.camera.position.copy(c.clone().add(dir.multiplyScalar(Math.max(2000, size * 2))));
    } else {
      const dist = size / (2 * Math.tan((this.perspective.fov * Math.PI) / 360)) * 1.1 + 10;
      this.controls.target.copy(c);
      this.camera.position.copy(c.clone().add(dir.multiplyScalar(dist)));
    }
    this.camera.updateProjectionMatrix(); this.controls.update(); this.render();
  }

  /** Standard views: Top, Front and Side are orthographic, Iso is perspective. */
  view(name: ViewName): void {
    const dirs = { top: [0, -0.0001, 1], front: [0, -1, 0], side: [1, 0, 0], iso: [1, -1, 0.8] } as const;
    this.setOrthographic(name !== 'iso');
    const t = this.controls.target;
    const dist = Math.max(100, this.camera.position.distanceTo(t));
    this.camera.position.copy(t.clone().add(new THREE.Vector3(...dirs[name]).normalize().multiplyScalar(dist)));
    this.controls.update();
    this.frameAll();
  }

  /** After an edit: re-frames when nothing shown is in the view any more (the scene moved away). */
  keepInView(): void {
    const box = this.visibleBox();
    if (box.isEmpty()) return;
    this.camera.updateMatrixWorld();
    const frustum = new THREE.Frustum().setFromProjectionMatrix(new THREE.Matrix4().multiplyMatrices(this.camera.projectionMatrix, this.camera.matrixWorldInverse));
    if (!frustum.containsPoint(box.getCenter(new THREE.Vector3())) || !frustum.intersectsBox(box)) this.frameAll();
  }

  // ---------------------------------------------------------------- hide, see-through, isolate
  /** Shows an object normally, see-through (drawn faint, clicks pass through) or hidden. */
  setDisplay(object: string, mode: 'normal' | 'xray' | 'hidden'): void {
    if (mode === 'normal') this.display.delete(object); else this.display.set(object, mode);
    this.restyle();
  }
  displayOf(object: string): 'normal' | 'xray' | 'hidden' {
    if (this.isolated && !this.isolated.has(object)) return 'hidden';
    return this.display.get(object) ?? 'normal';
  }
  /** Shows only these objects (null: everything again). */
  isolate(objects: string[] | null): void { this.isolated = objects ? new Set(objects) : null; this.restyle(); }
  isolatedObjects(): string[] | null { return this.isolated ? [...this.isolated] : null; }
  showAll(): void { this.display.clear(); this.isolated = null; this.restyle(); }
}
