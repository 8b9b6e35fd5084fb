// The hacks workspace: its state (library, picking, last check and solve), its commands
// (connect, environment, target, solve) and its scene layer. Panels are in ./panels.ts.
import * as THREE from 'three';
import { ApiError, hacksApi } from './api';
import { isAbort } from '../../shell/server';
import type { CheckResult, CheckStep, Compat, HacksApi, MeshData, PartInfo, PartMesh, PlacedPart, PrimRef, SolveResult } from './api';
import { Inventory, cloneDesign, countOf, freshName, instances, removeInstance, renameRefs } from './model';
import { shortName } from './words';
import type { Connection, Design, EnvItem } from './model';
import { designToYaml } from './yamlio';
import { designToPython } from './python';
import { frameMatrix, geometryOf, matrixFrame } from '../../shell/scene';
import type { Frame, Vec3 } from '../../shell/scene';
import type { SelectionState } from '../../shell/selection';
import type { MountedWorkspace, ShellContext } from '../../shell/workspace';
import { download } from '../../shell/ui';
import { fileStem } from '../../shell/shell';
import { PRIM_COLORS } from './colors';
import { PRIMITIVE_WORDS_DOC } from './words';
import { Panels } from './panels';

/** A part to draw: where, its mesh, its primitive types; a ghost is drawn see-through. */
export interface ScenePart { name: string; type: string; frame: Frame; mesh: PartMesh; primTypes: Record<string, string>; ghost?: boolean }

/** A connect the check refused: not in the design, shown until dismissed. */
export interface FailedConnect {
  conn: Connection; step: CheckStep | null; message: string; check: CheckResult | null;
  /** 'connect': the check refused it; 'inventory': all owned parts of that kind are in use. */
  kind?: 'connect' | 'inventory';
  /** Set once the camera has framed the failing parts (only once per failure). */
  framed?: boolean;
}

/** What the failure layer shows: the gap between the failing primitives at the best configuration found. */
export interface FailureView { gap_mm: number | null; a: Vec3 | null; b: Vec3 | null; suggestion: string; framed: boolean }

export class HacksWorkspace implements MountedWorkspace {
  readonly api: HacksApi;
  library: PartInfo[] = [];
  partByName = new Map<string, PartInfo>();
  private meshCache = new Map<string, Promise<PartMesh>>();
  private primMeshCache = new Map<string, Promise<MeshData>>();
  inventory = new Inventory();
  selectedLibPart: string | null = null;
  /** First picked primitive: either in the scene ("eyehook1.hook") or in the library panel. */
  pick: { scene?: string; lib?: { part: string; prim: string } } | null = null;
  compat = new Map<string, Compat>(); // key: scene "inst.prim" or "lib:Part.prim"
  lastCheck: CheckResult | null = null;
  lastSolve: SolveResult | null = null;
  failed: FailedConnect | null = null;
  private checkSeq = 0;
  /** The name typed for the next new instance of the selected library part (kept across re-renders). */
  nameDraft: { part: string; name: string } | null = null;
  /** Parameters typed for the next new instance of a parametric part, per part. */
  paramDraft = new Map<string, Record<string, number>>();
  /** Table 1 by primitive type (union of the library's `connects_to` lists), for loose primitives. */
  typeConnects = new Map<string, Set<string>>();
  private sceneFramed = false;
  readonly panels: Panels;
  private offs: (() => void)[] = [];
  hooks: Record<string, unknown>;

  constructor(readonly ctx: ShellContext<Design>) {
    this.api = hacksApi(ctx.server);
    const owned = ctx.store.get<Record<string, number>>('inventory');
    if (owned) for (const [k, v] of Object.entries(owned)) this.inventory.set(k, v);
    this.panels = new Panels(this);
    ctx.toolbarButton('file', 'Export Python', 'export-python', 'Download the design as a FabHaL Python program (run it with fabkit run)', () =>
      download(`${fileStem(this.design.name)}.py`, designToPython(this.design), 'text/x-python'));
    ctx.toolbarButton('file', 'Download .glb', 'download-glb', 'Solve and download the solved scene as binary glTF', () => void this.downloadGlb());
    ctx.toolbarButton('run', 'Solve', 'solve', 'Reach the target, then relax under gravity', () => void ctx.track(this.solve()), { primary: true });
    this.offs.push(ctx.history.onChange((_d, label) => {
      this.lastSolve = null; this.failed = null;
      if (label.startsWith('open') || label === 'new design') this.sceneFramed = false;
      this.panels.solveStale();
      void ctx.track(this.refresh());
    }));
    const scene = ctx.scene;
    scene.setLegend([
      ...Object.entries(PRIM_COLORS).map(([type, color]) => ({ color, label: type, title: PRIMITIVE_WORDS_DOC[type] })),
      { color: 0xc8c8c8, label: 'part body' },
      { color: 0x2e9e44, label: 'target goal', title: 'where the target should end up (ghost) and how far it is (line)' },
      { color: 0xff0000, label: 'failing / slipping', title: 'a connect that was refused, or a connection that slips' },
      { color: 0xff9800, label: 'selected' },
      { color: 0x2f6fff, label: 'under the pointer' },
    ]);
    scene.onPick = (prim, part) => {
      if (prim) void ctx.track(this.pickScene(prim));
      else { ctx.selection.set(part, null); void this.updateScene(); this.panels.render(); }
    };
    scene.onHover = (key, x, y) => this.panels.hover(key, x, y);
    this.hooks = {
      designYaml: () => designToYaml(this.design),
      python: () => designToPython(this.design),
      /** Scene keys ("inst.prim") that have a mesh in the 3D view, with their triangle counts. */
      /** The goal and the achieved point of the target's primitive (mm), with the label's text. */
      goal: () => this.goal,
      renderInfo: () => scene.renderInfo(),
      /** The last settling animation: the part that moved most, sampled at every frame. */
      settleLog: () => this.settleLog,
      /** The refused connect as the 3D view shows it (gap between the failing primitives, suggestion). */
      failure: () => this.failure,
      /** How a scene key is drawn: emissive colour, outline colour and width (px). */
      styleOf: (key: string) => scene.styleOf(key),
      hovered: () => scene.hovered,
      sceneMeshes: () => Object.fromEntries([...scene.pieces].map(([k, m]) => [k, (m.geometry.index?.count ?? 0) / 3])),
    };
    void ctx.track(this.load());
  }

