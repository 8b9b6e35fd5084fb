// The Flat-pack workspace: its state (component registry, the last assembled model, the picked
// edge), its commands (add, set, connect, delete) and its scene layers (pieces with their joints
// cut, pickable edges, joint markers, warnings beside the pieces). Panels are in ./panels.ts.
import * as THREE from 'three';
import { flatpackApi } from './api';
import type { Assembly, ComponentInfo, ComponentTypeInfo, FlatpackApi, FpDiagnostic } from './api';
import { JOINT_COLORS, clone, freshComponentName, removeComponent, splitRef } from './model';
import type { FpComponent, FpConnection, FpDesign, Num } from './model';
import { designToYaml } from './yamlio';
import { geometryOf } from '../../shell/scene';
import { ApiError, isAbort } from '../../shell/server';
import type { SelectionState } from '../../shell/selection';
import type { MountedWorkspace, ShellContext } from '../../shell/workspace';
import { download } from '../../shell/ui';
import { fileStem } from '../../shell/shell';
import { Panels } from './panels';

/** Starting sizes of a component added from the library (mm; counts for n). */
export const START_VALUES: Record<string, Record<string, number>> = {
  Rectangle: { l: 100, w: 60 }, Square: { l: 80 }, RightTriangle: { w: 80, h: 60 }, IsoscelesTriangle: { w: 80, h: 60 },
  Trapezoid: { b: 100, t: 60, h: 50, o: 20 }, RegularPolygon: { n: 6, s: 50 }, LShape: { l: 100, w: 80, a: 40, b: 40 },
  UShape: { l: 100, w: 60, nl: 40, nw: 20 }, Disc: { d: 100 },
};

const WOOD = [0xe2c08d, 0xd6ad72, 0xeacb9b, 0xcfa468];
const EDGE = 0x6d8fb3;

export class FlatpackWorkspace implements MountedWorkspace {
  readonly api: FlatpackApi;
  types: ComponentTypeInfo[] = [];
  typeByName = new Map<string, ComponentTypeInfo>();
  /** The last assembled model (of the current document, or of a preview while a slider moves). */
  asm: Assembly | null = null;
  /** Why the last assembly failed to come back (the design could not be read). */
  readError: ApiError | null = null;
  /** The first edge picked for a connection ("A.t"). */
  pick: string | null = null;
  /** 0 … 1: how far the pieces are pulled apart from the model's centre. */
  explode = 0;
  /** Milliseconds from an edit to the redrawn model and sheets, newest last. */
  roundTrips: number[] = [];
  /** Where each round trip's time went (ms): before sending, the request, drawing the view, the panels. */
  stages: { before: number; server: number; draw: number; panels: number }[] = [];
  private seq = 0;
  private abort: AbortController | null = null;
  readonly panels: Panels;
  private offs: (() => void)[] = [];
  hooks: Record<string, unknown>;

