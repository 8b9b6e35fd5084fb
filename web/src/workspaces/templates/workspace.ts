// The templates workspace: the composed model in the 3D view (parts in their materials,
// connectors blue, unstable parts red, unselected parts see-through), the selected node's
// handles (arrows translate, spheres scale; constrained directions have none), drags solved by
// the library's QP on the server, drops of templates from the library. Panels are in ./panels.ts.
import * as THREE from 'three';
import { ApiError, templatesApi } from './api';
import type { BuildAnswer, Composed, Controls, DragAnswer, ModelState, NodeData, PartData, TemplatesApi } from './api';
import { freshName, modelToYaml, withAdjust } from './model';
import type { TemplatesModel } from './model';
import { geometryOf } from '../../shell/scene';
import type { Vec3 } from '../../shell/scene';
import type { SelectionState } from '../../shell/selection';
import type { MountedWorkspace, ShellContext } from '../../shell/workspace';
import { download } from '../../shell/ui';
import { fileStem } from '../../shell/shell';
import { Panels } from './panels';
import './templates.css';

export const ROOT = '/';
const AXIS_COLORS = [0xe53935, 0x43a047, 0x1e63d6];
const AXIS_NAMES = ['x', 'y', 'z'];
export const STABLE_GREEN = 0x2eaa45;
export const UNSTABLE_RED = 0xff0000;
const CONNECTOR_GREY = 0x8a8a8a;
export const DRAG_MIME = 'application/x-fabkit-template';

const hex = (c: [number, number, number]) => (Math.round(c[0] * 255) << 16) | (Math.round(c[1] * 255) << 8) | Math.round(c[2] * 255);
const boxOf = (b: { min: number[]; max: number[] }) => new THREE.Box3(new THREE.Vector3(...b.min), new THREE.Vector3(...b.max));
/** Node paths: '' is the root; the selection uses ROOT for it. */
export const keyOf = (path: string) => path || ROOT;
export const pathOf = (key: string) => (key === ROOT ? '' : key);

export function describeError(e: unknown): string {
  if (e instanceof ApiError) {
    const more = e.diagnostics.filter((d) => d.severity === 'error').map((d) => d.text || d.message);
    return more.length > 1 ? `${e.message}\n${more.slice(1).join('\n')}` : e.message;
  }
  return (e as Error).message ?? String(e);
}

/** A handle; `sign` −1 for the sphere on a box's min face (dragging it outward grows the box). */
interface Handle { mesh: THREE.Mesh; control: string; axis: number; size: boolean; point: THREE.Vector3; sign: number }
interface Gesture {
  handle: Handle; node: string; startX: number; startY: number; dirPx: THREE.Vector2; pxPerMm: number;
  delta: number; sent: number | null; inFlight: boolean; last: DragAnswer | null; done: boolean; yaml: string;
}

export class TemplatesWorkspace implements MountedWorkspace {
  readonly api: TemplatesApi;
  library: Awaited<ReturnType<TemplatesApi['library']>> | null = null;
  composed: Composed | null = null;
  /** What the 3D view shows: the composed model, or a drag step's preview. */
  view: ModelState | null = null;
  composeError: string | null = null;
  controls: Controls | null = null;
  colorBy: 'materials' | 'stability' = 'materials';
  buildAnswer: { yaml: string; answer: BuildAnswer } | null = null;
  gesture: Gesture | null = null;
  /** Round trips of drag steps (request sent → new geometry drawn), ms; and the server's part. */
  dragTimings: { roundTrip: number; request: number; draw: number; server: number; qp: number }[] = [];
  lastDrag: DragAnswer | null = null;
  readonly panels: Panels;
  private handles: Handle[] = [];
  private meshes = new Map<string, THREE.Mesh>();
  private seq = 0;
  private framed = false;
  private offs: (() => void)[] = [];
  private raycaster = new THREE.Raycaster();
  hooks: Record<string, unknown>;