  get design(): Design { return this.ctx.history.current; }

  private async load(): Promise<void> {
    this.ctx.status('loading parts…');
    this.library = await this.api.parts();
    for (const p of this.library) {
      this.partByName.set(p.name, p);
      for (const q of p.primitives) {
        if (!this.typeConnects.has(q.type)) this.typeConnects.set(q.type, new Set());
        for (const t of q.connects_to) this.typeConnects.get(q.type)!.add(t);
      }
    }
    this.panels.buildLibrary();
    this.ctx.status('');
    await this.refresh();
  }

  unmount(): void {
    for (const off of this.offs) off();
    this.ctx.scene.onPick = () => {};
    this.ctx.scene.onHover = () => {};
  }

  // ---------------------------------------------------------------- names and lookups
  partInfo(type: string): PartInfo | undefined {
    return this.partByName.get(type) ?? this.library.find((p) => p.aliases.includes(type));
  }
  meshOf(type: string, params?: Record<string, number>): Promise<PartMesh> {
    const key = type + JSON.stringify(params ?? {});
    if (!this.meshCache.has(key)) this.meshCache.set(key, this.api.mesh(this.partInfo(type)?.name ?? type, params));
    return this.meshCache.get(key)!;
  }
  typeOfInstance(name: string): string | undefined {
    return instances(this.design).find((i) => i.name === name)?.part ?? (this.looseEnv(name) ? 'loose primitives' : undefined);
  }
  /** An environment made of loose primitives (no library part). */
  looseEnv(name: string): EnvItem | undefined { return this.design.environment.find((e) => e.name === name && !e.part && e.primitives); }
  /** The primitive type of a scene key ("eyehook1.hook" → hook, "table.surface" → surface). */
  primTypeOf(key: string): string | undefined {
    const [inst, prim] = key.split('.');
    const e = this.looseEnv(inst);
    if (e) { const t = looseSpec(e, prim)?.type; return t === undefined ? undefined : String(t); }
    return this.partInfo(this.typeOfInstance(inst) ?? '')?.primitives.find((p) => p.name === prim)?.type;
  }
  isLooseKey(key: string): boolean { return !!this.looseEnv(key.split('.')[0]); }
  private refOf(key: string): PrimRef | null {
    const [inst, prim] = key.split('.');
    const i = instances(this.design).find((x) => x.name === inst);
    if (!i) return null;
    const info = this.partInfo(i.part);
    return { part: info?.name ?? i.part, primitive: prim, ...(i.params ? { params: i.params } : {}) };
  }

  /** The selected connection's index (the selection's object is "#conn<i>"), or null. */
  selectedConnection(): number | null {
    const o = this.ctx.selection.current.object;
    return o?.startsWith('#conn') ? Number(o.slice(5)) : null;
  }

  selectConnection(i: number): void {
    this.ctx.selection.set(`#conn${i}`, null);
    void this.updateScene();
    this.panels.render();
  }

  exists(object: string): boolean {
    if (object.startsWith('#conn')) return Number(object.slice(5)) < this.design.connections.length;
    return instances(this.design).some((i) => i.name === object) || this.design.environment.some((e) => e.name === object);
  }

  describeSelection(sel: SelectionState): string {
    const lib = this.pick?.lib;
    if (lib) return `Picked: primitive ${lib.prim} (${this.partInfo(lib.part)?.primitives.find((p) => p.name === lib.prim)?.type ?? '?'}) of a new ${lib.part} — click a primitive in the scene to connect it (Esc cancels)`;
    if (sel.piece) {
      const inst = sel.piece.split('.')[0];
      const type = this.primTypeOf(sel.piece);
      return `Selected: primitive ${sel.piece}${type ? ` (${type})` : ''} of part ${inst} (${this.typeOfInstance(inst) ?? '?'})`;
    }
    const ci = this.selectedConnection();
    if (ci !== null) {
      const c = this.design.connections[ci];
      return `Selected: connection ${c.a} – ${c.b} (${c.alignment ?? 'default'} alignment${c.fixed ? ', fixed' : ''})`;
    }
    if (sel.object) return `Selected: part ${sel.object} (${this.typeOfInstance(sel.object) ?? '?'})`;
    return 'Nothing selected';
  }

  onDisplayChange(): void { this.panels.render(); }

