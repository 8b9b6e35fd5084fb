// The editor: wires the design model, the API, the 3D view and the panels together.
import './style.css';
import * as THREE from 'three';
import { api, ApiError } from './api';
import type { CheckResult, CheckStep, Compat, Frame, MeshData, PartInfo, PartMesh, PlacedPart, PrimRef, SolveResult, Vec3 } from './api';
import { History, Inventory, cloneDesign, countOf, emptyDesign, freshName, instances, removeInstance } from './model';
import type { Connection, Design, EnvItem } from './model';
import { designToYaml, parseDesign } from './yamlio';
import { designToPython } from './python';
import { SceneView, frameMatrix } from './scene';
import type { ScenePart } from './scene';
import { lazyThumbnail } from './thumbs';
import { renderTree } from './tree';
import { el, frameEditor, download } from './ui';

// ---------------------------------------------------------------- state
let library: PartInfo[] = [];
const partByName = new Map<string, PartInfo>();
const meshCache = new Map<string, Promise<PartMesh>>();
const inventory = new Inventory();
let selectedLibPart: string | null = null;
/** First picked primitive: either in the scene ("eyehook1.hook") or in the library panel. */
let pick: { scene?: string; lib?: { part: string; prim: string } } | null = null;
let compat = new Map<string, Compat>(); // key: scene "inst.prim" or "lib:Part.prim"
let selected: { part: string | null; prim: string | null } = { part: null, prim: null };
let lastCheck: CheckResult | null = null;
let lastSolve: SolveResult | null = null;
let failed: { conn: Connection; step: CheckStep | null; message: string; check: CheckResult | null } | null = null;
let checkSeq = 0;
/** The name typed for the next new instance of the selected library part (kept across re-renders). */
let nameDraft: { part: string; name: string } | null = null;
/** Parameters typed for the next new instance of a parametric part, per part. */
const paramDraft = new Map<string, Record<string, number>>();
/** Table 1 by primitive type (union of the library's `connects_to` lists), for loose primitives. */
const typeConnects = new Map<string, Set<string>>();
const primMeshCache = new Map<string, Promise<MeshData>>();
let pending = 0;
/** Counts running async UI operations so tests (and the status line) can tell when the editor is idle. */
function track<T>(p: Promise<T>): Promise<T> {
  pending++;
  return p.finally(() => { pending--; });
}

const $ = (id: string) => document.getElementById(id)!;
const view = new SceneView($('view'));
const history = new History(emptyDesign(), (_d, label) => {
  lastSolve = null; failed = null;
  $('solve-result').innerHTML = '<p class="hint">Not solved since the last change; press Solve.</p>';
  $('solve-result').dataset.state = 'stale';
  void track(refresh(label));
});
const design = () => history.current;

function message(text: string, kind: 'error' | 'info' = 'error'): void {
  const m = $('message');
  m.textContent = text; m.className = kind; m.hidden = !text;
}

