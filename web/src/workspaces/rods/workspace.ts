// The rods workspace (RodSteward §3, RSDesigner): edit a rod network while the server draws the
// joints and rods as they will be made and checks them on every edit. Panels are in
// ./panels.ts, the guided assembly (§5, RSAssembler) in ./assembler.ts.
import * as THREE from 'three';
import { TransformControls } from 'three/examples/jsm/controls/TransformControls.js';
import { ApiError } from '../../shell/server';
import { geometryOf } from '../../shell/scene';
import type { MeshData, Vec3 } from '../../shell/scene';
import type { SelectionState } from '../../shell/selection';
import type { MountedWorkspace, ShellContext } from '../../shell/workspace';
import { rodsApi } from './api';
import type { Finding, Preview, RodsApi } from './api';
import {
  addNode, connect, deleteParts, isolatedNodes, jointKey, jointLabel, jointName, moveNodes, parseKey, rodKey, rodName, snap, snapToAxis, splitRod,
} from './model';
import type { RodsDesign } from './model';
import { rodsToYaml } from './yamlio';
import { Panels } from './panels';
import { Assembler } from './assembler';

export const JOINT_COLOR = 0xf4f4f0;
export const ROD_COLOR = 0xa0703c;
const SKELETON_COLOR = 0x8899aa;

/** Blue → green → yellow → red for utilisation 0 → ≥ 1 (the frame analysis' colour ramp). */
export function rampColor(u: number): number {
  const t = Math.max(0, Math.min(1, u));
  const stops = [[0.18, 0.35, 0.85], [0.15, 0.7, 0.3], [0.95, 0.8, 0.1], [0.85, 0.1, 0.1]];
  const x = t * (stops.length - 1), k = Math.min(stops.length - 2, Math.floor(x)), f = x - k;
  const c = stops[k].map((v, i) => v + (stops[k + 1][i] - v) * f);
  return new THREE.Color(c[0], c[1], c[2]).getHex();
}

/** What the server is sent: the design without isolated nodes (the library refuses them). */
export function postable(d: RodsDesign): { yaml: string; kept: number[] } {
  const iso = isolatedNodes(d);
  const kept = d.nodes.map((_p, i) => i).filter((i) => !iso.has(i));
  return { yaml: rodsToYaml(iso.size ? deleteParts(d, iso, []) : d), kept };
}

export type Tool = 'select' | 'add' | 'box';
/** One edit's round trip (ms): request (server + transfer + JSON parse), drawing (JS), waiting for the GPU (tests only). */
export interface EditTiming { total_ms: number; fetch_ms: number; parse_render_ms: number; draw_ms: number; gpu_ms: number; server_ms: number; library_ms: number }

export class RodsWorkspace implements MountedWorkspace {
  readonly api: RodsApi;
  /** The last preview the server answered, the document it is of, and its joints' node indices. */
  preview: Preview | null = null;
  previewDoc: RodsDesign | null = null;
  kept: number[] = [];
  /** The preview was refused (400): the reason, shown until the next good preview. */
  previewError: string | null = null;
  /** A document shown while dragging (a gizmo, a slider): committed as one command on release. */
  draft: RodsDesign | null = null;
  /** Selected nodes in the order they were picked, and selected rods. */
  sel = { nodes: [] as number[], rods: [] as number[] };
  tool: Tool = 'select';
  gizmoMode: 'translate' | 'rotate' | 'scale' = 'translate';
  grid = 10;
  axisSnap = true;
  connectOnAdd = true;
  workZ = 0;
  ramp = false;
  /** Joint numbers drawn in the view (the names the checks and the cut list use). */
  showNumbers = true;
  timings: EditTiming[] = [];
  readonly panels: Panels;
  readonly assembler: Assembler;
  readonly transform: TransformControls;
  private pivot = new THREE.Object3D();
  private dragStart: { positions: Map<number, Vec3>; pivot: THREE.Vector3; quat: THREE.Quaternion } | null = null;
  private inflight = false;
  private queued: RodsDesign | null = null;
  private lastYaml = '';
  private down: { x: number; y: number; shift: boolean } | null = null;
  private boxEl: HTMLElement | null = null;
  private offs: (() => void)[] = [];
  /** Frame everything after the next preview (opened files, not designs built by clicking). */
  private frameNext = true;
  hooks: Record<string, unknown>;