  constructor(readonly ctx: ShellContext<TemplatesModel>) {
    this.api = templatesApi(ctx.server);
    this.panels = new Panels(this);
    ctx.toolbarButton('file', 'BOM CSV', 'download-bom-csv', 'Download the bill of materials as CSV (a spreadsheet)', () => void ctx.track(this.downloadOutput('bom.csv')));
    ctx.toolbarButton('file', 'Report', 'download-report', 'Download the printable report (HTML): a picture, the bill with prices, stability and every cut diagram', () => void ctx.track(this.downloadOutput('report.html')));
    ctx.toolbarButton('file', 'Download .glb', 'download-glb', 'Download the 3D model (binary glTF: parts in their materials, connectors blue, unstable parts red)', () => void ctx.track(this.downloadOutput('scene.glb')));
    ctx.toolbarButton('run', 'Build', 'build', 'Make every output (bill of materials, cut diagrams, report, 3D model) and list them for download', () => void ctx.track(this.build()), { primary: true });
    this.offs.push(ctx.history.onChange((_d, label) => {
      if (label.startsWith('open') || label === 'new design') this.framed = false;
      void ctx.track(this.refresh());
    }));
    const scene = ctx.scene;
    this.setLegend();
    scene.onPick = (piece) => this.pickPart(piece);
    scene.onHover = () => {};
    this.offs.push(ctx.selection.onChange(() => { this.restyle(); }));
    const host = scene.renderer.domElement.parentElement!;
    const down = (e: PointerEvent) => this.pointerDown(e);
    host.addEventListener('pointerdown', down, { capture: true });
    this.offs.push(() => host.removeEventListener('pointerdown', down, { capture: true }));
    const over = (e: DragEvent) => { if (e.dataTransfer?.types.includes(DRAG_MIME)) { e.preventDefault(); e.dataTransfer.dropEffect = 'copy'; } };
    const drop = (e: DragEvent) => {
      const spec = e.dataTransfer?.getData(DRAG_MIME);
      if (!spec) return;
      e.preventDefault();
      this.addTemplate(spec, this.dropPoint(e.clientX, e.clientY));
    };
    host.addEventListener('dragover', over);
    host.addEventListener('drop', drop);
    this.offs.push(() => { host.removeEventListener('dragover', over); host.removeEventListener('drop', drop); });
    this.hooks = {
      modelYaml: () => modelToYaml(this.model),
      composed: () => this.composed,
      view: () => this.view && { max_violation: this.view.max_violation, stable: this.view.stability?.stable ?? null, parts: this.view.parts.length },
      selectedNode: () => this.selectedPath(),
      controls: () => this.controls,
      /** Client coordinates of a handle ("size_z", "center_x") of the selected node. */
      handlePoint: (control: string, side?: number) => this.handlePoint(control, side),
      handleControls: () => [...new Set(this.handles.map((h) => h.control))],
      dragTimings: () => this.dragTimings,
      lastDrag: () => this.lastDrag && { achieved: this.lastDrag.achieved, start: this.lastDrag.start, requested: this.lastDrag.requested, message: this.lastDrag.message, max_violation: this.lastDrag.max_violation },
      /** How every part is drawn: colour, see-through, red (unstable). */
      partStyles: () => this.partStyles(),
      projectPart: (name: string) => scene.screenPointOf(`part:${name}`),
      /** Client coordinates of a world point (mm). */
      worldToScreen: (p: Vec3) => {
        const r = scene.renderer.domElement.getBoundingClientRect();
        const v = new THREE.Vector3(...p).project(scene.camera);
        return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
      },
    };
    void ctx.track(this.load());
  }

  get model(): TemplatesModel { return this.ctx.history.current; }

  private async load(): Promise<void> {
    this.ctx.status('loading the template library…');
    try { this.library = await this.api.library(); } catch (e) { this.ctx.message(`The template library could not be loaded: ${describeError(e)}`); }
    this.panels.buildLibrary();
    this.ctx.status('');
    await this.refresh();
  }

  unmount(): void {
    for (const off of this.offs) off();
    this.ctx.scene.onPick = () => {};
    this.ctx.scene.onHover = () => {};
  }