// ---------------------------------------------------------------- helpers
function partInfo(type: string): PartInfo | undefined {
  return partByName.get(type) ?? library.find((p) => p.aliases.includes(type));
}
function meshOf(type: string, params?: Record<string, number>): Promise<PartMesh> {
  const key = type + JSON.stringify(params ?? {});
  if (!meshCache.has(key)) meshCache.set(key, api.mesh(partInfo(type)?.name ?? type, params));
  return meshCache.get(key)!;
}
function typeOfInstance(name: string): string | undefined {
  return instances(design()).find((i) => i.name === name)?.part ?? (looseEnv(name) ? 'loose primitives' : undefined);
}
/** An environment made of loose primitives (no library part). */
function looseEnv(name: string): EnvItem | undefined { return design().environment.find((e) => e.name === name && !e.part && e.primitives); }
function looseSpec(e: EnvItem, prim: string): Record<string, unknown> | undefined { return (e.primitives ?? {})[prim] as Record<string, unknown> | undefined; }
/** The primitive type of a scene key ("eyehook1.hook" → hook, "table.surface" → surface). */
function primTypeOf(key: string): string | undefined {
  const [inst, prim] = key.split('.');
  const e = looseEnv(inst);
  if (e) { const t = looseSpec(e, prim)?.type; return t === undefined ? undefined : String(t); }
  return partInfo(typeOfInstance(inst) ?? '')?.primitives.find((p) => p.name === prim)?.type;
}
const isLooseKey = (key: string) => !!looseEnv(key.split('.')[0]);
function frameOfSpec(f: any): Frame { return { pos: (f?.pos ?? [0, 0, 0]).map(Number) as Vec3, rot: (f?.rot ?? [0, 0, 0]).map(Number) as Vec3 }; }
/** Meshes of a loose-primitive environment, each placed by the primitive's own frame inside the part. */
async function looseMeshOf(e: EnvItem): Promise<{ mesh: PartMesh; primTypes: Record<string, string> }> {
  const mesh: PartMesh = { name: e.name, body: { vertices: [], faces: [] }, primitives: {} };
  const primTypes: Record<string, string> = {};
  for (const [prim, raw] of Object.entries(e.primitives ?? {})) {
    const spec = raw as Record<string, unknown>;
    const type = String(spec.type ?? '');
    const sizes: Record<string, number> = {};
    for (const [k, v] of Object.entries(spec)) if (k !== 'type' && k !== 'frame') sizes[k] = Number(v);
    const key = type + JSON.stringify(sizes);
    if (!primMeshCache.has(key)) primMeshCache.set(key, api.primMesh(type, sizes));
    let m: MeshData;
    try { m = await primMeshCache.get(key)!; } catch (err) { primMeshCache.delete(key); message(`cannot draw ${e.name}.${prim}: ${(err as Error).message}`); continue; }
    const mat = frameMatrix(frameOfSpec(spec.frame));
    const v = new THREE.Vector3(), out: number[] = [];
    for (let i = 0; i < m.vertices.length; i += 3) { v.set(m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]).applyMatrix4(mat); out.push(v.x, v.y, v.z); }
    mesh.primitives[prim] = { vertices: out, faces: m.faces };
    primTypes[prim] = type;
  }
  return { mesh, primTypes };
}
function refOf(key: string): PrimRef | null {
  const [inst, prim] = key.split('.');
  const i = instances(design()).find((x) => x.name === inst);
  if (!i) return null;
  const info = partInfo(i.part);
  return { part: info?.name ?? i.part, primitive: prim, ...(i.params ? { params: i.params } : {}) };
}
const fmt = (x: number, d = 1) => x.toFixed(d);

/** The frame of a part whose primitive `prim` sits at world frame `f`. */
function partFrameFromPrimFrame(type: string, prim: string | undefined, f: Frame): Frame {
  const info = partInfo(type);
  const p = prim ? info?.primitives.find((q) => q.name === prim || (prim === 'hole' && q.name === 'ring')) : info?.primitives[0];
  if (!p) return f;
  const m = frameMatrix(f).multiply(frameMatrix(p.frame).invert());
  const e = new THREE.Euler().setFromRotationMatrix(m, 'ZYX');
  const pos = new THREE.Vector3().setFromMatrixPosition(m);
  const d = 180 / Math.PI;
  return { pos: [pos.x, pos.y, pos.z], rot: [e.x * d, e.y * d, e.z * d] };
}

// ---------------------------------------------------------------- check & scene
async function runCheck(d: Design): Promise<CheckResult | null> {
  if (!d.environment.length) return null;
  return api.check(designToYaml(d));
}

/** The connect steps of a check, in connection order. */
function connectSteps(c: CheckResult): CheckStep[] { return c.steps.filter((s) => s.text.startsWith('connect ')); }

async function refresh(_label: string): Promise<void> {
  const seq = ++checkSeq;
  renderPanels();
  try {
    const c = await runCheck(design());
    if (seq !== checkSeq) return;
    lastCheck = c;
  } catch (e) {
    if (seq !== checkSeq) return;
    lastCheck = null;
    $('check-diags').textContent = e instanceof ApiError ? `cannot read design: ${e.message}` : String(e);
  }
  await updateScene();
  renderPanels();
}

async function updateScene(): Promise<void> {
  const d = design();
  let placed: PlacedPart[] = lastSolve?.parts ?? lastCheck?.parts ?? [];
  const bad = new Set<string>();
  if (failed?.step?.best_part_frames && failed.check) {
    placed = failed.check.parts.map((p, i) => ({ ...p, frame: failed!.step!.best_part_frames![i] ?? p.frame }));
    bad.add(failed.conn.a); bad.add(failed.conn.b);
  }
  const parts: ScenePart[] = [];
  const seen = new Set<string>();
  const add = async (name: string, type: string, frame: Frame, ghost: boolean, params?: Record<string, number>) => {
    seen.add(name);
    const mesh = await meshOf(type, params);
    const info = partInfo(type);
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
    const { mesh, primTypes } = await looseMeshOf(e);
    parts.push({ name: e.name, type: 'Environment', frame: placed.find((p) => p.name === e.name)?.frame ?? e.frame, mesh, primTypes });
  }
  // environment and target that the check did not place yet: show them where the user put them
  for (const e of d.environment) if (e.part && !seen.has(e.name)) await add(e.name, e.part, e.frame, false);
  if (d.target && !seen.has(d.target.name)) await add(d.target.name, d.target.part, partFrameFromPrimFrame(d.target.part, d.target.primitive, d.target.frame), true);
  view.setParts(parts);
  const slipping = slippingConnections();
  view.clearPrimState();
  for (const key of view.primMeshes.keys()) {
    const c = compat.get(key);
    view.setPrimState(key, {
      dim: !!pick && !!c && !c.ok, picked: pick?.scene === key, selected: selected.prim === key,
      bad: bad.has(key) || slipping.some((i) => d.connections[i].a === key || d.connections[i].b === key),
    });
  }
  view.selectedPart = selected.part;
  view.restyle();
  if (!sceneFramed && parts.length) { sceneFramed = true; view.view('iso'); }
}
let sceneFramed = false;