  constructor(readonly ctx: ShellContext<FpDesign>) {
    this.api = flatpackApi(ctx.server);
    this.explode = ctx.store.get<number>('explode') ?? 0;
    this.panels = new Panels(this);
    const files: [string, string, string][] = [
      ['SVG', 'download-svg', 'Download the cut sheets as SVG (mm; cut red, engrave blue), one file per sheet'],
      ['DXF', 'download-dxf', 'Download the cut sheets as DXF (mm; layers CUT and LABELS), one file per sheet'],
      ['STL', 'download-stl', 'Download the assembled 3D model as STL (each board with its joints, one closed shell per piece)'],
      ['.glb', 'download-glb', 'Download the assembled 3D model as binary glTF'],
      ['Report', 'download-report', 'Download report.json: pieces, joints by kind, automatic joints, warnings, sheet usage, assembly order'],
    ];
    for (const [text, id, title] of files) ctx.toolbarButton('file', text, id, title, () => void ctx.track(this.downloadKind(id.slice(9))));
    this.offs.push(ctx.history.onChange((_d, label) => {
      // a new design, or a new component (laid beside the others, maybe out of view): frame all
      if (label.startsWith('open') || label.startsWith('new') || label.startsWith('add ')) this.framed = false;
      this.cancelPick();
      void ctx.track(this.refresh(performance.now()));
    }));
    ctx.scene.setLegend([
      { color: WOOD[0], label: 'board (joints cut)' },
      { color: EDGE, label: 'edge (click two to connect)' },
      { color: JOINT_COLORS['finger-finger'], label: 'finger–finger joint' },
      { color: JOINT_COLORS['finger-hole'], label: 'finger–hole joint' },
      { color: JOINT_COLORS['slot-slot'], label: 'slot–slot joint' },
      { color: 0xffffff, label: '“auto”: joint no connection asked for', title: 'found where two boards cross (paper Alg. 2)' },
      { color: 0xff0000, label: 'not placed / error' },
      { color: 0xff9800, label: 'selected / picked' },
    ]);
    ctx.scene.onPick = (piece, object) => this.onPick(piece, object);
    ctx.scene.onHover = (key, x, y) => { this.panels.hover(key); this.tooltip(key, x, y); };
    this.hooks = {
      designYaml: () => designToYaml(this.design),
      assembly: () => this.asm,
      roundTrips: () => [...this.roundTrips],
      roundTripStages: () => [...this.stages],
      edgeKeys: () => [...ctx.scene.pieces.keys()],
      styleOf: (key: string) => ctx.scene.styleOf(key),
      /** What a click at client coordinates would pick. */
      pickAt: (x: number, y: number) => ctx.scene.pickAt(x, y),
      pick: () => this.pick,
      /** Client coordinates of a point on the axis of an edge's rod that a click there picks, or null. */
      edgePoint: (key: string) => this.edgePoint(key),
    };
    void ctx.track(this.load());
  }

  get design(): FpDesign { return this.ctx.history.current; }

  private async load(): Promise<void> {
    this.ctx.status('loading components…');
    try {
      this.types = await this.api.components();
    } catch (e) { this.ctx.message(`cannot load the component library: ${(e as Error).message}`); }
    for (const t of this.types) this.typeByName.set(t.name, t);
    this.ctx.status('');
    this.panels.buildLibrary();
    await this.refresh(performance.now());
  }

  unmount(): void {
    for (const off of this.offs) off();
    this.abort?.abort();
    this.ctx.scene.onPick = () => {};
    this.ctx.scene.onHover = () => {};
  }

  // ---------------------------------------------------------------- assembling
  /**
   * Assembles `doc` (the current document unless a preview is given) on the server and redraws.
   * Newer requests win: an answer that arrives after a newer request was sent is dropped.
   */
  async refresh(t0: number, doc: FpDesign = this.design): Promise<void> {
    const seq = ++this.seq;
    this.abort?.abort();
    const abort = new AbortController();
    this.abort = abort;
    if (!doc.components.length) {
      this.asm = null; this.readError = null;
      this.draw(); this.panels.render();
      return;
    }
    const tSend = performance.now();
    try {
      const asm = await this.api.assemble(designToYaml(doc), abort.signal);
      if (seq !== this.seq) return;
      this.asm = asm; this.readError = null;
    } catch (e) {
      if (isAbort(e) || seq !== this.seq) return;
      this.asm = null;
      this.readError = e instanceof ApiError ? e : new ApiError(0, (e as Error).message);
    }
    const tBack = performance.now();
    this.draw();
    const tDrawn = performance.now();
    // A preview (a slider being dragged) redraws the results only, not the field being dragged.
    if (doc === this.design) this.panels.render(); else this.panels.renderResults();
    this.ctx.refreshSelectionLabel();
    const tEnd = performance.now();
    this.roundTrips.push(tEnd - t0);
    this.stages.push({ before: tSend - t0, server: tBack - tSend, draw: tDrawn - tBack, panels: tEnd - tDrawn });
    if (this.roundTrips.length > 200) { this.roundTrips.shift(); this.stages.shift(); }
  }