  // ---------------------------------------------------------------- composing
  /** Composes the document on the server and redraws everything. */
  async refresh(): Promise<void> {
    const seq = ++this.seq;
    const m = this.model;
    this.buildAnswer = null;
    if (!m.steps.length) {
      this.composed = null; this.view = null; this.composeError = null; this.controls = null;
      this.draw(); this.panels.render();
      return;
    }
    this.ctx.status('composing…');
    try {
      const c = await this.api.compose(modelToYaml(m));
      if (seq !== this.seq) return;
      this.composed = c; this.view = c; this.composeError = null;
      this.ctx.message('');
    } catch (e) {
      if (seq !== this.seq) return;
      this.composed = null; this.view = null;
      this.composeError = describeError(e);
      this.ctx.message(`The model cannot be composed: ${this.composeError}`, 'error');
    }
    this.ctx.status('');
    this.ctx.selection.keepOnly((k) => this.exists(k));
    await this.loadControls(seq);
    if (seq !== this.seq) return;
    this.draw();
    if (!this.framed && this.view) { this.framed = true; this.ctx.scene.frameAll?.(); }
    this.ctx.scene.keepInView();
    this.panels.render();
  }

  private async loadControls(seq = this.seq): Promise<void> {
    const path = this.selectedPath();
    if (path === null || !this.composed) { this.controls = null; return; }
    try {
      const c = await this.api.controls(modelToYaml(this.model), path);
      if (seq === this.seq) this.controls = c;
    } catch (e) {
      this.controls = null;
      this.ctx.message(`Cannot read the controls of '${path}': ${describeError(e)}`, 'error');
    }
  }

  node(path: string): NodeData | undefined { return this.view?.nodes.find((n) => n.path === path); }
  selectedPath(): string | null {
    const o = this.ctx.selection.current.object;
    return o === null ? null : pathOf(o);
  }

  /** Selects a node of the model (its path; '' the whole model) and shows its handles. */
  async selectNode(path: string | null): Promise<void> {
    this.ctx.selection.set(path === null ? null : keyOf(path), null);
    this.controls = null;
    await this.ctx.track(this.loadControls());
    this.drawHandles();
    this.panels.render();
  }

  /** A click on a part: selects its leaf; a click on a part of the selection walks up one level. */
  private pickPart(piece: string | null): void {
    if (!piece) { void this.selectNode(null); return; }
    const part = this.view?.parts.find((p) => `part:${p.name}` === piece);
    if (!part) return;
    const sel = this.selectedPath();
    if (sel !== null && this.isUnder(part.node, sel)) {
      const parent = this.node(sel)?.parent;
      void this.selectNode(sel === '' ? part.node : parent ?? '');
    } else void this.selectNode(part.node);
  }

  isUnder(path: string, ancestor: string): boolean { return ancestor === '' || path === ancestor || path.startsWith(`${ancestor}/`); }

  /** Adds a template ("design" or "design/path") to the model, dropped at `at` (mm; its box centre). */
  addTemplate(spec: string, at: Vec3 | null): void {
    const [design, ...rest] = spec.split('/');
    const d = this.library?.designs.find((x) => x.name === design);
    const node = d?.nodes.find((n) => n.path === rest.join('/'));
    const m = this.model;
    const base = rest.length ? rest[rest.length - 1] : design;
    const as = freshName(m, base);
    const step: TemplatesModel['steps'][number] = { use: spec, as };
    if (m.steps.length) {
      // The paper drops a part where the pointer is; without a point, under the model's middle.
      const box = this.view ? this.modelBox() : null;
      const h = node ? node.box.max[2] - node.box.min[2] : 0;
      const p: Vec3 = at ?? (box ? [(box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2, 0] : [0, 0, 0]);
      step.at = [Math.round(p[0]), Math.round(p[1]), Math.round(Math.max(p[2], 0) + h / 2)];
    }
    this.ctx.history.apply({ ...m, steps: [...m.steps, step] }, `add ${as} (${spec})`);
  }

  modelBox(): THREE.Box3 {
    const b = new THREE.Box3();
    for (const p of this.view?.parts ?? []) b.union(boxOf(p.box));
    return b;
  }

  /** Where a drop lands: on a part under the pointer, else on the floor (mm). */
  private dropPoint(x: number, y: number): Vec3 | null {
    const scene = this.ctx.scene;
    const r = scene.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, scene.camera);
    const hit = this.raycaster.intersectObjects([...scene.pieces.values()], false)[0];
    if (hit) return [hit.point.x, hit.point.y, hit.point.z];
    const p = new THREE.Vector3();
    const floor = new THREE.Plane(new THREE.Vector3(0, 0, 1), 0);
    return this.raycaster.ray.intersectPlane(floor, p) ? [p.x, p.y, 0] : null;
  }