function slippingConnections(): number[] {
  if (!lastSolve) return [];
  const out: number[] = [];
  design().connections.forEach((c, i) => {
    if (lastSolve!.slipping.some((s) => (s.includes(c.a) && s.includes(c.b)) || s.includes(c.a) || s.includes(c.b))) out.push(i);
  });
  return out;
}

// ---------------------------------------------------------------- picking & connecting
/** Table 1 by primitive type only (for loose primitives, which /api/compatible does not know). */
function typeRule(a: string | undefined, b: string | undefined): Compat {
  if (!a || !b) return { ok: true, reason: 'sizes are checked when you connect' };
  const ok = typeConnects.get(a)?.has(b) ?? false;
  return ok ? { ok, reason: `${a} – ${b}: allowed by Table 1; sizes are checked when you connect` }
    : { ok, reason: `a ${a} cannot connect to a ${b} (Table 1); sizes are checked when you connect` };
}

async function computeCompat(): Promise<void> {
  compat = new Map();
  if (!pick) return;
  let a: PrimRef | null;
  let aType: string | undefined;
  const lib = selectedLibPart ? partInfo(selectedLibPart) : undefined;
  if (pick.scene) { a = isLooseKey(pick.scene) ? null : refOf(pick.scene); aType = primTypeOf(pick.scene); }
  else {
    a = { part: pick.lib!.part, primitive: pick.lib!.prim };
    const pd = paramDraft.get(pick.lib!.part); if (pd && Object.keys(pd).length) a.params = pd;
    aType = partInfo(pick.lib!.part)?.primitives.find((p) => p.name === pick!.lib!.prim)?.type;
  }
  const keys: string[] = [], refs: PrimRef[] = [];
  for (const key of view.primMeshes.keys()) {
    if (key === pick.scene) continue;
    if (!a || isLooseKey(key)) { compat.set(key, typeRule(aType, primTypeOf(key))); continue; }
    const r = refOf(key); if (r) { keys.push(key); refs.push(r); }
  }
  if (lib) for (const p of lib.primitives) {
    if (!a) { compat.set(`lib:${lib.name}.${p.name}`, typeRule(aType, p.type)); continue; }
    keys.push(`lib:${lib.name}.${p.name}`); refs.push({ part: lib.name, primitive: p.name });
  }
  if (!refs.length || !a) return;
  const res = await api.compatible(a, refs);
  res.forEach((r, i) => compat.set(keys[i], r));
}

async function pickScene(key: string): Promise<void> {
  selected = { part: key.split('.')[0], prim: key };
  if (!pick) { pick = { scene: key }; await afterPickChange(); return; }
  if (pick.scene === key) { pick = null; await afterPickChange(); return; }
  const first = pick; pick = null;
  if (first.scene) await connect(first.scene, key, null);
  else await connect(null, key, first.lib!);
}

async function pickLibrary(part: string, prim: string): Promise<void> {
  if (!pick) { pick = { lib: { part, prim } }; await afterPickChange(); return; }
  if (pick.lib) {
    if (pick.lib.part === part && pick.lib.prim === prim) { pick = null; await afterPickChange(); return; }
    message('Pick the second primitive in the scene (two library primitives cannot be connected).');
    return;
  }
  const first = pick.scene!; pick = null;
  await connect(null, first, { part, prim });
}

async function afterPickChange(): Promise<void> {
  message('');
  await computeCompat();
  $('pick-label').textContent = pick ? `Picked: ${pick.scene ?? `${pick.lib!.part}.${pick.lib!.prim} (new part)`} — pick a second primitive to connect (Esc cancels)` : '';
  await updateScene();
  renderPanels();
}