  /** The Delete key: deletes the selected connection, or the selected part with its connections. */
  deleteSelection(): void {
    const ci = this.selectedConnection();
    const h = this.ctx.history;
    if (ci !== null) {
      const n = cloneDesign(this.design); const c = n.connections.splice(ci, 1)[0];
      this.ctx.selection.clear();
      h.apply(n, `delete connection ${c.a} – ${c.b}`);
      return;
    }
    const o = this.ctx.selection.current.object;
    if (!o || !this.exists(o)) { this.ctx.message('Select a part or a connection to delete it with the Delete key.', 'info'); return; }
    this.ctx.selection.clear();
    h.apply(removeInstance(this.design, o), `delete ${o}`);
  }

  cancel(): boolean {
    if (this.solving) { this.cancelSolve(); return true; }
    const had = !!this.pick;
    this.pick = null;
    void this.ctx.track(this.afterPickChange());
    return had;
  }

  /** Meshes of a loose-primitive environment, each placed by the primitive's own frame inside the part. */
  private async looseMeshOf(e: EnvItem): Promise<{ mesh: PartMesh; primTypes: Record<string, string> }> {
    const mesh: PartMesh = { name: e.name, body: { vertices: [], faces: [] }, primitives: {} };
    const primTypes: Record<string, string> = {};
    for (const [prim, raw] of Object.entries(e.primitives ?? {})) {
      const spec = raw as Record<string, unknown>;
      const type = String(spec.type ?? '');
      const sizes: Record<string, number> = {};
      for (const [k, v] of Object.entries(spec)) if (k !== 'type' && k !== 'frame') sizes[k] = Number(v);
      const key = type + JSON.stringify(sizes);
      if (!this.primMeshCache.has(key)) this.primMeshCache.set(key, this.api.primMesh(type, sizes));
      let m: MeshData;
      try { m = await this.primMeshCache.get(key)!; } catch (err) { this.primMeshCache.delete(key); this.ctx.message(`cannot draw ${e.name}.${prim}: ${(err as Error).message}`); continue; }
      const mat = frameMatrix(frameOfSpec(spec.frame));
      const v = new THREE.Vector3(), out: number[] = [];
      for (let i = 0; i < m.vertices.length; i += 3) { v.set(m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]).applyMatrix4(mat); out.push(v.x, v.y, v.z); }
      mesh.primitives[prim] = { vertices: out, faces: m.faces };
      primTypes[prim] = type;
    }
    return { mesh, primTypes };
  }

  /** The frame of a part whose primitive `prim` sits at world frame `f`. */
  partFrameFromPrimFrame(type: string, prim: string | undefined, f: Frame): Frame {
    const info = this.partInfo(type);
    const p = prim ? info?.primitives.find((q) => q.name === prim || (prim === 'hole' && q.name === 'ring')) : info?.primitives[0];
    if (!p) return f;
    return matrixFrame(frameMatrix(f).multiply(frameMatrix(p.frame).invert()));
  }

  // ---------------------------------------------------------------- check & scene
  async runCheck(d: Design): Promise<CheckResult | null> {
    if (!d.environment.length) return null;
    return this.api.check(designToYaml(d));
  }

  /** Re-checks the design and redraws (after every command). */
  async refresh(): Promise<void> {
    const seq = ++this.checkSeq;
    this.panels.render();
    try {
      const c = await this.runCheck(this.design);
      if (seq !== this.checkSeq) return;
      this.lastCheck = c;
      this.panels.checkError = null;
    } catch (e) {
      if (seq !== this.checkSeq) return;
      this.lastCheck = null;
      this.panels.checkError = e instanceof ApiError ? `cannot read design: ${e.message}` : String(e);
    }
    await this.updateScene();
    this.panels.render();
  }

  async updateScene(): Promise<void> {
    const d = this.design;
    const failed = this.failed;
    let placed: PlacedPart[] = this.lastSolve?.parts ?? this.lastCheck?.parts ?? [];
    const bad = new Set<string>();
    if (failed?.step?.best_part_frames && failed.check) {
      placed = failed.check.parts.map((p, i) => ({ ...p, frame: failed.step!.best_part_frames![i] ?? p.frame }));
      bad.add(failed.conn.a); bad.add(failed.conn.b);
    }
    const parts: ScenePart[] = [];
    const seen = new Set<string>();
    const add = async (name: string, type: string, frame: Frame, ghost: boolean, params?: Record<string, number>) => {
      seen.add(name);
      const mesh = await this.meshOf(type, params);
      const info = this.partInfo(type);
      parts.push({ name, type, frame, mesh, ghost, primTypes: Object.fromEntries((info?.primitives ?? []).map((p) => [p.name, p.type])) });
    };
    const jobs: Promise<void>[] = [];
    for (const p of placed) {
      const inst = instances(d).find((i) => i.name === p.name);
      if (inst) jobs.push(add(p.name, inst.part, p.frame, false, inst.params));
    }
    await Promise.all(jobs);
    // loose-primitive environments: at the checked/solved frame, else where the user put them
    for (const e of d.environment) if (!e.part && e.primitives) {
      seen.add(e.name);
      const { mesh, primTypes } = await this.looseMeshOf(e);
      parts.push({ name: e.name, type: 'Environment', frame: placed.find((p) => p.name === e.name)?.frame ?? e.frame, mesh, primTypes });
    }
    // environment and target that the check did not place yet: show them where the user put them
    for (const e of d.environment) if (e.part && !seen.has(e.name)) await add(e.name, e.part, e.frame, false);
    if (d.target && !seen.has(d.target.name)) await add(d.target.name, d.target.part, this.partFrameFromPrimFrame(d.target.part, d.target.primitive, d.target.frame), true);
    this.drawParts(parts);
    await this.drawGoal(placed);
    this.drawFailure();
    const scene = this.ctx.scene;
    const slipping = this.slippingConnections();
    const sel = this.ctx.selection.current;
    scene.clearStates();
    const ci = this.selectedConnection();
    const connKeys = ci !== null && d.connections[ci] ? [d.connections[ci].a, d.connections[ci].b] : [];
    for (const key of scene.pieces.keys()) {
      const c = this.compat.get(key);
      scene.setState(key, {
        dim: !!this.pick && !!c && !c.ok, picked: this.pick?.scene === key, selected: sel.piece === key || connKeys.includes(key.replace(/\.ring$/, '.hole')) || connKeys.includes(key),
        bad: bad.has(key) || slipping.some((i) => d.connections[i].a === key || d.connections[i].b === key),
      });
    }
    scene.selectedObject = sel.object;
    scene.restyle();
    if (!this.sceneFramed && parts.length) { this.sceneFramed = true; scene.view('iso'); }
    else if (!failed) scene.keepInView(); // an edit moved everything out of the view: follow it
  }

  /** The parts layer: one group per part at its frame, a grey body and one pickable mesh per primitive. */
  private drawParts(parts: ScenePart[]): void {
    const scene = this.ctx.scene;
    scene.clearLayer('parts');
    this.partGroups.clear();
    const layer = scene.layer('parts');
    for (const p of parts) {
      const g = new THREE.Group();
      g.matrixAutoUpdate = false;
      g.matrix.copy(frameMatrix(p.frame));
      this.partGroups.set(p.name, g);
      if (p.mesh.body.faces.length) { // loose-primitive environments have no body
        const body = new THREE.Mesh(geometryOf(p.mesh.body), new THREE.MeshStandardMaterial({ color: 0xc8c8c8, transparent: !!p.ghost, opacity: p.ghost ? 0.35 : 1, roughness: 0.8, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2 }));
        scene.pickable(body, p.name, null, 0xc8c8c8);
        if (p.ghost) body.userData.ghost = true;
        g.add(body);
      }
      for (const [prim, m] of Object.entries(p.mesh.primitives)) {
        const color = PRIM_COLORS[p.primTypes[prim]] ?? 0x999999;
        const mesh = new THREE.Mesh(geometryOf(m), new THREE.MeshStandardMaterial({ color, transparent: true, opacity: p.ghost ? 0.5 : 1, roughness: 0.5 }));
        scene.pickable(mesh, p.name, `${p.name}.${prim}`, color);
        if (p.ghost) mesh.userData.ghost = true;
        g.add(mesh);
      }
      layer.add(g);
    }
    layer.updateMatrixWorld(true);
  }

  /** Where the target should be and how far it is: the goal's world point, the achieved one. */
  goal: { goal: Vec3; achieved: Vec3 | null; distance_mm: number | null; text: string } | null = null;

  /**
   * The goal layer: the target part drawn as a green ghost at the pose asked for (always, also
   * once it is connected), and a line from where the target's primitive is to where it should be,
   * labelled with the error (the solve's position, tilt and twist; before a solve, the distance).
   */
  private async drawGoal(placed: PlacedPart[]): Promise<void> {
    const scene = this.ctx.scene;
    scene.clearLayer('goal');
    this.goal = null;
    const t = this.design.target;
    const info = t ? this.partInfo(t.part) : undefined;
    if (!t || !info) return;
    const primName = t.primitive ?? info.primitives[0]?.name;
    const prim = info.primitives.find((p) => p.name === primName || (primName === 'hole' && p.name === 'ring'));
    const goalPos = new THREE.Vector3().setFromMatrixPosition(frameMatrix(t.frame));
    const layer = scene.layer('goal');
    const at = placed.find((p) => p.name === t.name);
    const v3 = (v: THREE.Vector3): Vec3 => [v.x, v.y, v.z];
    if (!at) { // not placed yet: the pickable ghost in the parts layer is the goal
      scene.addLabel('goal', goalPos, `goal of ${t.name}`, { class: 'goal', 'data-testid': 'goal-label' });
      this.goal = { goal: v3(goalPos), achieved: null, distance_mm: null, text: '' };
      return;
    }
    let mesh: PartMesh;
    try { mesh = await this.meshOf(t.part); } catch { return; }
    const ghost = new THREE.Group();
    ghost.matrixAutoUpdate = false;
    ghost.matrix.copy(frameMatrix(this.partFrameFromPrimFrame(t.part, t.primitive, t.frame)));
    const fill = new THREE.MeshBasicMaterial({ color: 0x2e9e44, transparent: true, opacity: 0.16, depthWrite: false });
    const edge = new THREE.LineBasicMaterial({ color: 0x2e9e44, transparent: true, opacity: 0.7 });
    for (const m of [mesh.body, ...Object.values(mesh.primitives)]) {
      if (!m.faces.length) continue;
      const g = geometryOf(m);
      ghost.add(new THREE.Mesh(g, fill), new THREE.LineSegments(new THREE.EdgesGeometry(g, 35), edge));
    }
    ghost.userData.goal = true;
    layer.add(ghost);
    const achieved = new THREE.Vector3().setFromMatrixPosition(frameMatrix(at.frame).multiply(frameMatrix(prim?.frame ?? { pos: [0, 0, 0], rot: [0, 0, 0] })));
    const distance = achieved.distanceTo(goalPos);
    const solved = this.lastSolve?.target;
    const onTarget = solved ? this.onTarget(solved) : distance <= this.tolerance().mm;
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([achieved, goalPos]),
      new THREE.LineBasicMaterial({ color: onTarget ? 0x2e9e44 : 0xd9822b }));
    const dot = (p: THREE.Vector3, color: number) => {
      const s = new THREE.Mesh(new THREE.SphereGeometry(4, 12, 8), new THREE.MeshBasicMaterial({ color }));
      s.position.copy(p); return s;
    };
    layer.add(line, dot(goalPos, 0x2e9e44), dot(achieved, onTarget ? 0x2e9e44 : 0xd9822b));
    layer.updateMatrixWorld(true);
    const text = solved ? `${t.name}: ${describeError(solved)}` : `${t.name}: ${distance.toFixed(1)} mm from its goal (before solving)`;
    scene.addLabel('goal', achieved.clone().lerp(goalPos, 0.5), text, { class: onTarget ? 'ok' : 'off', 'data-testid': 'goal-error-label' });
    this.goal = { goal: v3(goalPos), achieved: v3(achieved), distance_mm: distance, text };
  }

  failure: FailureView | null = null;

  /**
   * The failure layer: where a refused connect is explained — a callout in the 3D view next to
   * the failing primitives with the diagnostic, for a cycle that cannot close a red line across
   * the gap (closest points of the two primitives at the best configuration found) with its
   * length and a suggestion of parts that span it; the camera frames the failing parts once.
   */
  private drawFailure(): void {
    const scene = this.ctx.scene;
    scene.clearLayer('failure');
    this.failure = null;
    const f = this.failed;
    if (!f) return;
    const layer = scene.layer('failure');
    const ma = scene.pieces.get(f.conn.a), mb = scene.pieces.get(f.conn.b);
    let a: THREE.Vector3 | null = null, b: THREE.Vector3 | null = null, gap: number | null = null;
    if (ma && mb && f.step?.best_part_frames) {
      [a, b] = closestPoints(ma, mb);
      gap = a.distanceTo(b);
      const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([a, b]), new THREE.LineBasicMaterial({ color: 0xe01010 }));
      const dot = (p: THREE.Vector3) => { const s = new THREE.Mesh(new THREE.SphereGeometry(3, 12, 8), new THREE.MeshBasicMaterial({ color: 0xe01010 })); s.position.copy(p); return s; };
      layer.add(line, dot(a), dot(b));
      layer.updateMatrixWorld(true);
    }
    const suggestion = gap !== null && gap > 1 ? this.suggestSpan(f.conn, gap) : '';
    const anchorMesh = mb ?? ma;
    const anchor = a && b ? a.clone().lerp(b, 0.5)
      : anchorMesh ? new THREE.Box3().setFromObject(anchorMesh).getCenter(new THREE.Vector3()) : null;
    if (anchor) {
      const box = document.createElement('div');
      const title = f.kind === 'inventory' ? 'Not added (inventory): ' : 'Not added: ';
      box.append(Object.assign(document.createElement('b'), { textContent: `${title}${f.conn.a} – ${f.conn.b}` }),
        Object.assign(document.createElement('div'), { className: 'diag', textContent: f.message }));
      if (gap !== null) box.append(Object.assign(document.createElement('div'), { textContent: `red line: a gap of ${gap.toFixed(1)} mm between the two primitives in the closest configuration found`, className: 'gap' }));
      if (suggestion) box.append(Object.assign(document.createElement('div'), { textContent: suggestion, className: 'suggestion' }));
      const dismiss = Object.assign(document.createElement('button'), { textContent: 'Dismiss', title: 'Back to the design (the connection is not added)' });
      dismiss.dataset.testid = 'failure-dismiss';
      dismiss.addEventListener('click', () => this.dismissFailed());
      box.append(dismiss);
      scene.addLabel('failure', anchor, box, { class: 'failure', 'data-testid': 'failure-callout' });
    }
    const v3 = (v: THREE.Vector3 | null): Vec3 | null => (v ? [v.x, v.y, v.z] : null);
    if (!f.framed) {
      f.framed = true;
      const box = new THREE.Box3();
      // the failing primitives, and the parts they belong to unless those are environment (a wall)
      const envs = new Set(this.design.environment.map((e) => e.name));
      for (const key of [f.conn.a, f.conn.b]) {
        const m = scene.pieces.get(key); if (m) box.expandByObject(m);
        const inst = key.split('.')[0];
        if (envs.has(inst)) continue;
        for (const [k, pm] of scene.pieces) if (k.split('.')[0] === inst) box.expandByObject(pm);
        const body = scene.bodies.get(inst); if (body) box.expandByObject(body);
      }
      if (a && b) box.expandByPoint(a).expandByPoint(b);
      if (!box.isEmpty()) scene.frameBox(box);
    }
    this.failure = { gap_mm: gap, a: v3(a), b: v3(b), suggestion, framed: !!f.framed };
  }

  /**
   * Two-primitive library parts that could bridge a gap between the failing primitives: each
   * end must connect (Table 1) to its neighbour, the span is the distance between the part's two
   * primitive frames. The fewest parts first; returns one sentence, or '' when nothing fits.
   */
  private suggestSpan(conn: Connection, gap: number): string {
    const ta = this.primTypeOf(conn.a), tb = this.primTypeOf(conn.b);
    if (!ta || !tb) return '';
    const ok = (x: string, y: string) => this.typeConnects.get(x)?.has(y) ?? false;
    const options: { name: string; n: number; span: number }[] = [];
    for (const p of this.library) {
      if (p.category === 'environment' || p.primitives.length !== 2 || p.params.length) continue;
      const [p1, p2] = p.primitives;
      const span = new THREE.Vector3(...p1.frame.pos).distanceTo(new THREE.Vector3(...p2.frame.pos));
      if (span < 5) continue;
      const chains = ok(p2.type, p1.type); // copies hang from one another
      const fits = (x: typeof p1, y: typeof p1) => ok(ta, x.type) && ok(y.type, tb);
      if (!fits(p1, p2) && !fits(p2, p1)) continue;
      const n = Math.ceil(gap / span);
      if (n > 1 && !chains) continue;
      if (n > 20) continue;
      options.push({ name: p.name, n, span });
    }
    options.sort((x, y) => x.n - y.n || x.span - y.span);
    if (!options.length) return '';
    const say = (o: { name: string; n: number; span: number }) => `${o.n === 1 ? 'one more' : `a chain of ${o.n} more`} ${o.name} (${o.span.toFixed(0)} mm each)`;
    const alt = options.find((o) => o.name !== options[0].name && o.n > options[0].n);
    return `Suggestion: ${say(options[0])} would span the ${gap.toFixed(0)} mm gap${alt ? `; or ${say(alt)}` : ''}.`;
  }

  /** The user's "does it do what I asked" tolerance (kept in local storage). */
  tolerance(): { mm: number; deg: number } {
    return this.ctx.store.get<{ mm: number; deg: number }>('tolerance') ?? { mm: 25, deg: 10 };
  }
  setTolerance(t: { mm: number; deg: number }): void {
    this.ctx.store.set('tolerance', t);
    if (this.lastSolve) this.panels.solveResult(this.lastSolve, null);
    void this.updateScene();
  }
  onTarget(e: { pos_error_mm: number; rot_error_deg: number }): boolean {
    const t = this.tolerance();
    return e.pos_error_mm <= t.mm && e.rot_error_deg <= t.deg;
  }

  private partGroups = new Map<string, THREE.Group>();
  settleLog: { part: string; from: Vec3; to: Vec3; samples: Vec3[] } | null = null;

  /**
   * Shows gravity act: every part moves from where step 1 put it (reaching for the target) to
   * where it came to rest, over 0.9 s (at once when the user prefers reduced motion).
   */
  async settle(): Promise<void> {
    const r = this.lastSolve;
    if (!r?.step1_parts?.length) return;
    const start = new Map(r.step1_parts.map((p) => [p.name, frameMatrix(p.frame)]));
    const moves: { name: string; g: THREE.Group; p0: THREE.Vector3; q0: THREE.Quaternion; p1: THREE.Vector3; q1: THREE.Quaternion }[] = [];
    for (const [name, g] of this.partGroups) {
      const a = start.get(name); if (!a) continue;
      const p0 = new THREE.Vector3(), q0 = new THREE.Quaternion(), p1 = new THREE.Vector3(), q1 = new THREE.Quaternion(), sc = new THREE.Vector3();
      const rest = r.parts.find((x) => x.name === name);
      a.decompose(p0, q0, sc); (rest ? frameMatrix(rest.frame) : g.matrix).decompose(p1, q1, sc);
      moves.push({ name, g, p0, q0, p1, q1 });
    }
    if (!moves.length) return;
    const most = moves.reduce((x, y) => (y.p0.distanceTo(y.p1) > x.p0.distanceTo(x.p1) ? y : x));
    const v3 = (v: THREE.Vector3): Vec3 => [v.x, v.y, v.z];
    this.settleLog = { part: most.name, from: v3(most.p0), to: v3(most.p1), samples: [] };
    const layer = this.ctx.scene.layer('parts');
    const one = new THREE.Vector3(1, 1, 1), p = new THREE.Vector3(), q = new THREE.Quaternion();
    await this.ctx.scene.animate(900, (t) => {
      const e = t < 0.5 ? 2 * t * t : 1 - (-2 * t + 2) ** 2 / 2; // ease in and out
      for (const m of moves) m.g.matrix.compose(p.copy(m.p0).lerp(m.p1, e), q.copy(m.q0).slerp(m.q1, e), one);
      layer.updateMatrixWorld(true);
      this.settleLog!.samples.push(v3(p.copy(most.p0).lerp(most.p1, e)));
    });
  }

  slippingConnections(): number[] {
    const solved = this.lastSolve;
    if (!solved) return [];
    const out: number[] = [];
    this.design.connections.forEach((c, i) => {
      if (solved.slipping.some((s) => (s.includes(c.a) && s.includes(c.b)) || s.includes(c.a) || s.includes(c.b))) out.push(i);
    });
    return out;
  }

  // ---------------------------------------------------------------- picking & connecting
  /** Table 1 by primitive type only (for loose primitives, which /api/compatible does not know). */
  private typeRule(a: string | undefined, b: string | undefined): Compat {
    if (!a || !b) return { ok: true, reason: 'sizes are checked when you connect' };
    const ok = this.typeConnects.get(a)?.has(b) ?? false;
    return ok ? { ok, reason: `${a} – ${b}: allowed by Table 1; sizes are checked when you connect` }
      : { ok, reason: `a ${a} cannot connect to a ${b} (Table 1); sizes are checked when you connect` };
  }

  private async computeCompat(): Promise<void> {
    this.compat = new Map();
    const pick = this.pick;
    if (!pick) return;
    let a: PrimRef | null;
    let aType: string | undefined;
    const lib = this.selectedLibPart ? this.partInfo(this.selectedLibPart) : undefined;
    if (pick.scene) { a = this.isLooseKey(pick.scene) ? null : this.refOf(pick.scene); aType = this.primTypeOf(pick.scene); }
    else {
      a = { part: pick.lib!.part, primitive: pick.lib!.prim };
      const pd = this.paramDraft.get(pick.lib!.part); if (pd && Object.keys(pd).length) a.params = pd;
      aType = this.partInfo(pick.lib!.part)?.primitives.find((p) => p.name === pick.lib!.prim)?.type;
    }
    const keys: string[] = [], refs: PrimRef[] = [];
    for (const key of this.ctx.scene.pieces.keys()) {
      if (key === pick.scene) continue;
      if (!a || this.isLooseKey(key)) { this.compat.set(key, this.typeRule(aType, this.primTypeOf(key))); continue; }
      const r = this.refOf(key); if (r) { keys.push(key); refs.push(r); }
    }
    if (lib) for (const p of lib.primitives) {
      if (pick.lib && pick.lib.part === lib.name && pick.lib.prim === p.name) continue; // the picked one itself
      if (!a) { this.compat.set(`lib:${lib.name}.${p.name}`, this.typeRule(aType, p.type)); continue; }
      keys.push(`lib:${lib.name}.${p.name}`); refs.push({ part: lib.name, primitive: p.name });
    }
    if (!refs.length || !a) return;
    const res = await this.api.compatible(a, refs);
    res.forEach((r, i) => this.compat.set(keys[i], r));
  }

  async pickScene(key: string): Promise<void> {
    this.ctx.selection.set(key.split('.')[0], key);
    const pick = this.pick;
    if (!pick) { this.pick = { scene: key }; await this.afterPickChange(); return; }
    if (pick.scene === key) { this.pick = null; await this.afterPickChange(); return; }
    this.pick = null;
    if (pick.scene) await this.connect(pick.scene, key, null);
    else await this.connect(null, key, pick.lib!);
  }

  async pickLibrary(part: string, prim: string): Promise<void> {
    const pick = this.pick;
    if (!pick) { this.pick = { lib: { part, prim } }; await this.afterPickChange(); return; }
    if (pick.lib) {
      if (pick.lib.part === part && pick.lib.prim === prim) { this.pick = null; await this.afterPickChange(); return; }
      this.ctx.message('Pick the second primitive in the scene (two library primitives cannot be connected).');
      return;
    }
    this.pick = null;
    await this.connect(null, pick.scene!, { part, prim });
  }

  async afterPickChange(): Promise<void> {
    this.ctx.message('');
    await this.computeCompat();
    this.panels.pickLabel();
    await this.updateScene();
    this.panels.render();
  }

  /** Connect `a` (scene) or a new instance of `lib` with scene primitive `b`; keep it only if the check accepts it. */
  async connect(a: string | null, b: string, lib: { part: string; prim: string } | null): Promise<void> {
    const next = cloneDesign(this.design);
    if (lib) {
      const owned = this.inventory.limit(lib.part);
      if (owned !== undefined && countOf(next, lib.part) >= owned) {
        const msg = `Inventory: you own ${owned} ${lib.part} and all ${owned} are already in the design; cannot add another (change "owned" under Primitives).`;
        this.failed = { conn: { a: `(new ${lib.part}).${lib.prim}`, b }, step: null, message: msg, check: null, kind: 'inventory' };
        this.compat = new Map(); this.panels.pickLabel();
        await this.updateScene();
        this.panels.render();
        return;
      }
      let name = this.takeName(lib.part) || freshName(next, shortName(lib.part));
      if (instances(next).some((i) => i.name === name) || next.environment.some((e) => e.name === name)) name = freshName(next, name.replace(/\d+$/, ''));
      const pd = this.paramDraft.get(lib.part);
      next.parts.push(pd && Object.keys(pd).length ? { name, part: lib.part, params: { ...pd } } : { name, part: lib.part });
      a = `${name}.${lib.prim}`;
    }
    const conn: Connection = { a: a!, b };
    next.connections.push(conn);
    this.ctx.status('checking…');
    let c: CheckResult | null = null;
    try { c = await this.runCheck(next); } catch (e) {
      this.failed = { conn, step: null, message: e instanceof ApiError ? e.message : String(e), check: null };
    }
    this.ctx.status('');
    if (c) {
      const step = connectSteps(c)[next.connections.length - 1] ?? null;
      if (step && step.accepted) {
        this.compat = new Map(); this.panels.pickLabel();
        if (lib) this.nameDraft = null;
        this.ctx.history.apply(next, `connect ${conn.a} – ${conn.b}`);
        return;
      }
      const msg = step ? (step.diagnostics.map((d) => d.message).join('; ') || (step.skipped ? 'skipped because an earlier step failed' : 'rejected')) : 'rejected';
      this.failed = { conn, step, message: msg, check: c };
    }
    this.compat = new Map(); this.panels.pickLabel();
    await this.updateScene();
    this.panels.render();
  }

  dismissFailed(): void {
    this.failed = null;
    void this.updateScene();
    this.panels.render();
  }

  // ---------------------------------------------------------------- commands
  setInventory(part: string, n: number | undefined): void {
    this.inventory.set(part, n);
    this.ctx.store.set('inventory', Object.fromEntries(this.inventory.owned));
    this.panels.render();
  }

  setEnvironment(part: string): void {
    const d = cloneDesign(this.design);
    const owned = this.inventory.limit(part);
    if (owned !== undefined && countOf(d, part) >= owned) { this.ctx.message(`Inventory: you own ${owned} ${part}; cannot add another.`); return; }
    const typed = this.takeName(part);
    if (typed && !this.nameFree(d, typed)) { this.ctx.message(`The name ${typed} is taken; choose another.`); return; }
    const name = typed || freshName(d, 'env');
    d.environment.push({ name, part, frame: { pos: [0, 0, 0], rot: [0, 0, 0] } });
    this.nameDraft = null;
    this.ctx.history.apply(d, `environment ${name}`);
  }

  setTarget(part: string): void {
    const d = cloneDesign(this.design);
    const owned = this.inventory.limit(part);
    const already = d.target ? 1 : 0;
    if (owned !== undefined && countOf(d, part) - (d.target?.part === part ? already : 0) >= owned) { this.ctx.message(`Inventory: you own ${owned} ${part}; cannot add another.`); return; }
    const typed = this.takeName(part);
    if (typed && typed !== d.target?.name && !this.nameFree(d, typed)) { this.ctx.message(`The name ${typed} is taken; choose another.`); return; }
    const name = typed || d.target?.name || freshName(d, 'target');
    if (d.target && d.target.name !== name) renameRefs(d, d.target.name, name);
    d.target = { name, part, frame: d.target?.frame ?? { pos: [0, 0, 0], rot: [0, 0, 0] } };
    this.nameDraft = null;
    this.ctx.history.apply(d, `target ${name}`);
  }

  /** The name typed for the next instance of `part`, or '' (cleared once the instance exists). */
  private takeName(part: string): string {
    return this.nameDraft?.part === part ? this.nameDraft.name.trim() : '';
  }
  private nameFree(d: Design, name: string): boolean {
    return !instances(d).some((i) => i.name === name) && !d.environment.some((e) => e.name === name);
  }

  selectPart(name: string): void {
    this.ctx.selection.set(name, null);
    void this.updateScene();
    this.panels.render();
  }

  // ---------------------------------------------------------------- solve
  private solving: AbortController | null = null;

  /** Stops waiting for a running solve (the server finishes it on its own; its answer is dropped). */
  cancelSolve(): void { this.solving?.abort(); }

  async solve(): Promise<void> {
    if (this.solving) { this.cancelSolve(); return; }
    this.panels.solveBusy(true);
    const ctl = new AbortController();
    this.solving = ctl;
    try {
      this.lastSolve = await this.api.solve(designToYaml(this.design), ctl.signal);
      this.solving = null;
      this.panels.solveBusy(false);
      this.panels.solveResult(this.lastSolve, null);
      await this.updateScene();
      await this.settle();
      this.panels.render();
      return;
    } catch (e) {
      this.lastSolve = null;
      if (isAbort(e)) this.panels.solveCancelled(); else this.panels.solveResult(null, e as ApiError);
    } finally {
      if (this.solving === ctl) this.solving = null;
      this.panels.solveBusy(false);
    }
    await this.updateScene();
    this.panels.render();
  }

  private async downloadGlb(): Promise<void> {
    this.ctx.status('solving for .glb…');
    try { download(`${fileStem(this.design.name)}.glb`, await this.api.solveGlb(designToYaml(this.design)), 'model/gltf-binary'); this.ctx.status(''); }
    catch (e) { this.ctx.status(''); this.ctx.message(`.glb export failed: ${(e as Error).message}`); }
  }
}