  /** Removes the selected node: a whole composition leaves the list, any other node goes to `remove:`. */
  removeSelected(): void {
    const path = this.selectedPath();
    if (path === null || path === '') { this.ctx.message('Select a part or a group of the model to remove (the whole model cannot be removed; use New).'); return; }
    const m = this.model;
    const comp = m.steps.find((s) => s.as === path);
    this.ctx.selection.clear();
    if (comp) {
      const keep = (n: string) => !(n === path || n.startsWith(`${path}/`));
      this.ctx.history.apply({ ...m, steps: m.steps.filter((s) => s !== comp), remove: m.remove.filter(keep), adjust: m.adjust.filter((a) => keep(a.node)) }, `remove ${path}`);
    } else {
      this.ctx.history.apply({ ...m, remove: [...m.remove, path] }, `remove ${path}`);
    }
  }
  deleteSelection(): void { this.removeSelected(); }

  /** Sets a control to a value (a field in the Controls panel): the server's set() reaches it or names what stops it. */
  setControl(control: string, value: number): void {
    const path = this.selectedPath();
    if (path === null || !Number.isFinite(value)) return;
    const last = this.model.adjust[this.model.adjust.length - 1];
    if (last && last.node === path && last.control === control && last.to === value) return; // a second change event
    this.ctx.history.apply(withAdjust(this.model, { node: path, control, to: value }), `set ${path || 'model'} ${control} to ${value} mm`);
  }

  // ---------------------------------------------------------------- drawing
  setLegend(): void {
    const entries = this.colorBy === 'stability'
      ? [{ color: STABLE_GREEN, label: 'stable part' }, { color: UNSTABLE_RED, label: 'unstable part', title: 'tips or slides at rest or under the loads' }, { color: CONNECTOR_GREY, label: 'connector' }]
      : [{ color: 0xc9a36b, label: 'wood / sheet' }, { color: 0x3366d9, label: 'connector', title: 'screws, brackets, hinges, slides that join parts' },
        { color: UNSTABLE_RED, label: 'unstable part' }];
    this.ctx.scene.setLegend([...entries,
      ...AXIS_NAMES.map((a, i) => ({ color: AXIS_COLORS[i], label: `${a}: arrow moves, sphere resizes` })),
      { color: 0xff9800, label: 'selected' }]);
  }

  /** Draws the model (or a drag preview) and the handles. */
  draw(): void {
    if (this.updateInPlace()) { this.drawHandles(); this.restyle(); return; }
    const scene = this.ctx.scene;
    this.meshes.clear();
    scene.clearLayer('model');
    scene.clearLayer('links');
    const layer = scene.layer('model');
    for (const p of this.view?.parts ?? []) {
      const mat = new THREE.MeshStandardMaterial({ color: hex(p.color), roughness: 0.75, metalness: p.role === 'connecting' ? 0.3 : 0, transparent: true });
      const mesh = new THREE.Mesh(geometryOf(p.mesh), mat);
      layer.add(mesh);
      scene.pickable(mesh, keyOf(p.node), `part:${p.name}`, this.colorOf(p));
      this.meshes.set(p.name, mesh);
    }
    // Pairs that could not be joined: a label between them saying why.
    const links = scene.layer('links');
    void links;
    for (const s of this.composed?.steps ?? []) {
      for (const l of s.links ?? []) {
        if (l.connected) continue;
        const a = this.view?.parts.find((p) => p.element === l.added), b = this.view?.parts.find((p) => p.element === l.existing);
        if (!a || !b) continue;
        const c = boxOf(a.box).union(boxOf(b.box)).getCenter(new THREE.Vector3());
        scene.addLabel('links', c, `no connection: ${l.added} – ${l.existing}`, { 'data-testid': `no-connection-label-${l.added}-${l.existing}`, class: 'failure', title: l.message });
      }
    }
    this.drawHandles();
    this.restyle();
  }