/** Connect `a` (scene) or a new instance of `lib` with scene primitive `b`; keep it only if the check accepts it. */
async function connect(a: string | null, b: string, lib: { part: string; prim: string } | null): Promise<void> {
  const next = cloneDesign(design());
  if (lib) {
    const owned = inventory.limit(lib.part);
    if (owned !== undefined && countOf(next, lib.part) >= owned) {
      message(`Inventory: you own ${owned} ${lib.part}${owned === 1 ? '' : 's'} and all are used; cannot add another.`);
      await afterPickChange(); message(`Inventory: you own ${owned} ${lib.part} and all ${owned} are already in the design; cannot add another.`);
      return;
    }
    let name = (nameDraft?.part === lib.part ? nameDraft.name.trim() : '') || freshName(next, lib.part.toLowerCase());
    if (instances(next).some((i) => i.name === name) || next.environment.some((e) => e.name === name)) name = freshName(next, name.replace(/\d+$/, ''));
    const pd = paramDraft.get(lib.part);
    next.parts.push(pd && Object.keys(pd).length ? { name, part: lib.part, params: { ...pd } } : { name, part: lib.part });
    a = `${name}.${lib.prim}`;
  }
  const conn: Connection = { a: a!, b };
  next.connections.push(conn);
  setStatus('checking…');
  let c: CheckResult | null = null;
  try { c = await runCheck(next); } catch (e) {
    failed = { conn, step: null, message: e instanceof ApiError ? e.message : String(e), check: null };
  }
  setStatus('');
  if (c) {
    const step = connectSteps(c)[next.connections.length - 1] ?? null;
    if (step && step.accepted) {
      compat = new Map(); $('pick-label').textContent = '';
      if (lib) nameDraft = null;
      history.apply(next, `connect ${conn.a} – ${conn.b}`);
      return;
    }
    const msg = step ? (step.diagnostics.map((d) => d.message).join('; ') || (step.skipped ? 'skipped because an earlier step failed' : 'rejected')) : 'rejected';
    failed = { conn, step, message: msg, check: c };
  }
  compat = new Map(); $('pick-label').textContent = '';
  await updateScene();
  renderPanels();
}

// ---------------------------------------------------------------- solve
async function solve(): Promise<void> {
  const btn = $('solve') as HTMLButtonElement;
  btn.disabled = true; btn.textContent = 'Solving…';
  $('solve-result').innerHTML = '<p class="busy" data-testid="solve-busy">Solving… (reaching the target, then relaxing under gravity)</p>';
  $('solve-result').dataset.state = 'busy';
  try {
    lastSolve = await api.solve(designToYaml(design()));
    const t = lastSolve.target;
    $('solve-result').innerHTML = '';
    $('solve-result').append(
      el('div', { class: `verdict ${lastSolve.stable ? 'stable' : 'falls'}`, 'data-testid': 'verdict' }, lastSolve.stable ? 'STABLE' : 'FALLS APART'),
      el('div', { 'data-testid': 'target-error' }, t ? `Target error: ${fmt(t.pos_error_mm)} mm, ${fmt(t.rot_error_deg)}°` : 'No target'),
      el('div', { class: 'hint' }, `${lastSolve.termination}: ${lastSolve.message}`),
      ...lastSolve.slipping.map((s) => el('div', { class: 'diag', 'data-testid': 'slipping' }, `slipping: ${s}`)),
    );
    $('solve-result').dataset.state = lastSolve.stable ? 'stable' : 'falls';
  } catch (e) {
    lastSolve = null;
    const err = e as ApiError;
    const what = err.status === 422 ? 'Infeasible' : err.status === 503 ? 'Timed out' : 'Error';
    $('solve-result').innerHTML = '';
    $('solve-result').append(el('div', { class: 'verdict falls', 'data-testid': 'verdict' }, what),
      ...(err.diagnostics?.length ? err.diagnostics.map((d) => el('div', { class: 'diag' }, d.text)) : [el('div', { class: 'diag' }, err.message)]));
    $('solve-result').dataset.state = 'error';
  } finally {
    btn.disabled = false; btn.textContent = 'Solve';
  }
  await updateScene();
  renderPanels();
}

// ---------------------------------------------------------------- panels
function setStatus(s: string): void { $('status').textContent = s; }

function renderLibrary(): void {
  const q = ($('part-search') as HTMLInputElement).value.trim().toLowerCase();
  const host = $('library');
  for (const item of host.children) {
    const name = (item as HTMLElement).dataset.part!;
    const info = partByName.get(name)!;
    const hay = [info.name, ...info.aliases, info.description, info.category].join(' ').toLowerCase();
    (item as HTMLElement).hidden = !!q && !hay.includes(q);
    item.classList.toggle('selected', name === selectedLibPart);
  }
}