  /** Shows `doc` without making it a command (a slider being dragged). */
  preview(doc: FpDesign): void { void this.ctx.track(this.refresh(performance.now(), doc)); }

  /**
   * Applies a command. One that changes nothing is dropped: a field that loses focus because
   * the panel was redrawn reports its (already applied) change again.
   */
  apply(next: FpDesign, label: string): void {
    if (designToYaml(next) === designToYaml(this.design)) return;
    this.ctx.history.apply(next, label);
  }

  // ---------------------------------------------------------------- lookups
  component(name: string): FpComponent | undefined { return this.design.components.find((c) => c.name === name); }
  placed(name: string): ComponentInfo | undefined { return this.asm?.components.find((c) => c.name === name); }
  /** The piece a component was cut into (its own name unless merged into another). */
  pieceOf(component: string): string { return this.placed(component)?.piece ?? component; }
  diagnosticsOf(piece: string): FpDiagnostic[] { return (this.asm?.diagnostics ?? []).filter((d) => d.pieces.includes(piece)); }

  exists(object: string): boolean {
    return this.design.components.some((c) => c.name === object) || !!this.asm?.pieces.some((p) => p.name === object);
  }

  describeSelection(sel: SelectionState): string {
    if (sel.piece) {
      const [comp, edge] = splitRef(sel.piece);
      const c = this.placed(comp);
      const e = c?.edges.find((x) => x.name === edge);
      const len = e ? ` (${Math.hypot(e.end[0] - e.start[0], e.end[1] - e.start[1], e.end[2] - e.start[2]).toFixed(1)} mm)` : '';
      return `Selected: edge ${edge} of ${comp}${len}${this.pick === sel.piece ? ' — picked: click the edge to lay it on' : ''}`;
    }
    if (sel.object) {
      const c = this.component(sel.object);
      const p = this.asm?.pieces.find((x) => x.name === this.pieceOf(sel.object!));
      const size = p ? `, cut ${p.size_mm[0].toFixed(1)} × ${p.size_mm[1].toFixed(1)} mm from ${p.material.thickness} mm ${p.material.name}` : '';
      const merged = p && p.components.length > 1 ? `, one piece with ${p.components.filter((x) => x !== sel.object).join(', ')}` : '';
      return `Selected: ${c ? `${c.type} ${c.name}` : `piece ${sel.object}`}${size}${merged}`;
    }
    return 'Nothing selected — click a board to select it, or two edges to connect them';
  }

  // ---------------------------------------------------------------- commands
  addComponent(type: string, name?: string): void {
    const t = this.typeByName.get(type);
    const d = clone(this.design);
    const n = name && !d.components.some((c) => c.name === name) ? name : freshComponentName(d);
    const params: Record<string, Num> = {};
    const own = new Set((t?.constraints ?? []).map((c) => c.split('=')[0].trim()));
    for (const p of t?.params ?? []) {
      if (own.has(p.name)) continue;
      const v = START_VALUES[type]?.[p.name];
      if (v !== undefined) params[p.name] = v;
      else if (p.default === null) params[p.name] = p.kind === 'count' ? 6 : 50;
    }
    const c: FpComponent = { name: n, type, params };
    if (t?.takes_points) c.extra = { points: [[0, 0], [80, 0], [0, 60]] };
    d.components.push(c);
    this.apply(d, `add ${type} ${n}`);
    this.ctx.selection.set(n, null);
  }

  setComponentParam(name: string, param: string, value: Num | null, preview = false): void {
    const d = clone(this.design);
    const c = d.components.find((x) => x.name === name); if (!c) return;
    if (value === null) delete c.params[param]; else c.params[param] = value;
    if (preview) this.preview(d); else this.apply(d, `set ${name}.${param} = ${value ?? '(solved)'}`);
  }