  /**
   * During a drag the parts keep their meshes (same parts, same vertex counts): only the vertex
   * positions and colours change, which keeps a drag step's redraw cheap.
   */
  private updateInPlace(): boolean {
    const parts = this.view?.parts ?? [];
    if (!this.gesture || parts.length !== this.meshes.size) return false;
    for (const p of parts) {
      const m = this.meshes.get(p.name);
      if (!m || m.geometry.getAttribute('position').count * 3 !== p.mesh.vertices.length) return false;
    }
    for (const p of parts) {
      const m = this.meshes.get(p.name)!;
      const pos = m.geometry.getAttribute('position') as THREE.BufferAttribute;
      (pos.array as Float32Array).set(p.mesh.vertices);
      pos.needsUpdate = true;
      m.geometry.computeVertexNormals();
      m.geometry.computeBoundingSphere();
      m.geometry.computeBoundingBox();
      m.userData.color = this.colorOf(p);
    }
    return true;
  }

  colorOf(p: PartData): number {
    if (this.colorBy === 'stability') return p.role === 'connecting' ? CONNECTOR_GREY : p.stable ? STABLE_GREEN : UNSTABLE_RED;
    return hex(p.color);
  }

  restyle(): void {
    const scene = this.ctx.scene;
    const sel = this.selectedPath();
    scene.selectedObject = null;
    scene.clearStates();
    for (const p of this.view?.parts ?? []) {
      const under = sel !== null && this.isUnder(p.node, sel);
      scene.setState(`part:${p.name}`, { dim: sel !== null && !under, selected: under && sel !== '', bad: this.colorBy === 'materials' && p.role === 'principal' && !p.stable });
    }
    scene.restyle();
  }

  partStyles(): Record<string, { color: number; dim: boolean; red: boolean; opacity: number }> {
    const out: Record<string, { color: number; dim: boolean; red: boolean; opacity: number }> = {};
    for (const [key, mesh] of this.ctx.scene.pieces) {
      if (!key.startsWith('part:')) continue;
      const mat = mesh.material as THREE.MeshStandardMaterial;
      out[key.slice(5)] = { color: mat.color.getHex(), dim: mat.opacity < 0.5, red: mat.color.getHex() === UNSTABLE_RED, opacity: mat.opacity };
    }
    return out;
  }