function buildLibrary(): void {
  const host = $('library'); host.innerHTML = '';
  for (const p of library) {
    const img = el('img', { alt: p.name }) as HTMLImageElement;
    const item = el('div', { class: 'lib-item', 'data-testid': `lib-part-${p.name}`, 'data-part': p.name }, img,
      el('div', {}, el('b', {}, p.name), el('small', {}, [p.category, p.aliases.length ? `aka ${p.aliases.join(', ')}` : '', p.description].filter(Boolean).join(' · '))));
    item.addEventListener('click', () => { selectedLibPart = p.name; renderLibrary(); renderPrimPanel(); if (pick) void afterPickChange(); });
    host.appendChild(item);
    lazyThumbnail(p, img);
  }
}

function shapeSummary(shape: Record<string, number>): string {
  return Object.entries(shape).map(([k, v]) => `${k} ${+v.toFixed(2)}`).join(', ');
}

function renderPrimPanel(): void {
  const body = $('prim-panel-body'); body.innerHTML = '';
  const info = selectedLibPart ? partInfo(selectedLibPart) : undefined;
  if (!info) { body.append(el('p', { class: 'hint' }, 'Select a part in the library.')); return; }
  const d = design();
  const owned = inventory.limit(info.name);
  const draft = nameDraft?.part === info.name ? nameDraft.name : freshName(d, info.name.toLowerCase());
  const nameInput = el('input', { id: 'new-instance-name', 'data-testid': 'new-instance-name', value: draft }) as HTMLInputElement;
  nameInput.addEventListener('input', () => { nameDraft = { part: info.name, name: nameInput.value }; });
  const ownedInput = el('input', { type: 'number', min: '0', id: 'owned-count', 'data-testid': 'owned-count', placeholder: 'unlimited', value: owned === undefined ? '' : String(owned), style: 'width:80px' }) as HTMLInputElement;
  ownedInput.addEventListener('change', () => { inventory.set(info.name, ownedInput.value === '' ? undefined : Number(ownedInput.value)); renderPanels(); });
  body.append(
    el('div', {}, el('b', { 'data-testid': 'prim-panel-part' }, info.name), ` — ${info.description}`),
    el('div', { class: 'hint' }, `in design: ${countOf(d, info.name)}; owned: `, ownedInput),
    el('div', {}, 'new instance name ', nameInput),
    ...paramFields(info, paramDraft.get(info.name) ?? defaultParams(info), 'new-param', (vals) => { paramDraft.set(info.name, vals); if (pick) void track(afterPickChange()); }),
    el('div', {},
      button('Set as environment', 'set-environment', () => setEnvironment(info.name)),
      button('Set as target', 'set-target', () => setTarget(info.name))),
    el('p', { class: 'hint' }, 'Click a primitive, then one in the scene, to add a new instance connected there.'),
  );
  for (const p of info.primitives) {
    const key = `lib:${info.name}.${p.name}`;
    const c = compat.get(key);
    const item = el('div', {
      class: 'prim-item' + (pick && c && !c.ok ? ' dim' : '') + (pick?.lib?.part === info.name && pick.lib.prim === p.name ? ' picked' : ''),
      'data-testid': `lib-prim-${p.name}`, title: pick && c && !c.ok ? c.reason : p.description,
    }, el('span', {}, el('b', {}, p.name), ` ${p.type}${p.closed ? ' (closed)' : ''}`), el('small', {}, shapeSummary(p.shape)));
    item.addEventListener('click', () => void track(pickLibrary(info.name, p.name)));
    body.append(item);
  }
}

function defaultParams(info: PartInfo): Record<string, number> {
  return Object.fromEntries(info.params.map((p) => [p.name, p.default]));
}

/** Numeric fields for a parametric part's parameters (schema min/max/default/unit); onChange gets all values. */
function paramFields(info: PartInfo, values: Record<string, number>, testid: string, onChange: (v: Record<string, number>) => void): HTMLElement[] {
  return info.params.map((p) => {
    const input = el('input', {
      type: 'number', min: String(p.min), max: String(p.max), step: 'any', value: String(values[p.name] ?? p.default),
      'data-testid': `${testid}-${p.name}`, title: `${p.doc} (${p.min}–${p.max} ${p.unit}, default ${p.default})`, style: 'width:80px',
    }) as HTMLInputElement;
    input.addEventListener('change', () => {
      const x = Number(input.value);
      if (input.value === '' || Number.isNaN(x) || x < p.min || x > p.max) {
        message(`${info.name} ${p.name} must be between ${p.min} and ${p.max} ${p.unit}`);
        input.value = String(values[p.name] ?? p.default); return;
      }
      message('');
      onChange({ ...defaultParams(info), ...values, [p.name]: x });
    });
    return el('div', { class: 'param-field' }, `${p.name} `, input, ` ${p.unit}`);
  });
}