  constructor(readonly ctx: ShellContext<RodsDesign>) {
    this.api = rodsApi(ctx.server);
    const scene = ctx.scene;
    this.transform = new TransformControls(scene.camera, scene.renderer.domElement);
    this.transform.setSize(0.8);
    scene.scene.add(this.pivot, this.transform.getHelper());
    // the gizmo says 'change' for every property it sets (mode, object, axis...): one frame for all
    this.transform.addEventListener('change', () => this.renderSoon());
    this.transform.addEventListener('dragging-changed', (e) => this.onGizmoDragging(!!(e as any).value));
    this.transform.addEventListener('objectChange', () => this.onGizmoChange());
    this.assembler = new Assembler(this);
    this.panels = new Panels(this);
    this.assembler.renderPanel();
    this.setSnapping();
    ctx.toolbarButton('run', 'Build', 'build', 'Make it: build the exact joints (booleans on the server), the 3MF, the cut plan and the assembly guide', () => void this.panels.build(), { primary: true });
    this.offs.push(ctx.history.onChange((_d, label) => {
      this.draft = null;
      this.pruneSelection();
      if (label.startsWith('open') || label === 'new design' || label.startsWith('import')) { this.frameNext = true; this.assembler.stop(); }
      this.panels.render();
      this.panels.renderMake();
      this.requestPreview(this.doc);
    }));
    scene.onPick = (piece, object) => this.onPick(piece ?? object);
    scene.onHover = (key, x, y) => this.panels.hover(key, x, y);
    const canvas = scene.renderer.domElement;
    const down = (e: PointerEvent) => this.onPointerDown(e);
    const move = (e: PointerEvent) => this.onPointerMove(e);
    const up = (e: PointerEvent) => this.onPointerUp(e);
    canvas.addEventListener('pointerdown', down, true);
    window.addEventListener('pointermove', move);
    window.addEventListener('pointerup', up);
    const keys = (e: KeyboardEvent) => this.onKey(e);
    document.addEventListener('keydown', keys);
    const syncCamera = () => { if (this.transform.camera !== scene.camera) { this.transform.camera = scene.camera; } };
    scene.onRender.push(syncCamera);
    this.offs.push(() => {
      canvas.removeEventListener('pointerdown', down, true);
      window.removeEventListener('pointermove', move);
      window.removeEventListener('pointerup', up);
      document.removeEventListener('keydown', keys);
      scene.onRender = scene.onRender.filter((f) => f !== syncCamera);
    });
    this.legend();
    this.hooks = {
      designYaml: () => rodsToYaml(this.doc),
      preview: () => this.preview,
      previewError: () => this.previewError,
      selection: () => ({ nodes: [...this.sel.nodes], rods: [...this.sel.rods] }),
      /** Client coordinates of a world point (mm). */
      screenOf: (p: Vec3) => this.screenOf(p),
      /** Client coordinates of a point on the gizmo's handle for `axis` ('X', 'Y', 'Z'), or null. */
      gizmoHandle: (axis: string) => this.gizmoHandle(axis),
      /** The gizmo handle under the pointer ('X', 'XY', ...) or null. */
      gizmoAxis: () => this.transform.axis,
      styleOf: (key: string) => {
        const m = scene.pieces.get(key); if (!m) return null;
        return { color: (m.material as THREE.MeshStandardMaterial).color.getHex(), visible: m.visible };
      },
      /** Client coordinates where a click picks the joint or rod `key` (along a rod's axis, at a joint's node), or null. */
      pointOf: (key: string) => this.pointOf(key),
      timeEdits: (n: number) => this.timeEdits(n),
      /** Median time (ms) of drawing the view once, waiting for the GPU. */
      timeRender: (n: number) => {
        const gl = scene.renderer.getContext();
        const ts: number[] = [];
        for (let k = 0; k < n; ++k) {
          const t0 = performance.now();
          scene.render();
          gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
          ts.push(performance.now() - t0);
        }
        ts.sort((a, b) => a - b);
        return ts[Math.floor(n / 2)];
      },
      assembly: () => this.assembler.state(),
      guideHtml: () => this.assembler.guideHtml(),
      buildJob: () => this.panels.job,
    };
    this.frameNext = this.doc.edges.length > 0;
    this.requestPreview(this.doc);
  }

  /** The document shown: a drag's draft, else the history's current one. */
  get doc(): RodsDesign { return this.draft ?? this.ctx.history.current; }

  unmount(): void {
    for (const off of this.offs) off();
    this.transform.detach();
    this.ctx.scene.scene.remove(this.pivot, this.transform.getHelper());
    this.transform.dispose();
    this.assembler.stop();
    this.ctx.scene.onPick = () => {};
    this.ctx.scene.onHover = () => {};
    this.ctx.scene.controls.enabled = true;
    this.boxEl?.remove();
  }

  // ---------------------------------------------------------------- shell interface
  describeSelection(_s: SelectionState): string {
    const d = this.doc;
    const { nodes, rods } = this.sel;
    if (!nodes.length && !rods.length) return this.tool === 'add' ? 'Add node: click the floor grid (or a joint to start from it)' : 'Nothing selected';
    const parts: string[] = [];
    if (nodes.length === 1) { const p = d.nodes[nodes[0]]; parts.push(`${jointName(d, nodes[0])} at ${p.map((x) => x.toFixed(1)).join(', ')} mm`); }
    else if (nodes.length) parts.push(`${nodes.length} joints (${nodes.map((i) => jointName(d, i).slice(6)).join(', ')})`);
    if (rods.length === 1) {
      const r = this.previewRod(rods[0]);
      parts.push(`${rodName(d, rods[0])}${r ? `: cut ${r.length.toFixed(1)} mm` : ''}`);
    } else if (rods.length) parts.push(`${rods.length} rods`);
    return `Selected: ${parts.join('; ')}`;
  }
  exists(object: string): boolean {
    const k = parseKey(object); if (!k) return false;
    return k.kind === 'joint' ? k.index < this.doc.nodes.length : k.index < this.doc.edges.length;
  }
  deleteSelection(): void { this.deleteSelected(); }
  cancel(): boolean {
    if (this.assembler.active) { this.assembler.stop(); return true; }
    if (this.tool !== 'select') { this.setTool('select'); return true; }
    if (this.sel.nodes.length || this.sel.rods.length) { this.select([], []); return true; }
    return false;
  }