  /** The selected node's handles: an arrow per free centre direction, a sphere per free size. */
  drawHandles(): void {
    const scene = this.ctx.scene;
    scene.clearLayer('handles');
    this.handles = [];
    const path = this.selectedPath();
    const c = this.controls;
    if (path === null || !c || c.node !== path) { scene.render(); return; }
    const node = this.node(path);
    const box = boxOf(node?.box ?? c.box);
    const size = box.getSize(new THREE.Vector3()), center = box.getCenter(new THREE.Vector3());
    const scale = Math.min(Math.max(size.length() * 0.025, 8), 40);
    const layer = scene.layer('handles');
    for (const ctl of c.controls) {
      if (ctl.hidden) continue;
      const axis = new THREE.Vector3().setComponent(ctl.axis, 1);
      const face = center.clone().addScaledVector(axis, size.getComponent(ctl.axis) / 2);
      const mat = new THREE.MeshBasicMaterial({ color: AXIS_COLORS[ctl.axis], depthTest: false, transparent: true, opacity: 0.95 });
      let mesh: THREE.Mesh;
      let point: THREE.Vector3;
      if (ctl.size) {
        point = face.clone();
        mesh = new THREE.Mesh(new THREE.SphereGeometry(scale * 0.8, 20, 14), mat);
        mesh.position.copy(point);
        // a second sphere on the opposite face (paper Fig. 7: both sides can be pulled)
        const minFace = center.clone().addScaledVector(axis, -size.getComponent(ctl.axis) / 2);
        const other = new THREE.Mesh(mesh.geometry, mat);
        other.position.copy(minFace);
        other.renderOrder = 10;
        other.userData.handle = ctl.control;
        layer.add(other);
        this.handles.push({ mesh: other, control: ctl.control, axis: ctl.axis, size: true, point: minFace, sign: -1 });
      } else {
        point = face.clone().addScaledVector(axis, scale * 3.2);
        const g = new THREE.ConeGeometry(scale * 0.7, scale * 2, 16);
        g.translate(0, scale, 0);
        const shaft = new THREE.CylinderGeometry(scale * 0.18, scale * 0.18, scale * 2.2, 8);
        shaft.translate(0, -scale * 1.1, 0);
        mesh = new THREE.Mesh(g, mat);
        const s = new THREE.Mesh(shaft, mat);
        mesh.add(s);
        mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis);
        mesh.position.copy(face.clone().addScaledVector(axis, scale * 2.2));
      }
      mesh.renderOrder = 10;
      mesh.userData.handle = ctl.control;
      layer.add(mesh);
      this.handles.push({ mesh, control: ctl.control, axis: ctl.axis, size: ctl.size, point, sign: 1 });
    }
    scene.render();
  }

  /** Where a handle is on the screen (`side` −1: a size's sphere on the min face). */
  handlePoint(control: string, side = 1): { x: number; y: number } | null {
    const h = this.handles.find((x) => x.control === control && x.sign === side);
    if (!h) return null;
    const r = this.ctx.scene.renderer.domElement.getBoundingClientRect();
    const v = h.mesh.getWorldPosition(new THREE.Vector3()).project(this.ctx.scene.camera);
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  }

  // ---------------------------------------------------------------- dragging a handle
  private pointerDown(e: PointerEvent): void {
    if (e.button !== 0 || !this.handles.length || this.gesture) return;
    const scene = this.ctx.scene;
    const r = scene.renderer.domElement.getBoundingClientRect();
    this.raycaster.setFromCamera(new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1), scene.camera);
    const hit = this.raycaster.intersectObjects(this.handles.map((h) => h.mesh), true)[0];
    if (!hit) return;
    let o: THREE.Object3D | null = hit.object;
    while (o && !o.userData.handle) o = o.parent;
    const handle = this.handles.find((h) => h.mesh === o);
    if (!handle) return;
    // the handle takes the gesture: no orbiting, no picking
    e.stopPropagation(); e.preventDefault();
    const p0 = handle.mesh.getWorldPosition(new THREE.Vector3());
    const axis = new THREE.Vector3().setComponent(handle.axis, 1);
    const L = 100;
    const s0 = p0.clone().project(scene.camera), s1 = p0.clone().addScaledVector(axis, L).project(scene.camera);
    const dir = new THREE.Vector2(((s1.x - s0.x) / 2) * r.width, (-(s1.y - s0.y) / 2) * r.height);
    const len = dir.length();
    if (len < 4) { this.ctx.message(`The ${AXIS_NAMES[handle.axis]} axis points at you: turn the view to drag this handle.`); return; }
    this.gesture = {
      handle, node: this.selectedPath()!, startX: e.clientX, startY: e.clientY, dirPx: dir.divideScalar(len), pxPerMm: len / L,
      delta: 0, sent: null, inFlight: false, last: null, done: false, yaml: modelToYaml(this.model),
    };
    const move = (ev: PointerEvent) => {
      const g = this.gesture; if (!g) return;
      ev.stopPropagation(); // the view's hover highlighting would redraw the scene on every move
      const d = new THREE.Vector2(ev.clientX - g.startX, ev.clientY - g.startY);
      g.delta = g.handle.sign * Math.round((d.dot(g.dirPx) / g.pxPerMm) * 10) / 10;
      this.pump();
    };
    const up = (ev: PointerEvent) => {
      ev.stopPropagation();
      window.removeEventListener('pointermove', move, true);
      window.removeEventListener('pointerup', up, true);
      if (this.gesture) { this.gesture.done = true; this.pump(); }
    };
    window.addEventListener('pointermove', move, true);
    window.addEventListener('pointerup', up, true);
    this.ctx.status(`dragging ${handle.control} of ${this.gesture.node || 'the model'}…`);
    // shadows are redrawn when the drag is let go: the shadow pass doubles a frame's cost
    scene.renderer.shadowMap.autoUpdate = false;
    // counted as busy until the gesture is committed
    void this.ctx.track(new Promise<void>((resolve) => { this.gestureDone = resolve; }));
  }
  private gestureDone: (() => void) | null = null;

  /** Sends the gesture's latest δ when no step is in flight; commits it when the pointer is up. */
  private pump(): void {
    const g = this.gesture;
    if (!g || g.inFlight) return;
    if (g.sent !== g.delta) {
      const delta = g.delta;
      g.inFlight = true; g.sent = delta;
      const t0 = performance.now();
      // Under loads the contact-force check takes ~100 ms: it runs when the drag is let go.
      const stability = !this.model.loads.length;
      this.api.drag(g.yaml, g.node, g.handle.control, delta, { stability }).then(async (a) => {
        const received = performance.now();
        if (!a.stability && this.composed) {
          const was = new Map(this.composed.parts.map((p) => [p.name, p.stable]));
          for (const p of a.parts) p.stable = was.get(p.name) ?? true;
        }
        g.last = a; this.lastDrag = a;
        this.view = a;
        this.draw();
        this.panels.renderLive(a);
        const drawn = performance.now();
        // until the browser has painted the frame with the new geometry
        await new Promise((r) => requestAnimationFrame(() => r(null)));
        this.dragTimings.push({ roundTrip: performance.now() - t0, request: received - t0, draw: drawn - received, server: a.milliseconds, qp: a.qp_milliseconds });
      }).catch((e) => {
        this.ctx.message(`The drag was refused: ${describeError(e)}`, 'error');
        g.done = true; g.sent = g.delta;
      }).finally(() => { g.inFlight = false; this.pump(); });
      return;
    }
    if (g.done) this.commit(g);
  }

  private commit(g: Gesture): void {
    this.gesture = null;
    this.ctx.scene.renderer.shadowMap.autoUpdate = true;
    this.ctx.scene.renderer.shadowMap.needsUpdate = true;
    this.ctx.status('');
    const resolve = this.gestureDone; this.gestureDone = null;
    const a = g.last;
    if (a && Math.abs(a.achieved - a.start) > 0.05) {
      this.ctx.history.apply(withAdjust(this.model, { node: g.node, control: g.handle.control, to: Math.round(a.achieved * 10) / 10 }),
        `drag ${g.node || 'model'} ${g.handle.control} to ${a.achieved.toFixed(1)} mm`);
      if (a.message) this.ctx.message(a.message, 'info');
    } else if (this.composed) {
      this.view = this.composed; this.draw();
    }
    resolve?.();
  }

  // ---------------------------------------------------------------- outputs
  async build(): Promise<BuildAnswer | null> {
    const yaml = modelToYaml(this.model);
    if (this.buildAnswer?.yaml === yaml) return this.buildAnswer.answer;
    if (!this.model.steps.length) { this.ctx.message('The model is empty: drag a template from the library into the view first.'); return null; }
    this.ctx.status('building…');
    try {
      const answer = await this.api.build(yaml);
      this.buildAnswer = { yaml, answer };
      this.ctx.message(answer.message, answer.termination === 'built' ? 'info' : 'error');
      return answer;
    } catch (e) {
      this.ctx.message(`Cannot build: ${describeError(e)}`, 'error');
      return null;
    } finally {
      this.ctx.status('');
      this.panels.renderDownloads();
    }
  }

  async downloadOutput(name: string): Promise<void> {
    const answer = await this.build();
    const f = answer?.files.find((x) => x.name === name);
    if (!f) { if (answer) this.ctx.message(`The build wrote no ${name}.`, 'error'); return; }
    this.downloadFile(f);
  }

  downloadFile(f: BuildAnswer['files'][number]): void {
    const stem = fileStem(this.model.name);
    const data = f.base64 !== undefined ? new Blob([Uint8Array.from(atob(f.base64), (c) => c.charCodeAt(0))], { type: f.type }) : f.text ?? '';
    download(`${stem}_${f.name}`, data, f.type);
  }

  // ---------------------------------------------------------------- shell
  describeSelection(sel: SelectionState): string {
    if (!sel.object) return this.view ? 'Nothing selected — click a part to select it (click again to walk up the hierarchy)' : 'Nothing selected';
    const path = pathOf(sel.object);
    const n = this.node(path);
    if (!n) return `Selected: ${path}`;
    const kind = path === '' ? 'the whole model' : n.element ? `part ${n.element}` : n.connection ? `connection ${n.name}` : `group ${path}`;
    const parts = this.view?.parts.filter((p) => this.isUnder(p.node, path)).length ?? 0;
    const free = this.controls?.node === path ? this.controls.controls.filter((c) => !c.hidden).map((c) => c.control) : [];
    return `Selected: ${kind} (${parts} parts)${free.length ? ` — drag: ${free.join(', ')}` : this.controls?.node === path ? ' — fully constrained: nothing to drag' : ''}`;
  }

  exists(object: string): boolean { return object === ROOT ? !!this.view : !!this.node(pathOf(object)); }
  cancel(): boolean { if (this.ctx.selection.current.object) { void this.selectNode(null); return true; } return false; }
}