function button(text: string, testid: string, onClick: () => void, extra: Record<string, string> = {}): HTMLButtonElement {
  const b = el('button', { 'data-testid': testid, ...extra }, text) as HTMLButtonElement;
  b.addEventListener('click', onClick);
  return b;
}

function setEnvironment(part: string): void {
  const d = cloneDesign(design());
  const owned = inventory.limit(part);
  if (owned !== undefined && countOf(d, part) >= owned) { message(`Inventory: you own ${owned} ${part}; cannot add another.`); return; }
  const name = freshName(d, 'env');
  d.environment.push({ name, part, frame: { pos: [0, 0, 0], rot: [0, 0, 0] } });
  history.apply(d, `environment ${name}`);
}

function setTarget(part: string): void {
  const d = cloneDesign(design());
  const owned = inventory.limit(part);
  const already = d.target ? 1 : 0;
  if (owned !== undefined && countOf(d, part) - (d.target?.part === part ? already : 0) >= owned) { message(`Inventory: you own ${owned} ${part}; cannot add another.`); return; }
  const name = d.target?.name ?? freshName(d, 'target');
  d.target = { name, part, frame: d.target?.frame ?? { pos: [0, 0, 0], rot: [0, 0, 0] } };
  history.apply(d, `target ${name}`);
}

function renderFrames(): void {
  const host = $('frames'); host.innerHTML = '';
  const d = design();
  d.environment.forEach((e, i) => {
    host.append(frameEditor(`env-${i}`, `${e.name} (${e.part ?? 'primitives'}) — environment`, e.frame,
      (name) => { const n = cloneDesign(design()); const old = n.environment[i].name; n.environment[i].name = name; renameRefs(n, old, name); history.apply(n, 'rename'); },
      e.name,
      (f) => { const n = cloneDesign(design()); n.environment[i].frame = f; history.apply(n, `move ${e.name}`); },
      () => history.apply(removeInstance(design(), e.name), `delete ${e.name}`)));
  });
  if (d.target) {
    const t = d.target;
    host.append(frameEditor('target', `${t.name} (${t.part}) — target${t.primitive ? `, frame of ${t.primitive}` : ''}`, t.frame,
      (name) => { const n = cloneDesign(design()); const old = n.target!.name; n.target!.name = name; renameRefs(n, old, name); history.apply(n, 'rename'); },
      t.name,
      (f) => { const n = cloneDesign(design()); n.target!.frame = f; history.apply(n, `move ${t.name}`); },
      () => history.apply(removeInstance(design(), t.name), `delete ${t.name}`)));
  }
  if (!d.environment.length) host.append(el('p', { class: 'hint' }, 'Choose an environment part in the library and press "Set as environment"; the same for the target.'));
}

function renameRefs(d: Design, old: string, name: string): void {
  for (const c of d.connections) {
    if (c.a.split('.')[0] === old) c.a = name + c.a.slice(old.length);
    if (c.b.split('.')[0] === old) c.b = name + c.b.slice(old.length);
  }
}

function renderConnections(): void {
  const host = $('connections'); host.innerHTML = '';
  const d = design();
  const steps = lastCheck ? connectSteps(lastCheck) : [];
  const slipping = slippingConnections();
  d.connections.forEach((c, i) => {
    const step = steps[i];
    const rejected = step && !step.accepted;
    const li = el('li', { 'data-testid': `connection-${i}`, class: (rejected ? 'rejected' : '') + (slipping.includes(i) ? ' slipping' : '') },
      el('span', { class: 'conn-text', 'data-testid': `connection-text-${i}` }, `${c.a} – ${c.b}`), ' ',
      button(c.alignment === 'flip' ? 'flip' : 'default', `flip-${i}`, () => {
        const n = cloneDesign(design()); const wasSolved = !!lastSolve;
        if (n.connections[i].alignment === 'flip') delete n.connections[i].alignment; else n.connections[i].alignment = 'flip';
        history.apply(n, 'alignment');
        if (wasSolved) void track(solve()); // re-solve with the flipped alignment
      }, { title: 'alignment (click to toggle; re-solves when a solve result is shown)' }),
      button(c.fixed ? 'fixed' : 'free', `fixed-${i}`, () => { const n = cloneDesign(design()); if (n.connections[i].fixed) delete n.connections[i].fixed; else n.connections[i].fixed = true; history.apply(n, 'fixed'); }, { title: 'fixed connection (click to toggle)' }),
      button('✕', `delete-connection-${i}`, () => { const n = cloneDesign(design()); n.connections.splice(i, 1); history.apply(n, 'delete connection'); }, { title: 'delete connection' }),
      ...(step?.closes_cycle ? [el('div', { class: 'hint' }, `closes cycle ${step.cycles.join(', ')}`)] : []),
      ...(step ? step.diagnostics.map((x) => el('div', { class: 'diag' }, x.message)) : []),
      ...(slipping.includes(i) ? [el('div', { class: 'diag' }, 'slipping')] : []));
    host.append(li);
  });
  const f = $('failed-connect');
  f.hidden = !failed;
  f.innerHTML = '';
  if (failed) {
    f.append(el('div', {}, el('b', {}, 'Not added: '), `${failed.conn.a} – ${failed.conn.b}`),
      el('div', { class: 'diag', 'data-testid': 'failed-connect-message' }, failed.message),
      ...(failed.step?.best_part_frames ? [el('div', { class: 'hint' }, 'The 3D view shows the closest configuration the cycle search found; the failing primitives are red.')] : []),
      button('Dismiss', 'dismiss-failed', () => { failed = null; void updateScene(); renderPanels(); }));
  }
}