  // ---------------------------------------------------------------- preview round trips
  /** Asks the server for the preview of `doc`; one request at a time, the newest state wins. */
  requestPreview(doc: RodsDesign): void {
    this.queued = doc;
    // while dragging, the skeleton follows at once (one frame before the server answers)
    this.drawSkeleton(this.draft !== null);
    if (!this.inflight) void this.ctx.track(this.pump());
  }
  private async pump(): Promise<void> {
    this.inflight = true;
    try {
      while (this.queued) { const d = this.queued; this.queued = null; await this.runPreview(d); }
    } finally { this.inflight = false; }
  }
  private async runPreview(doc: RodsDesign): Promise<void> {
    const { yaml, kept } = postable(doc);
    if (!doc.edges.length) {
      this.preview = null; this.previewDoc = doc; this.kept = []; this.lastYaml = ''; this.previewError = null;
      this.ctx.message('');
      this.draw(); this.panels.renderChecks();
      return;
    }
    if (yaml === this.lastYaml && this.preview) { this.previewDoc = doc; this.kept = kept; this.draw(); return; }
    const t0 = performance.now();
    try {
      const p = await this.api.preview(yaml);
      const t1 = performance.now();
      this.preview = p; this.previewDoc = doc; this.kept = kept; this.lastYaml = yaml;
      if (this.previewError) this.ctx.message('');
      this.previewError = null;
      this.draw();
      const tDraw = performance.now();
      if (this.syncTimings) { // wait for the GPU to finish drawing (timings only: it stalls the pipeline)
        const gl = this.ctx.scene.renderer.getContext();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      }
      const t2 = performance.now();
      this.timings.push({ total_ms: t2 - t0, fetch_ms: t1 - t0, parse_render_ms: t2 - t1, draw_ms: tDraw - t1, gpu_ms: t2 - tDraw, server_ms: p.timings.server_ms, library_ms: p.timings.library_ms });
      if (this.timings.length > 200) this.timings.shift();
      if (this.frameNext) { this.frameNext = false; this.ctx.scene.frameAll(); } else this.ctx.scene.keepInView();
      this.panels.renderChecks();
      if (!this.assembler.active) this.assembler.renderPanel();
      this.ctx.refreshSelectionLabel();
    } catch (e) {
      if (!(e instanceof ApiError)) throw e;
      this.previewError = e.message;
      this.lastYaml = '';
      this.ctx.message(`The library cannot make this design: ${e.message}. The view shows the last state it could make; fix it or undo.`);
      this.panels.renderChecks();
    }
  }

  /** Applies `n` small moves one after another and times each round trip (tests, docs/benchmarks.md). */
  private syncTimings = false;
  private async timeEdits(n: number): Promise<EditTiming[]> {
    this.syncTimings = true;
    const start = this.timings.length;
    for (let k = 0; k < n; ++k) {
      const d = this.doc;
      const i = d.nodes.length - 1;
      const p = d.nodes[i];
      this.ctx.history.apply(moveNodes(d, new Map([[i, [p[0] + (k % 2 ? -1 : 1), p[1], p[2]] as Vec3]])), 'move (timing)');
      while (this.inflight || this.queued) await new Promise((r) => setTimeout(r, 1));
    }
    this.syncTimings = false;
    return this.timings.slice(start);
  }

  previewRod(e: number) { return this.preview && this.previewDoc === this.doc ? this.preview.rods[e] : this.preview?.rods[e]; }
  /** The preview joint of a document node (none for isolated nodes). */
  previewJoint(i: number) { const k = this.kept.indexOf(i); return k >= 0 ? this.preview?.joints[k] ?? null : null; }
  /** Findings that name a rod or joint (document indices). */
  findingsOf(key: string): Finding[] {
    const k = parseKey(key); if (!k || !this.preview) return [];
    const pk = k.kind === 'joint' ? this.kept.indexOf(k.index) : k.index;
    return this.preview.findings.filter((f) => f.severity === 'error' && (k.kind === 'joint' ? f.joints.includes(pk) : f.rods.includes(pk)));
  }

  // ---------------------------------------------------------------- drawing
  legend(): void {
    if (this.ramp) {
      this.ctx.scene.setLegend([0, 0.25, 0.5, 0.75, 1].map((u) => ({ color: rampColor(u), label: u === 1 ? 'utilisation ≥ 1 (fails)' : `utilisation ${u.toFixed(2)}` })));
      return;
    }
    this.ctx.scene.setLegend([
      { color: JOINT_COLOR, label: 'joint (printed)' },
      { color: ROD_COLOR, label: 'rod (cut)' },
      { color: 0xff0000, label: 'failing check', title: 'collisions, swallowed or short rods, tipping: hover for the reason' },
      { color: 0x2e9e44, label: 'centre of mass / support', title: 'red when the design would tip over' },
      { color: 0xff9800, label: 'selected' },
      { color: 0x2f6fff, label: 'under the pointer' },
    ]);
  }