/** Closest pair of vertices of two meshes (world coordinates); meshes are subsampled to ≤ 1500 vertices each. */
function closestPoints(a: THREE.Mesh, b: THREE.Mesh): [THREE.Vector3, THREE.Vector3] {
  const pts = (m: THREE.Mesh) => {
    const pos = m.geometry.getAttribute('position');
    const step = Math.max(1, Math.floor(pos.count / 1500));
    const out: THREE.Vector3[] = [];
    for (let i = 0; i < pos.count; i += step) out.push(new THREE.Vector3().fromBufferAttribute(pos, i).applyMatrix4(m.matrixWorld));
    return out;
  };
  const pa = pts(a), pb = pts(b);
  let best = Infinity, ba = pa[0], bb = pb[0];
  for (const x of pa) for (const y of pb) { const d = x.distanceToSquared(y); if (d < best) { best = d; ba = x; bb = y; } }
  return [ba.clone(), bb.clone()];
}

/** "18.0 mm off, tilt 0.0°, twist 0.0° about the vertical" from a solve's target error. */
export function describeError(e: { pos_error_mm: number; rot_error_deg: number; tilt_deg: number; twist_deg: number; twist_free: boolean }): string {
  const twist = e.twist_free ? 'twist free (not asked for)' : `twist ${e.twist_deg.toFixed(1)}° about the vertical`;
  return `${e.pos_error_mm.toFixed(1)} mm off, tilt ${e.tilt_deg.toFixed(1)}°, ${twist}`;
}

/** The connect steps of a check, in connection order. */
export function connectSteps(c: CheckResult): CheckStep[] { return c.steps.filter((s) => s.text.startsWith('connect ')); }
function looseSpec(e: EnvItem, prim: string): Record<string, unknown> | undefined { return (e.primitives ?? {})[prim] as Record<string, unknown> | undefined; }
function frameOfSpec(f: any): Frame { return { pos: (f?.pos ?? [0, 0, 0]).map(Number) as Vec3, rot: (f?.rot ?? [0, 0, 0]).map(Number) as Vec3 }; }