function renderInstances(): void {
  const host = $('instances'); host.innerHTML = '';
  for (const i of instances(design())) {
    const li = el('li', { class: selected.part === i.name ? 'selected' : '', 'data-testid': `instance-${i.name}` },
      el('span', {}, `${i.name} (${i.part}, ${i.role})`),
      button('select', `select-${i.name}`, () => selectPart(i.name)),
      button('delete', `delete-${i.name}`, () => history.apply(removeInstance(design(), i.name), `delete ${i.name}`)));
    const info = partInfo(i.part);
    if (i.role === 'part' && info?.params.length) {
      li.append(...paramFields(info, { ...defaultParams(info), ...(i.params ?? {}) }, `param-${i.name}`, (vals) => {
        const n = cloneDesign(design());
        const p = n.parts.find((x) => x.name === i.name); if (!p) return;
        if (JSON.stringify({ ...defaultParams(info), ...(p.params ?? {}) }) === JSON.stringify(vals)) return; // unchanged (e.g. a repeated change event)
        p.params = vals;
        history.apply(n, `params ${i.name}`);
      }));
    }
    host.append(li);
  }
}

function renderScenePrims(): void {
  const host = $('scene-prims'); host.innerHTML = '';
  for (const key of view.primMeshes.keys()) {
    const c = compat.get(key);
    const dim = !!pick && !!c && !c.ok;
    const type = primTypeOf(key) ?? '';
    const loose = isLooseKey(key);
    const bad = !!failed && (failed.conn.a === key || failed.conn.b === key);
    const li = el('li', {
      class: 'scene-prim' + (dim ? ' dim' : '') + (pick?.scene === key ? ' picked' : '') + (selected.prim === key ? ' selected' : '') + (bad ? ' bad' : ''),
      'data-testid': `scene-prim-${key}`, title: dim ? c!.reason : loose ? 'loose primitive: sizes are checked when you connect' : '',
    }, el('span', {}, key), el('small', {}, type + (loose ? ' (loose)' : '') + (dim ? ' — cannot connect' : '') + (bad ? ' — failed connect' : '')));
    li.addEventListener('click', () => void track(pickScene(key)));
    host.append(li);
  }
}

function renderCheckDiags(): void {
  const host = $('check-diags'); host.innerHTML = '';
  if (!lastCheck) { host.append(el('p', { class: 'hint' }, design().environment.length ? 'not checked' : 'no environment yet')); return; }
  host.append(el('div', { 'data-testid': 'check-valid' }, lastCheck.valid ? 'design valid' : 'design has problems'));
  for (const d of lastCheck.diagnostics) host.append(el('div', { class: d.severity === 'error' ? 'diag' : 'hint' }, d.text));
  for (const s of lastCheck.steps) if (!s.text.startsWith('connect ')) for (const d of s.diagnostics) host.append(el('div', { class: 'diag' }, `${s.text}: ${d.message}`));
}

function selectPart(name: string): void {
  selected = { part: name, prim: null };
  void updateScene();
  renderPanels();
}

function renderSelection(): void {
  let text = 'Nothing selected';
  if (selected.prim) {
    const [inst, prim] = selected.prim.split('.');
    const type = primTypeOf(selected.prim);
    void prim;
    text = `Selected: primitive ${selected.prim}${type ? ` (${type})` : ''} of part ${inst} (${typeOfInstance(inst) ?? '?'})`;
  } else if (selected.part) text = `Selected: part ${selected.part} (${typeOfInstance(selected.part) ?? '?'})`;
  $('selection-label').textContent = text;
}