  setParameter(name: string, patch: Partial<FpDesign['parameters'][number]>, preview = false): void {
    const d = clone(this.design);
    const p = d.parameters.find((x) => x.name === name); if (!p) return;
    Object.assign(p, patch);
    if (preview) this.preview(d);
    else this.apply(d, 'value' in patch ? `set ${name} = ${patch.value}` : `change parameter ${name}`);
  }

  /** Lays the picked edge `a` ("A.t") on edge `b` ("B.b"): the paper's 5-tuple with A folded up 90° about the edge. */
  connect(a: string, b: string): void {
    const d = clone(this.design);
    const conn: FpConnection = { a, b, alignment: 'front-front', offset: [0, 0, 0], rotation: [90, 0, 0] };
    d.connections.push(conn);
    this.apply(d, `connect ${a} → ${b}`);
    this.panels.selectedConnection = d.connections.length - 1;
  }

  setConnection(i: number, patch: Partial<FpConnection>, label: string): void {
    const d = clone(this.design);
    Object.assign(d.connections[i], patch);
    if (patch.joint === undefined && 'joint' in patch) delete d.connections[i].joint;
    this.apply(d, label);
  }

  deleteConnection(i: number): void {
    const d = clone(this.design);
    const [c] = d.connections.splice(i, 1);
    this.apply(d, `delete connection ${c.a} → ${c.b}`);
  }

  deleteComponent(name: string): void {
    this.apply(removeComponent(this.design, name), `delete ${name}`);
    this.ctx.selection.clear();
  }

  deleteSelection(): void {
    const o = this.ctx.selection.current.object;
    if (o && this.component(o)) this.deleteComponent(o);
    else if (this.panels.selectedConnection !== null && this.design.connections[this.panels.selectedConnection]) this.deleteConnection(this.panels.selectedConnection);
  }

  cancel(): boolean {
    if (!this.pick) return false;
    this.cancelPick();
    this.restyle();
    return true;
  }

  private cancelPick(): void {
    this.pick = null;
    const l = document.getElementById('pick-label'); if (l) l.textContent = '';
  }

  // ---------------------------------------------------------------- picking
  private onPick(piece: string | null, object: string | null): void {
    if (piece) { this.pickEdge(piece); return; }
    this.cancelPick();
    const comp = object ? (this.asm?.pieces.find((p) => p.name === object)?.components[0] ?? object) : null;
    this.ctx.selection.set(comp, null);
    this.restyle();
    this.panels.render();
  }

  /** Clicking an edge: the first picks it, the second (of another component) connects the two. */
  pickEdge(key: string): void {
    const [comp] = splitRef(key);
    if (this.pick && this.pick !== key) {
      const [first] = splitRef(this.pick);
      if (first === comp) { this.ctx.message(`${key} is an edge of ${comp} too: pick an edge of another component to connect ${this.pick} to.`, 'info'); return; }
      const a = this.pick;
      this.cancelPick();
      this.ctx.message('');
      this.ctx.selection.set(first, null);
      this.connect(a, key);
      return;
    }
    if (this.pick === key) { this.cancelPick(); this.restyle(); return; }
    this.pick = key;
    this.ctx.selection.set(comp, key);
    const l = document.getElementById('pick-label');
    if (l) l.textContent = `${key} picked: now click the edge to lay it on (${comp} moves; Esc cancels)`;
    this.restyle();
    this.panels.render();
  }

  // ---------------------------------------------------------------- drawing
  private framed = false;
  /** Piece name → how far it is moved for the exploded view (mm, world). */
  private offsets = new Map<string, THREE.Vector3>();