  /** Draws the preview (joints white, rods wood-brown, red where a check fails) and the checks. */
  draw(): void {
    const scene = this.ctx.scene;
    scene.clearLayer('rods-checks');
    scene.clearLayer('rods-free');
    scene.clearStates();
    const doc = this.doc;
    const p = this.preview;
    const flat = (color: number) => new THREE.MeshStandardMaterial({ color, roughness: 0.75, metalness: 0, flatShading: true });
    // What to draw, by key; meshes whose geometry did not change are kept as they are (an edit
    // touches the joints and rods around what moved, and uploading only those keeps drags smooth).
    const want = new Map<string, { layer: string; mesh: MeshData; color: number }>();
    if (p && this.previewDoc) {
      p.joints.forEach((j, k) => {
        const i = this.kept[k];
        if (i !== undefined && i < doc.nodes.length) want.set(jointKey(i), { layer: 'rods-joints', mesh: j.mesh, color: JOINT_COLOR });
      });
      p.rods.forEach((r, e) => {
        if (e >= doc.edges.length) return;
        want.set(rodKey(e), { layer: 'rods-rods', mesh: r.mesh, color: this.ramp && r.utilisation !== undefined ? rampColor(r.utilisation) : ROD_COLOR });
      });
    }
    let removed = false;
    for (const [key, d] of this.drawn) {
      if (want.get(key)?.layer === d.layer) continue;
      scene.layer(d.layer).remove(d.mesh);
      d.mesh.geometry.dispose();
      this.drawn.delete(key);
      removed = true;
    }
    let reshaped = removed;
    for (const [key, w] of want) {
      const d = this.drawn.get(key);
      if (!d) {
        const mesh = new THREE.Mesh(geometryOf(w.mesh), flat(w.color));
        scene.layer(w.layer).add(mesh);
        scene.pickable(mesh, key, key, w.color);
        this.drawn.set(key, { layer: w.layer, mesh, data: w.mesh });
        continue;
      }
      d.mesh.userData.color = w.color;
      if (!sameMesh(d.data, w.mesh)) {
        const g = geometryOf(w.mesh);
        d.mesh.geometry.dispose();
        d.mesh.geometry = g;
        for (const c of d.mesh.children) if ((c as THREE.Mesh).isMesh) (c as THREE.Mesh).geometry = g; // its outline
        d.data = w.mesh;
        reshaped = true;
      }
    }
    // forgets removed pickables and lets the floor follow the new shape (clearLayer does both)
    if (reshaped) { scene.layer('rods-scratch'); scene.clearLayer('rods-scratch'); }
    if (p && this.previewDoc && !this.assembler.active) this.drawChecks(p);
    // nodes no rod touches yet: a white ball to pick and connect from
    const iso = isolatedNodes(doc);
    const ball = Math.max(doc.rod.radius + doc.joint.wall, 4);
    for (const i of iso) {
      const mesh = new THREE.Mesh(new THREE.SphereGeometry(ball, 16, 12), flat(JOINT_COLOR));
      mesh.position.set(...doc.nodes[i]);
      scene.layer('rods-free').add(mesh);
      scene.pickable(mesh, jointKey(i), jointKey(i), JOINT_COLOR);
    }
    this.drawNumbers();
    this.drawSkeleton(false);
    this.styleSelection(); // renders once
    this.assembler.redraw();
  }
  private drawn = new Map<string, { layer: string; mesh: THREE.Mesh; data: MeshData }>();