function renderPanels(): void {
  ($('undo') as HTMLButtonElement).disabled = !history.canUndo();
  ($('redo') as HTMLButtonElement).disabled = !history.canRedo();
  renderLibrary(); renderPrimPanel(); renderFrames(); renderConnections(); renderInstances(); renderScenePrims(); renderCheckDiags(); renderSelection();
  renderTree($('tree'), design(), selected.part, selectPart);
}

// ---------------------------------------------------------------- wiring
view.onPick = (prim, part) => { if (prim) void track(pickScene(prim)); else { selected = { part, prim: null }; void updateScene(); renderPanels(); } };
view.onHover = (key, x, y) => {
  const t = $('tooltip');
  const c = key ? compat.get(key) : undefined;
  if (key && pick && c && !c.ok) { t.hidden = false; t.textContent = `${key}: ${c.reason}`; t.style.left = `${x + 12}px`; t.style.top = `${y + 12}px`; }
  else if (key) { t.hidden = false; t.textContent = isLooseKey(key) ? `${key} (loose ${primTypeOf(key) ?? ''}; sizes are checked when you connect)` : key; t.style.left = `${x + 12}px`; t.style.top = `${y + 12}px`; }
  else t.hidden = true;
};
$('part-search').addEventListener('input', renderLibrary);
$('undo').addEventListener('click', () => history.undo());
$('redo').addEventListener('click', () => history.redo());
$('solve').addEventListener('click', () => void track(solve()));
$('view-all').addEventListener('click', () => view.frameAll());
for (const v of ['top', 'front', 'side', 'iso'] as const) $(`view-${v}`).addEventListener('click', () => view.view(v));
$('save-yaml').addEventListener('click', () => download(`${design().name || 'design'}.yaml`, designToYaml(design()), 'application/x-yaml'));
$('export-python').addEventListener('click', () => download(`${(design().name || 'design').replace(/\W+/g, '_')}.py`, designToPython(design()), 'text/x-python'));
$('download-glb').addEventListener('click', async () => {
  setStatus('solving for .glb…');
  try { download(`${design().name || 'design'}.glb`, await api.solveGlb(designToYaml(design())), 'model/gltf-binary'); setStatus(''); }
  catch (e) { setStatus(''); message(`.glb export failed: ${(e as Error).message}`); }
});
$('open-file').addEventListener('change', (ev) => {
  const f = (ev.target as HTMLInputElement).files?.[0]; if (!f) return;
  // Counted as busy until the file is read and opened (tests wait on idle()).
  void track(f.text().then((text) => {
    openYaml(text);
    (ev.target as HTMLInputElement).value = '';
  }));
});
document.addEventListener('keydown', (e) => {
  if ((e.target as HTMLElement).tagName === 'INPUT') return;
  if (e.key === 'Escape') { pick = null; void afterPickChange(); }
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'z') { e.preventDefault(); if (e.shiftKey) history.redo(); else history.undo(); }
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'y') { e.preventDefault(); history.redo(); }
});

function openYaml(text: string): void {
  try { const d = parseDesign(text); sceneFramed = false; history.reset(d); message(''); }
  catch (e) { message(`cannot open design: ${(e as Error).message}`); }
}

// Test and scripting hooks (used by web/tests).
(window as any).__fabkit = {
  designYaml: () => designToYaml(design()),
  python: () => designToPython(design()),
  screenPointOf: (key: string) => view.screenPointOf(key),
  /** Scene keys ("inst.prim") that have a mesh in the 3D view, with their triangle counts. */
  sceneMeshes: () => Object.fromEntries([...view.primMeshes].map(([k, m]) => [k, (m.geometry.index?.count ?? 0) / 3])),
  setCamera: (pos: Vec3, target: Vec3) => { view.camera.position.set(...pos); view.controls.target.set(...target); view.controls.update(); view.render(); },
  ready: false,
  idle: () => pending === 0,
};

(async () => {
  setStatus('loading parts…');
  library = await api.parts();
  for (const p of library) {
    partByName.set(p.name, p);
    for (const q of p.primitives) { if (!typeConnects.has(q.type)) typeConnects.set(q.type, new Set()); for (const t of q.connects_to) typeConnects.get(q.type)!.add(t); }
  }
  buildLibrary();
  setStatus('');
  const initial = await api.design();
  if (initial) openYaml(initial); else await refresh('start');
  (window as any).__fabkit.ready = true;
  document.body.dataset.ready = '1';
})().catch((e) => { setStatus(`error: ${e.message}`); });