  draw(): void {
    const scene = this.ctx.scene;
    // (each layer made first: clearLayer also removes a layer's labels, but only of a layer that exists)
    for (const l of ['fp-pieces', 'fp-edges', 'fp-joints', 'fp-notes']) { scene.layer(l); scene.clearLayer(l); }
    scene.clearStates();
    this.offsets.clear();
    const asm = this.asm;
    if (!asm) { scene.restyle(); return; }
    const centre = new THREE.Vector3();
    for (const p of asm.pieces) centre.add(new THREE.Vector3(...p.centre));
    if (asm.pieces.length) centre.divideScalar(asm.pieces.length);
    let extent = 1;
    for (const p of asm.pieces) extent = Math.max(extent, new THREE.Vector3(...p.centre).distanceTo(centre));
    for (const p of asm.pieces) {
      const dir = new THREE.Vector3(...p.centre).sub(centre);
      this.offsets.set(p.name, dir.multiplyScalar(this.explode * 0.8 * Math.max(1, 150 / extent)));
    }
    const offsetOf = (piece: string) => this.offsets.get(piece) ?? new THREE.Vector3();
    const pieces = scene.layer('fp-pieces');
    asm.pieces.forEach((p, i) => {
      const mat = new THREE.MeshStandardMaterial({ color: WOOD[i % WOOD.length], roughness: 0.85, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
      const mesh = new THREE.Mesh(geometryOf(p.mesh), mat);
      mesh.position.copy(offsetOf(p.name));
      scene.pickable(mesh, p.name, null, WOOD[i % WOOD.length]);
      pieces.add(mesh);
    });
    if (!asm.placed) {
      // Not placed (a cycle that does not close, a bad value): each component's outline where
      // placement put it, in red, so what is wrong can be seen and its edges still clicked.
      for (const c of asm.components) {
        if (c.outline.length < 3) continue;
        const shape = new THREE.Shape(c.outline.map(([x, y]) => new THREE.Vector2(x, y)));
        const g = new THREE.ExtrudeGeometry(shape, { depth: c.material.thickness, bevelEnabled: false });
        g.translate(0, 0, -c.material.thickness / 2);
        g.applyMatrix4(new THREE.Matrix4().fromArray(c.frame));
        const mesh = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: 0xf08080, transparent: true, opacity: 0.8 }));
        scene.pickable(mesh, c.name, null, 0xf08080);
        pieces.add(mesh);
      }
    }
    // Edges: a thin rod along each named edge, pickable; shortened at the ends so that two
    // edges meeting at a corner can each be clicked.
    const edges = scene.layer('fp-edges');
    for (const c of asm.components) {
      const r = Math.max(0.9, c.material.thickness * 0.55);
      for (const e of c.edges) {
        const a = new THREE.Vector3(...e.start), b = new THREE.Vector3(...e.end);
        const len = a.distanceTo(b);
        if (len < 1e-6) continue;
        const inset = Math.min(len * 0.12, 10);
        const g = new THREE.CylinderGeometry(r, r, Math.max(len - 2 * inset, len * 0.5), 8);
        const mesh = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: EDGE, roughness: 0.6 }));
        mesh.position.copy(a.clone().add(b).multiplyScalar(0.5)).add(offsetOf(c.piece));
        mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
        scene.pickable(mesh, asm.placed ? c.piece : c.name, `${c.name}.${e.name}`, EDGE);
        edges.add(mesh);
      }
    }
    // Joints: a marker along each intersection, drawn over the boards, coloured by kind;
    // automatic ones (no connection asked for them) labelled "auto".
    const joints = scene.layer('fp-joints');
    for (const j of asm.joints) {
      const a = new THREE.Vector3(...j.start), b = new THREE.Vector3(...j.end);
      const len = a.distanceTo(b); if (len < 1e-6) continue;
      const off = offsetOf(j.pieces[0]).clone().add(offsetOf(j.pieces[1])).multiplyScalar(0.5);
      const mat = new THREE.MeshBasicMaterial({ color: JOINT_COLORS[j.kind], depthTest: false, transparent: true, opacity: 0.85 });
      const mesh = new THREE.Mesh(new THREE.CylinderGeometry(0.9, 0.9, len, 6), mat);
      mesh.renderOrder = 10;
      mesh.position.copy(a.clone().add(b).multiplyScalar(0.5)).add(off);
      mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
      mesh.raycast = () => {};
      mesh.userData.joint = j.id;
      joints.add(mesh);
      if (j.automatic) {
        scene.addLabel('fp-joints', a.clone().add(b).multiplyScalar(0.5).add(off), `auto j${j.id}`, { class: 'fp-auto', 'data-testid': `auto-joint-${j.id}`, title: `joint ${j.id}: ${j.kind} between ${j.pieces.join(' and ')}, found where they cross — no connection asked for it` });
      }
    }
    // A cycle that does not close: a dashed outline where the closing connection would put the
    // component, and a line from where it is to there, labelled with the residual.
    for (const r of asm.residuals) {
      if (r.closes) continue;
      const c = asm.components.find((x) => x.name === r.component);
      if (!c || c.outline.length < 3) continue;
      const there = new THREE.Matrix4().fromArray(r.frame), here = new THREE.Matrix4().fromArray(c.frame);
      const ring = c.outline.map(([x, y]) => new THREE.Vector3(x, y, 0).applyMatrix4(there));
      const loop = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(ring), new THREE.LineDashedMaterial({ color: 0xd00000, dashSize: 4, gapSize: 3 }));
      loop.computeLineDistances();
      const mid = (m: THREE.Matrix4) => c.outline.reduce((acc, [x, y]) => acc.add(new THREE.Vector3(x, y, 0).applyMatrix4(m)), new THREE.Vector3()).divideScalar(c.outline.length);
      const a = mid(here), b = mid(there);
      const gap = new THREE.Line(new THREE.BufferGeometry().setFromPoints([a, b]), new THREE.LineBasicMaterial({ color: 0xd00000 }));
      scene.layer('fp-notes').add(loop, gap);
      scene.addLabel('fp-notes', b, `${r.name} would put ${r.component} here: ${r.position_mm.toFixed(2)} mm, ${r.angle_deg.toFixed(2)}° off`, { class: 'fp-note error', 'data-testid': `residual-ghost-${r.name}` });
    }
    // Warnings and residuals beside the piece they concern.
    const notes = new Map<string, string[]>();
    for (const d of asm.diagnostics) for (const p of d.pieces) notes.set(p, [...(notes.get(p) ?? []), `${d.severity === 'error' ? '✖' : d.severity === 'note' ? 'ℹ' : '⚠'} ${d.message}`]);
    for (const r of asm.residuals) if (!r.closes) notes.set(r.piece, [...(notes.get(r.piece) ?? []), `✖ ${r.name} misses by ${r.position_mm.toFixed(2)} mm, ${r.angle_deg.toFixed(2)}°`]);
    for (const [piece, lines] of notes) {
      const at = this.anchorOf(piece); if (!at) continue;
      const el = document.createElement('div');
      for (const line of lines.slice(0, 3)) { const row = document.createElement('div'); row.textContent = line.length > 110 ? `${line.slice(0, 107)}…` : line; el.append(row); }
      if (lines.length > 3) el.append(`… ${lines.length - 3} more (see Warnings)`);
      scene.addLabel('fp-notes', at.add(offsetOf(piece)), el, { class: lines.some((l) => l.startsWith('✖')) ? 'fp-note error' : 'fp-note', 'data-testid': `note-${piece}` });
    }
    this.restyle();
    if (!this.framed && asm.components.length) { scene.frameAll(); this.framed = true; } else scene.keepInView();
  }

  /** A world point of a piece (or unplaced component) to pin its notes to: its top. */
  private anchorOf(piece: string): THREE.Vector3 | null {
    const p = this.asm?.pieces.find((x) => x.name === piece);
    if (p) {
      let top = -Infinity;
      for (let i = 2; i < p.mesh.vertices.length; i += 3) top = Math.max(top, p.mesh.vertices[i]);
      return new THREE.Vector3(p.centre[0], p.centre[1], top);
    }
    const c = this.placed(piece);
    if (c?.edges.length) return new THREE.Vector3(...c.edges[0].start);
    return null;
  }

  /** A clickable point of an edge: on its rod's axis (a vertex sits on the silhouette, where rounding may miss it). */
  edgePoint(key: string): { x: number; y: number } | null {
    const scene = this.ctx.scene;
    const mesh = scene.pieces.get(key); if (!mesh) return null;
    mesh.updateMatrixWorld();
    const r = scene.renderer.domElement.getBoundingClientRect();
    const len = (mesh.geometry as THREE.CylinderGeometry).parameters.height;
    for (const f of [0, 0.25, -0.25, 0.4, -0.4, 0.1, -0.1]) {
      const v = new THREE.Vector3(0, f * len, 0).applyMatrix4(mesh.matrixWorld).project(scene.camera);
      const x = r.left + ((v.x + 1) / 2) * r.width, y = r.top + ((1 - v.y) / 2) * r.height;
      if (x < r.left + 2 || x > r.right - 2 || y < r.top + 2 || y > r.bottom - 2) continue;
      if (scene.pickAt(x, y).piece === key) return { x, y };
    }
    return null;
  }

  setExplode(v: number): void {
    this.explode = v;
    this.ctx.store.set('explode', v);
    this.draw();
  }

  /** Edge, board and selection highlighting from the current pick and selection. */
  restyle(): void {
    const scene = this.ctx.scene;
    const sel = this.ctx.selection.current;
    scene.selectedObject = sel.object ? this.pieceOf(sel.object) : null;
    const pickComp = this.pick ? splitRef(this.pick)[0] : null;
    for (const key of scene.pieces.keys()) {
      const [comp] = splitRef(key);
      scene.setState(key, { picked: key === this.pick, selected: key === sel.piece && !this.pick, dim: !!pickComp && comp === pickComp && key !== this.pick });
    }
    scene.restyle();
  }

  /** The tooltip over an edge in the view: which edge, how long, what a click does. */
  private tooltip(key: string | null, x: number, y: number): void {
    const tip = document.getElementById('tooltip'); if (!tip) return;
    const c = key ? this.placed(splitRef(key)[0]) : undefined;
    const e = c?.edges.find((x) => x.name === splitRef(key!)[1]);
    if (!key || !e) { tip.hidden = true; return; }
    const len = Math.hypot(e.end[0] - e.start[0], e.end[1] - e.start[1], e.end[2] - e.start[2]);
    const what = !this.pick ? 'click: pick it (it moves onto the next edge you click)'
      : this.pick === key ? 'picked — click again to drop it'
        : splitRef(this.pick)[0] === splitRef(key)[0] ? `an edge of ${splitRef(key)[0]} too: pick another component's edge`
          : `click: lay ${this.pick} on it`;
    tip.textContent = `edge ${key}, ${len.toFixed(1)} mm — ${what}`;
    tip.hidden = false;
    tip.style.left = `${x + 14}px`; tip.style.top = `${y + 14}px`;
  }

  // ---------------------------------------------------------------- downloads
  async downloadKind(kind: string): Promise<void> {
    const yaml = designToYaml(this.design);
    const stem = fileStem(this.design.name);
    const files = kind === 'svg' || kind === 'dxf'
      ? Array.from({ length: Math.max(1, this.asm?.sheets.count ?? 1) }, (_, i) => `sheet-${i + 1}.${kind}`)
      : [{ stl: 'model.stl', glb: 'scene.glb', report: 'report.json' }[kind]!];
    await this.downloadFiles(yaml, stem, files);
  }

  async downloadFiles(yaml: string, stem: string, files: string[]): Promise<void> {
    this.ctx.status('building…');
    try {
      for (const f of files) {
        const blob = await this.api.file(yaml, f);
        download(`${stem}-${f}`, blob, blob.type);
      }
      this.ctx.status('');
    } catch (e) {
      this.ctx.status('');
      this.ctx.message(`cannot build the downloads: ${(e as Error).message}`);
    }
  }
}