  private drawChecks(p: Preview): void {
    const scene = this.ctx.scene;
    const layer = scene.layer('rods-checks');
    const r = p.parameters.radius;
    const red = new THREE.MeshBasicMaterial({ color: 0xff0000, transparent: true, opacity: 0.45, depthTest: false });
    for (const x of p.intersections) {
      const s = new THREE.Mesh(new THREE.SphereGeometry(Math.max(2 * r, 3), 16, 12), red);
      s.position.set(...x.point);
      s.renderOrder = 5;
      layer.add(s);
      scene.addLabel('rods-checks', new THREE.Vector3(...x.point), `${p.rods[x.rods[0]].name} × ${p.rods[x.rods[1]].name}: ${(-x.clearance).toFixed(1)} mm overlap`,
        { class: 'failure-tag', 'data-testid': 'collision-label' });
    }
    const b = p.balance;
    if (b.checked && b.support_polygon.length) {
      const color = b.stands ? 0x2e9e44 : 0xff0000;
      const z = b.ground_z + 0.5;
      const pts = b.support_polygon.map(([x, y]) => new THREE.Vector3(x, y, z));
      if (pts.length > 2) pts.push(pts[0].clone());
      const poly = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts), new THREE.LineBasicMaterial({ color }));
      poly.name = 'support-polygon';
      layer.add(poly);
      if (pts.length > 2) {
        const shape = new THREE.Shape(b.support_polygon.map(([x, y]) => new THREE.Vector2(x, y)));
        const fill = new THREE.Mesh(new THREE.ShapeGeometry(shape), new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.12, side: THREE.DoubleSide, depthWrite: false }));
        fill.position.z = z;
        layer.add(fill);
      }
      const c = new THREE.Vector3(...b.center_of_mass);
      const com = new THREE.Mesh(new THREE.SphereGeometry(Math.max(4, r * 1.5), 16, 12), new THREE.MeshBasicMaterial({ color, depthTest: false }));
      com.position.copy(c); com.renderOrder = 6; com.name = 'center-of-mass';
      layer.add(com);
      const drop = new THREE.Line(new THREE.BufferGeometry().setFromPoints([c, new THREE.Vector3(c.x, c.y, z)]), new THREE.LineDashedMaterial({ color, dashSize: 6, gapSize: 4 }));
      drop.computeLineDistances();
      layer.add(drop);
      const foot = new THREE.Mesh(new THREE.RingGeometry(3, 5, 20), new THREE.MeshBasicMaterial({ color, side: THREE.DoubleSide }));
      foot.position.set(c.x, c.y, z);
      layer.add(foot);
      scene.addLabel('rods-checks', new THREE.Vector3(c.x, c.y, z), b.stands ? `stands: margin ${b.margin.toFixed(1)} mm` : `tips over: ${(-b.margin).toFixed(1)} mm outside`,
        { class: b.stands ? 'ok' : 'failure-tag', 'data-testid': 'balance-label' });
    }
  }

  /** The joints' numbers (their engraved IDs), next to each joint. */
  drawNumbers(): void {
    const scene = this.ctx.scene;
    scene.layer('rods-numbers'); // (clearLayer removes a layer's labels only once the layer exists)
    scene.clearLayer('rods-numbers');
    if (!this.showNumbers || this.assembler.active) return;
    const d = this.doc;
    d.nodes.forEach((p, i) => scene.addLabel('rods-numbers', new THREE.Vector3(...p), jointLabel(d, i), { class: 'rods-id', 'data-testid': `joint-number-${i + 1}` }));
  }

  /** Thin lines along the edges of the document shown: they follow a drag before the server answers. */
  drawSkeleton(render = true): void {
    const scene = this.ctx.scene;
    scene.clearLayer('rods-skeleton');
    const d = this.doc;
    if (!d.edges.length) { if (render) this.renderSoon(); return; }
    const pts: number[] = [];
    for (const [a, b] of d.edges) pts.push(...d.nodes[a], ...d.nodes[b]);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
    const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: SKELETON_COLOR, transparent: true, opacity: 0.7 }));
    lines.raycast = () => {};
    scene.layer('rods-skeleton').add(lines);
    if (render) this.renderSoon(); // a drag moves the pointer more often than frames are drawn
  }

  /** Selection states, the gizmo on the selected nodes, the panels. */
  styleSelection(): void {
    const scene = this.ctx.scene;
    const bad = (k: string) => {
      const q = parseKey(k)!;
      if (q.kind === 'joint') return !!this.previewJoint(q.index)?.red;
      return !this.ramp && !!this.preview?.rods[q.index]?.red;
    };
    for (const key of scene.pieces.keys()) scene.setState(key, { bad: bad(key) });
    for (const i of this.sel.nodes) scene.setState(jointKey(i), { selected: true, bad: bad(jointKey(i)) });
    for (const e of this.sel.rods) scene.setState(rodKey(e), { selected: true, bad: bad(rodKey(e)) });
    scene.selectedObject = null;
    this.placeGizmo();
    scene.restyle();
  }

  // ---------------------------------------------------------------- selection and tools
  select(nodes: number[], rods: number[]): void {
    this.sel = { nodes: [...new Set(nodes)], rods: [...new Set(rods)] };
    const first = nodes.length ? jointKey(nodes[nodes.length - 1]) : rods.length ? rodKey(rods[rods.length - 1]) : null;
    this.ctx.selection.set(first, first);
    this.styleSelection();
    this.panels.renderSelection();
    this.ctx.refreshSelectionLabel();
  }
  private pruneSelection(): void {
    const d = this.ctx.history.current;
    this.sel.nodes = this.sel.nodes.filter((i) => i < d.nodes.length);
    this.sel.rods = this.sel.rods.filter((e) => e < d.edges.length);
  }

  setTool(t: Tool): void {
    this.tool = t;
    this.ctx.scene.controls.enabled = t !== 'box';
    this.panels.renderTools();
    this.placeGizmo();
    this.ctx.refreshSelectionLabel();
  }
  setGizmoMode(m: 'translate' | 'rotate' | 'scale'): void { this.gizmoMode = m; this.transform.setMode(m); this.panels.renderTools(); this.placeGizmo(); }
  setSnapping(): void {
    this.transform.setTranslationSnap(this.grid > 0 ? this.grid : null);
    this.transform.setRotationSnap(this.grid > 0 ? (15 * Math.PI) / 180 : null);
    this.transform.setScaleSnap(this.grid > 0 ? 0.05 : null);
  }

  private onPick(key: string | null): void {
    if (this.assembler.active || this.transform.dragging || this.transform.axis) return;
    if (this.tool === 'box') return;
    const shift = !!this.down?.shift;
    const k = parseKey(key);
    if (this.tool === 'add' && !k) { this.addAtPointer(); return; }
    if (!k) { if (!shift) this.select([], []); return; }
    if (shift) {
      const nodes = [...this.sel.nodes], rods = [...this.sel.rods];
      const list = k.kind === 'joint' ? nodes : rods;
      const at = list.indexOf(k.index);
      if (at >= 0) list.splice(at, 1); else list.push(k.index);
      this.select(nodes, rods);
    } else if (k.kind === 'joint') this.select([k.index], []);
    else this.select([], [k.index]);
  }

  /** The floor point (z = work plane) under the last pointer press, snapped to the grid. */
  private floorPoint(x: number, y: number): Vec3 | null {
    const scene = this.ctx.scene;
    const r = scene.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, scene.camera);
    const hit = ray.ray.intersectPlane(new THREE.Plane(new THREE.Vector3(0, 0, 1), -this.workZ), new THREE.Vector3());
    if (!hit) return null;
    return [snap(hit.x, this.grid), snap(hit.y, this.grid), this.workZ];
  }

  private addAtPointer(): void {
    if (!this.down) return;
    let p = this.floorPoint(this.down.x, this.down.y);
    if (!p) { this.ctx.message('Click the floor grid to add a node (the view looks away from the work plane).', 'info'); return; }
    const d = this.doc;
    const from = this.connectOnAdd ? this.sel.nodes.filter((i) => i < d.nodes.length) : [];
    if (from.length === 1 && this.axisSnap) p = snapToAxis(p, d.nodes[from[0]], 8);
    if (d.nodes.some((q) => Math.hypot(q[0] - p![0], q[1] - p![1], q[2] - p![2]) < 0.5)) { this.ctx.message('There is a node there already: pick it instead (click it).', 'info'); return; }
    const next = addNode(d, p, from);
    const i = next.nodes.length - 1;
    this.sel = { nodes: [i], rods: [] };
    this.ctx.history.apply(next, from.length ? `add ${jointName(next, i)} connected to ${from.map((j) => jointName(next, j)).join(', ')}` : `add ${jointName(next, i)}`);
    this.select([i], []);
  }

  connectSelected(): void {
    const n = this.sel.nodes;
    if (n.length < 2) { this.ctx.message('Select two joints (click one, shift-click the other), then Connect.', 'info'); return; }
    const d = this.doc;
    const [from, ...to] = n;
    const fresh = to.filter((j) => !d.edges.some(([a, b]) => (a === from && b === j) || (a === j && b === from)));
    if (!fresh.length) { this.ctx.message(`${jointName(d, from)} is already connected to ${to.map((j) => jointName(d, j)).join(', ')}.`, 'info'); return; }
    const next = connect(d, from, fresh);
    this.ctx.history.apply(next, `connect ${jointName(d, from)} to ${fresh.map((j) => jointName(d, j)).join(', ')}`);
    this.select(n, []);
  }

  splitSelected(): void {
    if (!this.sel.rods.length) { this.ctx.message('Select a rod (click it), then Split.', 'info'); return; }
    const e = Math.max(...this.sel.rods);
    const d = this.doc;
    const next = splitRod(d, e);
    const m = next.nodes.length - 1;
    this.ctx.history.apply(next, `split ${rodName(d, e)} by ${jointName(next, m)}`);
    this.select([m], []);
  }

  deleteSelected(): void {
    const { nodes, rods } = this.sel;
    if (!nodes.length && !rods.length) return;
    const d = this.doc;
    const what = [...nodes.map((i) => jointName(d, i)), ...rods.map((e) => rodName(d, e))];
    const next = deleteParts(d, nodes, rods);
    this.sel = { nodes: [], rods: [] };
    this.ctx.history.apply(next, `delete ${what.length > 3 ? `${what.length} parts` : what.join(', ')}`);
    this.select([], []);
  }

  /** Sets node positions from the panel's fields (one node, or the selection's centre). */
  moveSelectionTo(c: Vec3): void {
    const d = this.doc;
    const n = this.sel.nodes; if (!n.length) return;
    const c0 = centroid(n.map((i) => d.nodes[i]));
    const delta = [c[0] - c0[0], c[1] - c0[1], c[2] - c0[2]];
    if (delta.every((x) => Math.abs(x) < 1e-9)) return; // nothing moves: no command
    const pos = new Map(n.map((i) => [i, d.nodes[i].map((x, k) => x + delta[k]) as Vec3]));
    this.ctx.history.apply(moveNodes(d, pos), `move ${n.length === 1 ? jointName(d, n[0]) : `${n.length} joints`} to ${c.map((x) => x.toFixed(1)).join(', ')}`);
  }

  /** Changes parameters while dragging a slider (draft) or for good (`commit` with a label). */
  setParams(update: (d: RodsDesign) => void, label: string | null): void {
    const next = JSON.parse(JSON.stringify(this.ctx.history.current)) as RodsDesign;
    update(next);
    if (label === null) { this.draft = next; this.requestPreview(next); return; }
    this.draft = null;
    if (JSON.stringify(next) === JSON.stringify(this.ctx.history.current)) { this.requestPreview(next); return; } // unchanged: no command
    this.ctx.history.apply(next, label);
  }

  // ---------------------------------------------------------------- gizmo
  private placeGizmo(): void {
    const n = this.sel.nodes.filter((i) => i < this.doc.nodes.length);
    if (!n.length || this.tool !== 'select' || this.assembler.active) { this.transform.detach(); this.renderSoon(); return; }
    if (this.transform.dragging) return;
    const c = centroid(n.map((i) => this.doc.nodes[i]));
    this.pivot.position.set(...c);
    this.pivot.quaternion.identity();
    this.pivot.scale.set(1, 1, 1);
    this.pivot.updateMatrixWorld();
    this.transform.setMode(n.length === 1 && this.gizmoMode !== 'translate' ? 'translate' : this.gizmoMode);
    this.transform.attach(this.pivot);
    this.renderSoon();
  }

  private renderPending = false;
  /** Renders at the next animation frame (however many changes come before it). */
  renderSoon(): void {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => { this.renderPending = false; this.ctx.scene.render(); });
  }

  private onGizmoDragging(dragging: boolean): void {
    const scene = this.ctx.scene;
    scene.controls.enabled = !dragging && this.tool !== 'box';
    if (dragging) {
      const d = this.ctx.history.current;
      this.dragStart = { positions: new Map(this.sel.nodes.map((i) => [i, d.nodes[i]])), pivot: this.pivot.position.clone(), quat: this.pivot.quaternion.clone() };
      return;
    }
    const start = this.dragStart; this.dragStart = null;
    const draft = this.draft;
    if (!start || !draft) { this.placeGizmo(); return; }
    const d = this.ctx.history.current;
    const moved = [...start.positions.keys()].some((i) => draft.nodes[i].some((x, k) => Math.abs(x - d.nodes[i][k]) > 1e-9));
    this.draft = null;
    if (!moved) { this.placeGizmo(); return; }
    const verb = this.transform.mode === 'translate' ? 'move' : this.transform.mode === 'rotate' ? 'rotate' : 'scale';
    const n = [...start.positions.keys()];
    this.ctx.history.apply(draft, `${verb} ${n.length === 1 ? jointName(d, n[0]) : `${n.length} joints`}`);
    this.placeGizmo();
  }

  private onGizmoChange(): void {
    const s = this.dragStart; if (!s) return;
    const d = this.ctx.history.current;
    const pos = new Map<number, Vec3>();
    const c = s.pivot;
    const mode = this.transform.mode;
    const dq = this.pivot.quaternion.clone().multiply(s.quat.clone().invert());
    for (const [i, p0] of s.positions) {
      const v = new THREE.Vector3(...p0);
      if (mode === 'translate') v.add(this.pivot.position.clone().sub(c));
      else if (mode === 'rotate') v.sub(c).applyQuaternion(dq).add(c);
      else v.sub(c).multiply(this.pivot.scale).add(c);
      let p: Vec3 = [v.x, v.y, v.z].map((x) => Math.round(x * 1e4) / 1e4) as Vec3;
      if (mode === 'translate' && s.positions.size === 1 && this.axisSnap) {
        // snap the rod to the neighbour it is closest to aligning with an axis
        for (const [a, b] of d.edges) {
          const j = a === i ? b : b === i ? a : -1;
          if (j < 0) continue;
          const q = snapToAxis(p, d.nodes[j], 3);
          if (q !== p) { p = q; break; }
        }
      }
      pos.set(i, p);
    }
    this.draft = moveNodes(d, pos);
    this.requestPreview(this.draft);
    this.panels.renderSelection();
  }

  private gizmoHandle(axis: string): { x: number; y: number } | null {
    if (!this.transform.object) return null;
    const helper = this.transform.getHelper();
    helper.updateMatrixWorld(true);
    // the gizmo's invisible picking handles for the current mode (three's TransformControlsGizmo)
    const pickers = (this.transform as any)._gizmo?.picker?.[this.transform.mode] as THREE.Object3D | undefined;
    const found = pickers?.children.find((o) => o.name === axis) ?? null;
    if (!found) return null;
    if (this.transform.mode === 'rotate' && (found as THREE.Mesh).geometry?.getAttribute('position')) {
      // a point on the ring's centre line 45° from the other rings' axes (which can cover the
      // ring where they cross it): between the torus' outer and inner vertex at that angle
      const pos = (found as THREE.Mesh).geometry.getAttribute('position');
      const outer = new THREE.Vector3().fromBufferAttribute(pos, 3), inner = new THREE.Vector3().fromBufferAttribute(pos, Math.min(pos.count - 1, 53));
      const v = outer.add(inner).multiplyScalar(0.5).applyMatrix4(found.matrixWorld);
      return this.screenOf([v.x, v.y, v.z]);
    }
    const box = new THREE.Box3().setFromObject(found, true);
    const c = box.getCenter(new THREE.Vector3());
    return this.screenOf([c.x, c.y, c.z]);
  }

  private pointOf(key: string): { x: number; y: number } | null {
    const k = parseKey(key); if (!k) return null;
    const d = this.doc;
    const tries: Vec3[] = [];
    if (k.kind === 'rod') {
      const [a, b] = d.edges[k.index] ?? [];
      if (a === undefined) return null;
      for (const t of [0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8]) tries.push(d.nodes[a].map((x, i) => x + (d.nodes[b][i] - x) * t) as Vec3);
    } else if (d.nodes[k.index]) tries.push(d.nodes[k.index]);
    // a point whose neighbourhood picks the part too (a ray exactly through a mesh vertex, as
    // at a joint's node, can miss once the event's coordinates are rounded)
    const picks = (x: number, y: number) => [[0, 0], [0.7, 0], [-0.7, 0], [0, 0.7], [0, -0.7]].every(([dx, dy]) => this.ctx.scene.pickAt(x + dx, y + dy).piece === key);
    for (const p of tries) {
      const s = this.screenOf(p);
      for (const [dx, dy] of [[0, 0], [3, 3], [-3, 3], [3, -3], [-3, -3], [6, 0], [0, 6], [-6, 0], [0, -6]]) {
        const x = Math.round(s.x + dx), y = Math.round(s.y + dy);
        if (picks(x, y)) return { x, y };
      }
    }
    return this.ctx.scene.screenPointOf(key);
  }

  screenOf(p: Vec3): { x: number; y: number } {
    const scene = this.ctx.scene;
    const v = new THREE.Vector3(...p).project(scene.camera);
    const r = scene.renderer.domElement.getBoundingClientRect();
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  }

  // ---------------------------------------------------------------- pointer: add, box select
  private onPointerDown(e: PointerEvent): void {
    this.down = { x: e.clientX, y: e.clientY, shift: e.shiftKey };
    if (this.tool === 'box' && e.button === 0 && !this.transform.axis) {
      this.boxEl?.remove();
      this.boxEl = document.createElement('div');
      this.boxEl.className = 'rods-box';
      this.boxEl.dataset.testid = 'box-select';
      document.body.append(this.boxEl);
      this.onPointerMove(e);
    }
  }
  private onPointerMove(e: PointerEvent): void {
    if (!this.boxEl || !this.down) return;
    const x0 = Math.min(this.down.x, e.clientX), y0 = Math.min(this.down.y, e.clientY);
    Object.assign(this.boxEl.style, { left: `${x0}px`, top: `${y0}px`, width: `${Math.abs(e.clientX - this.down.x)}px`, height: `${Math.abs(e.clientY - this.down.y)}px` });
  }
  private onPointerUp(e: PointerEvent): void {
    if (!this.boxEl || !this.down) return;
    this.boxEl.remove(); this.boxEl = null;
    const x0 = Math.min(this.down.x, e.clientX), x1 = Math.max(this.down.x, e.clientX);
    const y0 = Math.min(this.down.y, e.clientY), y1 = Math.max(this.down.y, e.clientY);
    const inside = this.doc.nodes.map((p, i) => ({ i, s: this.screenOf(p) })).filter(({ s }) => s.x >= x0 && s.x <= x1 && s.y >= y0 && s.y <= y1).map(({ i }) => i);
    const d = this.doc;
    const rods = d.edges.map((_e, k) => k).filter((k) => inside.includes(d.edges[k][0]) && inside.includes(d.edges[k][1]));
    if (this.down.shift) this.select([...this.sel.nodes, ...inside], [...this.sel.rods, ...rods]);
    else this.select(inside, rods);
  }

  private onKey(e: KeyboardEvent): void {
    const tag = (e.target as HTMLElement).tagName;
    if (tag === 'INPUT' || tag === 'SELECT' || tag === 'TEXTAREA' || e.ctrlKey || e.metaKey || e.altKey) return;
    if (this.assembler.active) {
      if (e.key === 'ArrowRight' || e.key === 'n' || e.key === ' ') { e.preventDefault(); this.assembler.next(); }
      if (e.key === 'ArrowLeft' || e.key === 'b') { e.preventDefault(); this.assembler.back(); }
      return;
    }
    const k = e.key.toLowerCase();
    if (k === 'a') this.setTool(this.tool === 'add' ? 'select' : 'add');
    else if (k === 'c') this.connectSelected();
    else if (k === 's') this.splitSelected();
    else if (k === 'g') this.setGizmoMode('translate');
    else if (k === 'r') this.setGizmoMode('rotate');
    else if (k === 'x') this.setGizmoMode('scale');
  }
}

function sameMesh(a: MeshData, b: MeshData): boolean {
  if (a === b) return true;
  if (a.vertices.length !== b.vertices.length || a.faces.length !== b.faces.length) return false;
  for (let i = 0; i < a.vertices.length; ++i) if (a.vertices[i] !== b.vertices[i]) return false;
  for (let i = 0; i < a.faces.length; ++i) if (a.faces[i] !== b.faces[i]) return false;
  return true;
}

export function centroid(ps: Vec3[]): Vec3 {
  const c: Vec3 = [0, 0, 0];
  for (const p of ps) for (let k = 0; k < 3; ++k) c[k] += p[k] / ps.length;
  return c;
}
