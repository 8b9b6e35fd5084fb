// The hacks workspace's panels: parts library, primitives, environment & target, connections,
// solve result, connection tree, parts in the design, scene primitives, check.
import type { ApiError, PartInfo, SolveResult } from './api';
import { cloneDesign, countOf, defaultParams, freshName, instances, removeInstance, renameRefs } from './model';
import { lazyThumbnail, renderPreview } from './thumbs';
import { renderTree } from './tree';
import { el, frameEditor } from '../../shell/ui';
import { connectSteps, describeError } from './workspace';
import { PRIMITIVE_WORDS_DOC, categoryLabel, guidance, shapeSummary, shortName, terminationText, verdictText } from './words';
import type { HacksWorkspace } from './workspace';

const fmt = (x: number, d = 1) => x.toFixed(d);

export class Panels {
  private lib: HTMLElement;
  private category: HTMLSelectElement;
  private preview: HTMLElement;
  private search: HTMLInputElement;
  private primBody: HTMLElement;
  private frames: HTMLElement;
  private connections: HTMLElement;
  private failedBox: HTMLElement;
  private solveBox: HTMLElement;
  private tree: HTMLElement;
  private instances: HTMLElement;
  private scenePrims: HTMLElement;
  private checkDiags: HTMLElement;
  /** Why the last check could not run (shown in the Check panel). */
  checkError: string | null = null;

  constructor(private w: HacksWorkspace) {
    const p = w.ctx.panel.bind(w.ctx);
    const libBody = p('left', 'library', 'Parts library');
    this.search = el('input', { id: 'part-search', 'data-testid': 'part-search', placeholder: 'search parts…', type: 'search', title: 'Search names, aliases, descriptions and categories' }) as HTMLInputElement;
    this.category = el('select', { 'data-testid': 'category-filter', title: 'Show one category of parts' }) as HTMLSelectElement;
    this.lib = el('div', { id: 'library', 'data-testid': 'library' });
    this.preview = el('div', { class: 'part-preview', 'data-testid': 'part-preview' });
    this.preview.hidden = true;
    libBody.append(el('div', { class: 'lib-filters' }, this.search, this.category), this.lib);
    document.body.append(this.preview);
    this.search.addEventListener('input', () => this.renderLibrary());
    this.category.addEventListener('change', () => this.renderLibrary());
    this.primBody = el('div', { id: 'prim-panel-body', 'data-testid': 'prim-panel' });
    p('left', 'primitives', 'Primitives').append(this.primBody);
    this.frames = el('div', { id: 'frames', 'data-testid': 'frames' });
    p('right', 'frames', 'Environment & target').append(this.frames);
    this.connections = el('ol', { id: 'connections', 'data-testid': 'connections' });
    this.failedBox = el('div', { id: 'failed-connect', 'data-testid': 'failed-connect' });
    this.failedBox.hidden = true;
    p('right', 'connections', 'Connections', { hint: 'A connect that fails its check is not added to the design; its diagnostic is shown below the list.' })
      .append(this.connections, this.failedBox);
    this.solveBox = el('div', { id: 'solve-result', 'data-testid': 'solve-result' }, el('p', { class: 'hint' }, 'Not solved yet.'));
    p('right', 'solve', 'Solve result').append(this.toleranceRow(), this.solveBox);
    this.tree = el('div', { id: 'tree', 'data-testid': 'tree' });
    p('right', 'tree', 'Connection tree').append(this.tree);
    this.instances = el('ul', { id: 'instances', 'data-testid': 'instances' });
    p('right', 'instances', 'Parts in the design').append(this.instances);
    this.scenePrims = el('ul', { id: 'scene-prims', 'data-testid': 'scene-prims' });
    p('right', 'scene-prims', 'Scene primitives', { hint: 'Clicking an item is the same as clicking the primitive in the 3D view.' }).append(this.scenePrims);
    this.checkDiags = el('div', { id: 'check-diags', 'data-testid': 'check-diags' });
    p('right', 'check', 'Check').append(this.checkDiags);
  }

  render(): void {
    this.renderLibrary(); this.renderPrimPanel(); this.renderFrames(); this.renderConnections(); this.renderInstances();
    this.renderScenePrims(); this.renderCheckDiags();
    this.w.ctx.refreshSelectionLabel();
    const sel = this.w.ctx.selection.current;
    renderTree(this.tree, this.w.design, { node: sel.object, edge: this.w.selectedConnection() }, (n) => this.w.selectPart(n), (i) => this.w.selectConnection(i));
  }

  // ---------------------------------------------------------------- 3D view overlays
  pickLabel(): void {
    const pick = this.w.pick;
    // a library pick is named by the selection label; a scene pick gets the instruction here
    document.getElementById('pick-label')!.textContent = pick?.scene
      ? `Picked: ${pick.scene} — pick a second primitive to connect (Esc cancels)` : '';
  }

  hover(key: string | null, x: number, y: number): void {
    const t = document.getElementById('tooltip')!;
    const w = this.w;
    const c = key ? w.compat.get(key) : undefined;
    if (key && w.pick && c && !c.ok) t.textContent = `${key}: ${c.reason}`;
    else if (key) t.textContent = w.isLooseKey(key) ? `${key} (loose ${w.primTypeOf(key) ?? ''}; sizes are checked when you connect)` : key;
    t.hidden = !key;
    if (key) { t.style.left = `${x + 12}px`; t.style.top = `${y + 12}px`; }
  }

  // ---------------------------------------------------------------- solve result
  solveStale(): void {
    this.solveBox.className = '';
    this.solveBox.innerHTML = '<p class="hint">Not solved since the last change; press Solve.</p>';
    this.solveBox.dataset.state = 'stale';
  }

  solveBusy(busy: boolean): void {
    const btn = document.getElementById('solve') as HTMLButtonElement;
    btn.textContent = busy ? 'Cancel solve' : 'Solve';
    btn.title = busy ? 'Stop waiting for this solve (Esc)' : 'Reach the target, then relax under gravity';
    btn.classList.toggle('cancel', busy);
    if (busy) {
      this.solveBox.innerHTML = '';
      this.solveBox.className = '';
      this.solveBox.append(el('p', { class: 'busy', 'data-testid': 'solve-busy' }, 'Solving… (reaching the target, then relaxing under gravity) '),
        button('Cancel', 'cancel-solve', () => this.w.cancelSolve(), { title: 'Stop waiting for this solve; the design is unchanged' }));
      this.solveBox.dataset.state = 'busy';
    }
  }

  solveCancelled(): void {
    this.solveBox.innerHTML = '';
    this.solveBox.className = '';
    this.solveBox.append(el('p', { class: 'hint', 'data-testid': 'solve-cancelled' }, 'Solve cancelled; press Solve to run it again.'));
    this.solveBox.dataset.state = 'cancelled';
  }

  /** "On target within [25] mm and [10]°": what counts as doing what was asked. */
  private toleranceRow(): HTMLElement {
    const t = this.w.tolerance();
    const field = (testid: string, value: number, unit: string, title: string) => {
      const f = el('input', { type: 'number', min: '0', step: 'any', value: String(value), 'data-testid': testid, title, style: 'width:60px' }) as HTMLInputElement;
      f.addEventListener('change', () => {
        const mm = Number(mmField.value), deg = Number(degField.value);
        if (!(mm >= 0) || !(deg >= 0)) { this.w.ctx.message('The target tolerance must be a number ≥ 0.'); return; }
        this.w.setTolerance({ mm, deg });
      });
      return [f, ` ${unit}`] as const;
    };
    const [mmField, mmUnit] = field('tolerance-mm', t.mm, 'mm', 'How far (mm) the target may end up from its goal and still count as on target');
    const [degField, degUnit] = field('tolerance-deg', t.deg, '°', 'How much (degrees) the target may be rotated from its goal and still count as on target');
    return el('div', { class: 'hint tolerance' }, 'On target when within ', mmField, mmUnit, ' and ', degField, degUnit);
  }

  solveResult(r: SolveResult | null, err: ApiError | null): void {
    this.solveBox.innerHTML = '';
    if (r) {
      const t = r.target;
      const hasTarget = !!this.w.design.target && !!t;
      const on = hasTarget && this.w.onTarget(t);
      const tol = this.w.tolerance();
      // one colour for both questions: holds and on target (green), holds but misses (amber), falls (red)
      const state = !r.stable ? 'falls' : hasTarget && !on ? 'off' : 'stable';
      this.solveBox.append(
        el('div', { class: `verdict ${r.stable ? 'stable' : 'falls'}`, 'data-testid': 'verdict' }, verdictText(r)),
        ...(hasTarget ? [el('div', { class: `target-verdict ${on ? 'on' : 'off'}`, 'data-testid': 'target-verdict' },
          on ? `ON TARGET (within ${tol.mm} mm, ${tol.deg}°)` : `OFF TARGET (more than ${tol.mm} mm or ${tol.deg}° from the goal)`)] : []),
        el('div', { 'data-testid': 'target-error' }, hasTarget ? `Target error: ${fmt(t.pos_error_mm)} mm, ${fmt(t.rot_error_deg)}° — ${describeError(t)}` : 'No target'),
        ...(hasTarget && t.step1 ? [el('div', { class: 'hint', 'data-testid': 'target-error-step1' }, `before gravity (step 1): ${describeError(t.step1)}`)] : []),
        el('div', { class: 'hint', 'data-testid': 'termination' }, `Solver: ${terminationText(r.termination)}${r.message ? ` — ${r.message}` : ''}`),
        ...r.slipping.map((s) => el('div', { class: 'diag', 'data-testid': 'slipping' }, `slipping: ${s}`)),
        ...(r.remedy ? [el('div', { class: 'hint', 'data-testid': 'remedy' }, `To make it hold: ${r.remedy}`), ...this.remedyButton(r.remedy)] : []),
        ...(r.step1_parts?.length ? [button('Replay settling', 'replay-settle', () => void this.w.ctx.track(this.w.settle()), { title: 'Show again how the assembly moves from reaching for the target (step 1) to resting under gravity' })] : []),
      );
      this.solveBox.dataset.state = state;
      this.solveBox.className = `result-${state}`;
      return;
    }
    this.solveBox.className = 'result-falls';
    const e = err!;
    const what = e.status === 422 ? 'Infeasible' : e.status === 503 ? 'Timed out' : 'Error';
    this.solveBox.append(el('div', { class: 'verdict falls', 'data-testid': 'verdict' }, what),
      ...(e.diagnostics?.length ? e.diagnostics.map((d) => el('div', { class: 'diag' }, d.text)) : [el('div', { class: 'diag' }, e.message)]));
    this.solveBox.dataset.state = 'error';
  }

  // ---------------------------------------------------------------- library and primitives
  renderLibrary(): void {
    const q = this.search.value.trim().toLowerCase();
    const cat = this.category.value;
    for (const item of this.lib.children) {
      const name = (item as HTMLElement).dataset.part!;
      const info = this.w.partByName.get(name)!;
      const hay = [info.name, ...info.aliases, info.description, info.category, categoryLabel(info.category)].join(' ').toLowerCase();
      (item as HTMLElement).hidden = (!!q && !hay.includes(q)) || (!!cat && info.category !== cat);
      item.classList.toggle('selected', name === this.w.selectedLibPart);
    }
  }

  buildLibrary(): void {
    this.lib.innerHTML = '';
    const cats = [...new Set(this.w.library.map((p) => p.category))].sort();
    this.category.innerHTML = '';
    this.category.append(el('option', { value: '' }, 'all categories'), ...cats.map((c) => el('option', { value: c }, categoryLabel(c))));
    for (const p of this.w.library) {
      const img = el('img', { alt: p.name }) as HTMLImageElement;
      const item = el('div', { class: 'lib-item', 'data-testid': `lib-part-${p.name}`, 'data-part': p.name, role: 'button', tabindex: '0' }, img,
        el('div', {}, el('b', {}, p.name), el('small', {}, [categoryLabel(p.category), p.aliases.length ? `aka ${p.aliases.join(', ')}` : '', p.description].filter(Boolean).join(' · '))));
      item.title = [p.description, guidance(p.name)].filter(Boolean).join('\n');
      item.addEventListener('click', () => {
        this.w.selectedLibPart = p.name; this.renderLibrary(); this.renderPrimPanel();
        if (this.w.pick) void this.w.ctx.track(this.w.afterPickChange());
      });
      item.addEventListener('mouseenter', () => void this.showPreview(p, item));
      item.addEventListener('focus', () => void this.showPreview(p, item));
      item.addEventListener('mouseleave', () => { this.preview.hidden = true; });
      item.addEventListener('blur', () => { this.preview.hidden = true; });
      this.lib.appendChild(item);
      lazyThumbnail(this.w.api, p, img);
    }
  }

  /** A larger 3D rendering of the hovered library part, with its primitives, beside the library. */
  private async showPreview(p: PartInfo, item: HTMLElement): Promise<void> {
    const shown = p.name;
    this.previewFor = shown;
    const url = await renderPreview(this.w.api, p, 220);
    if (this.previewFor !== shown || !item.matches(':hover, :focus')) return;
    const box = this.preview;
    box.innerHTML = '';
    box.dataset.part = p.name;
    box.append(el('img', { src: url, width: '220', height: '220', alt: `${p.name} in 3D` }), el('b', {}, p.name),
      el('div', { class: 'hint' }, p.description),
      el('div', { class: 'hint' }, p.primitives.map((q) => `${q.name} (${q.type})`).join(', ')));
    const r = item.getBoundingClientRect();
    box.style.left = `${r.right + 8}px`;
    box.style.top = `${Math.max(4, Math.min(window.innerHeight - 330, r.top - 40))}px`;
    box.hidden = false;
  }
  private previewFor: string | null = null;

  renderPrimPanel(): void {
    const w = this.w;
    const body = this.primBody; body.innerHTML = '';
    const info = w.selectedLibPart ? w.partInfo(w.selectedLibPart) : undefined;
    if (!info) { body.append(el('p', { class: 'hint' }, 'Select a part in the library.')); return; }
    const d = w.design;
    const owned = w.inventory.limit(info.name);
    const draft = w.nameDraft?.part === info.name ? w.nameDraft.name : '';
    const fallback = freshName(d, shortName(info.name));
    const nameInput = el('input', { id: 'new-instance-name', 'data-testid': 'new-instance-name', value: draft, placeholder: fallback,
      title: `Name of the next instance of ${info.name}: as a part (empty: ${fallback}), environment (empty: ${freshName(d, 'env')}) or target (empty: ${d.target?.name ?? freshName(d, 'target')})` }) as HTMLInputElement;
    nameInput.addEventListener('input', () => { w.nameDraft = { part: info.name, name: nameInput.value }; });
    const ownedInput = el('input', { type: 'number', min: '0', id: 'owned-count', 'data-testid': 'owned-count', placeholder: 'unlimited', title: `How many ${info.name} you own: adding more is refused (empty: unlimited; kept in this browser)`, value: owned === undefined ? '' : String(owned), style: 'width:80px' }) as HTMLInputElement;
    ownedInput.addEventListener('change', () => w.setInventory(info.name, ownedInput.value === '' ? undefined : Number(ownedInput.value)));
    body.append(
      el('div', {}, el('b', { 'data-testid': 'prim-panel-part' }, info.name), ` — ${info.description}`),
      ...(guidance(info.name) ? [el('p', { class: 'hint guidance', 'data-testid': 'part-guidance' }, guidance(info.name)!)] : []),
      el('div', { class: 'hint' }, `in design: ${countOf(d, info.name)}; owned: `, ownedInput),
      el('div', {}, 'new instance name ', nameInput),
      ...this.paramFields(info, w.paramDraft.get(info.name) ?? defaultParams(info), 'new-param', (vals) => { w.paramDraft.set(info.name, vals); if (w.pick) void w.ctx.track(w.afterPickChange()); }),
      el('div', {},
        button('Set as environment', 'set-environment', () => w.setEnvironment(info.name), { title: `Add a ${info.name} fixed in the world, for the parts to hang from or rest on` }),
        button('Set as target', 'set-target', () => w.setTarget(info.name), { title: `Make a ${info.name} the thing to hold: where it should end up is its goal (drawn green)` })),
      el('p', { class: 'hint' }, 'Click a primitive, then one in the scene, to add a new instance connected there.'),
    );
    for (const p of info.primitives) {
      const key = `lib:${info.name}.${p.name}`;
      const c = w.compat.get(key);
      const item = el('div', {
        class: 'prim-item' + (w.pick && c && !c.ok ? ' dim' : '') + (w.pick?.lib?.part === info.name && w.pick.lib.prim === p.name ? ' picked' : ''),
        'data-testid': `lib-prim-${p.name}`, title: w.pick && c && !c.ok ? c.reason : p.description, role: 'button', tabindex: '0',
      }, el('span', {}, el('b', {}, p.name), ` ${p.type}${p.closed ? ' (closed)' : ''}`), el('small', {}, shapeSummary(p.shape)));
      if (!(w.pick && c && !c.ok)) item.title = `${p.description} — ${PRIMITIVE_WORDS_DOC[p.type] ?? p.type}. Click to pick it for a new ${info.name}, then click a primitive in the scene.`;
      item.addEventListener('click', () => void w.ctx.track(w.pickLibrary(info.name, p.name)));
      body.append(item);
    }
  }

  /** Numeric fields for a parametric part's parameters (schema min/max/default/unit); onChange gets all values. */
  private paramFields(info: PartInfo, values: Record<string, number>, testid: string, onChange: (v: Record<string, number>) => void): HTMLElement[] {
    return info.params.map((p) => {
      const input = el('input', {
        type: 'number', min: String(p.min), max: String(p.max), step: 'any', value: String(values[p.name] ?? p.default),
        'data-testid': `${testid}-${p.name}`, title: `${p.doc} (${p.min}–${p.max} ${p.unit}, default ${p.default})`, style: 'width:80px',
      }) as HTMLInputElement;
      input.addEventListener('change', () => {
        const x = Number(input.value);
        if (input.value === '' || Number.isNaN(x) || x < p.min || x > p.max) {
          this.w.ctx.message(`${info.name} ${p.name} must be between ${p.min} and ${p.max} ${p.unit}`);
          input.value = String(values[p.name] ?? p.default); return;
        }
        this.w.ctx.message('');
        onChange({ ...defaultParams(info), ...values, [p.name]: x });
      });
      return el('div', { class: 'param-field' }, `${p.name} `, input, ` ${p.unit}`);
    });
  }

  // ---------------------------------------------------------------- design panels
  private renderFrames(): void {
    const w = this.w, h = w.ctx.history;
    const host = this.frames; host.innerHTML = '';
    const d = w.design;
    d.environment.forEach((e, i) => {
      host.append(frameEditor(`env-${i}`, `${e.name} (${e.part ?? 'primitives'}) — environment`, e.frame,
        (name) => { const n = cloneDesign(w.design); const old = n.environment[i].name; n.environment[i].name = name; renameRefs(n, old, name); h.apply(n, 'rename'); },
        e.name,
        (f) => { const n = cloneDesign(w.design); n.environment[i].frame = f; h.apply(n, `move ${e.name}`); },
        () => h.apply(removeInstance(w.design, e.name), `delete ${e.name}`)));
    });
    if (d.target) {
      const t = d.target;
      host.append(frameEditor('target', `${t.name} (${t.part}) — target${t.primitive ? `, frame of ${t.primitive}` : ''}`, t.frame,
        (name) => { const n = cloneDesign(w.design); const old = n.target!.name; n.target!.name = name; renameRefs(n, old, name); h.apply(n, 'rename'); },
        t.name,
        (f) => { const n = cloneDesign(w.design); n.target!.frame = f; h.apply(n, `move ${t.name}`); },
        () => h.apply(removeInstance(w.design, t.name), `delete ${t.name}`)));
    }
    if (!d.environment.length) host.append(el('p', { class: 'hint' }, 'Choose an environment part in the library and press "Set as environment"; the same for the target.'));
  }

  /** Connection i the other way round (its alignment flipped), undoably; solved again if asked. */
  private turnConnection(i: number, solve: boolean): void {
    const w = this.w;
    const n = cloneDesign(w.design);
    if (n.connections[i].alignment === 'flip') delete n.connections[i].alignment; else n.connections[i].alignment = 'flip';
    w.ctx.history.apply(n, 'alignment');
    if (solve) void w.ctx.track(w.solve());
  }

  /** A button that makes the change a solve's remedy names (the connection of its two primitives). */
  private remedyButton(remedy: string): HTMLElement[] {
    const i = this.w.design.connections.findIndex((c) => remedy.includes(`${c.a} and ${c.b} `) || remedy.includes(`${c.b} and ${c.a} `));
    if (i < 0) return [];
    return [button('Turn it and solve', 'apply-remedy', () => this.turnConnection(i, true),
      { title: 'Turn that connection the other way round (its alignment) and solve again (undoable)' })];
  }

  private renderConnections(): void {
    const w = this.w, h = w.ctx.history;
    const host = this.connections; host.innerHTML = '';
    const d = w.design;
    const steps = w.lastCheck ? connectSteps(w.lastCheck) : [];
    const slipping = w.slippingConnections();
    d.connections.forEach((c, i) => {
      const step = steps[i];
      const rejected = step && !step.accepted;
      const text = el('span', { class: 'conn-text', 'data-testid': `connection-text-${i}`, title: 'Click to select this connection (Delete deletes it)', role: 'button', tabindex: '0' }, `${c.a} – ${c.b}`);
      text.addEventListener('click', () => w.selectConnection(i));
      const li = el('li', { 'data-testid': `connection-${i}`, class: (rejected ? 'rejected' : '') + (slipping.includes(i) ? ' slipping' : '') + (w.selectedConnection() === i ? ' selected' : '') },
        text, ' ',
        button(c.alignment === 'flip' ? 'alignment: flipped' : 'alignment: default', `flip-${i}`, () => {
          this.turnConnection(i, !!w.lastSolve); // re-solve with the flipped alignment
        }, { title: 'Which way round the two primitives meet: default, or flipped (turned over — e.g. an eye hook hanging from the other side of a rod). Click to switch; re-solves when a solve result is shown.' }),
        button(c.fixed ? 'joint: fixed' : 'joint: free', `fixed-${i}`, () => { const n = cloneDesign(w.design); if (n.connections[i].fixed) delete n.connections[i].fixed; else n.connections[i].fixed = true; h.apply(n, 'fixed'); }, { title: 'free: the connection may slide and turn when the assembly settles under gravity; fixed: it stays where step 1 put it (e.g. a hook you tape down). Click to switch.' }),
        button('✕', `delete-connection-${i}`, () => { const n = cloneDesign(w.design); n.connections.splice(i, 1); h.apply(n, 'delete connection'); }, { title: 'Delete this connection (undoable)', 'aria-label': `delete connection ${c.a} – ${c.b}` }),
        ...(step?.closes_cycle ? [el('div', { class: 'hint' }, `closes cycle ${step.cycles.join(', ')}`)] : []),
        ...(step ? step.diagnostics.map((x) => el('div', { class: 'diag' }, x.message)) : []),
        ...(slipping.includes(i) ? [el('div', { class: 'diag' }, 'slipping')] : []));
      host.append(li);
    });
    const f = this.failedBox, failed = w.failed;
    const wasHidden = f.hidden;
    f.hidden = !failed;
    f.innerHTML = '';
    if (failed) {
      const view = w.failure;
      f.append(el('div', {}, el('b', {}, failed.kind === 'inventory' ? 'Not added (inventory): ' : 'Not added: '), `${failed.conn.a} – ${failed.conn.b}`),
        el('div', { class: 'diag', 'data-testid': 'failed-connect-message' }, failed.message),
        ...(failed.step?.best_part_frames ? [el('div', { class: 'hint' }, `The 3D view shows the closest configuration the cycle search found; the failing primitives are red${view?.gap_mm != null ? `, the red line spans the ${view.gap_mm.toFixed(1)} mm gap` : ''}.`)] : []),
        ...(view?.suggestion ? [el('div', { class: 'suggestion', 'data-testid': 'failed-suggestion' }, view.suggestion)] : []),
        button('Dismiss', 'dismiss-failed', () => w.dismissFailed(), { title: 'Back to the design (the connection is not added)' }));
      if (wasHidden) f.scrollIntoView({ block: 'nearest' });
    }
  }

  private renderInstances(): void {
    const w = this.w, h = w.ctx.history;
    const host = this.instances; host.innerHTML = '';
    const sel = w.ctx.selection.current;
    for (const i of instances(w.design)) {
      const li = el('li', { class: sel.object === i.name ? 'selected' : '', 'data-testid': `instance-${i.name}` },
        el('span', { title: this.w.partInfo(i.part)?.description ?? '' }, `${i.name} (${i.part}, ${i.role})`),
        button('select', `select-${i.name}`, () => w.selectPart(i.name), { title: `Select ${i.name} (F frames it)` }),
        this.displayButton(i.name),
        button(w.ctx.scene.isolatedObjects()?.includes(i.name) ? 'show all' : 'isolate', `isolate-${i.name}`, () => {
          const scene = w.ctx.scene;
          scene.isolate(scene.isolatedObjects()?.includes(i.name) ? null : [i.name]);
          this.render();
        }, { title: `Show only ${i.name} (again: show everything)` }),
        button('delete', `delete-${i.name}`, () => h.apply(removeInstance(w.design, i.name), `delete ${i.name}`), { title: `Delete ${i.name} and its connections (undoable; also the Delete key)` }));
      const info = w.partInfo(i.part);
      if (i.role === 'part' && info?.params.length) {
        li.append(...this.paramFields(info, { ...defaultParams(info), ...(i.params ?? {}) }, `param-${i.name}`, (vals) => {
          const n = cloneDesign(w.design);
          const p = n.parts.find((x) => x.name === i.name); if (!p) return;
          if (JSON.stringify({ ...defaultParams(info), ...(p.params ?? {}) }) === JSON.stringify(vals)) return; // unchanged (e.g. a repeated change event)
          p.params = vals;
          h.apply(n, `params ${i.name}`);
        }));
      }
      host.append(li);
    }
  }

  /** Cycles how a part is shown: shown → see-through → hidden (view only; not part of the design). */
  private displayButton(name: string): HTMLButtonElement {
    const scene = this.w.ctx.scene;
    const mode = scene.displayOf(name);
    const text = { normal: 'shown', xray: 'see-through', hidden: 'hidden' }[mode];
    return button(text, `display-${name}`, () => {
      const next = mode === 'normal' ? 'xray' : mode === 'xray' ? 'hidden' : 'normal';
      if (scene.isolatedObjects() && mode === 'hidden') scene.isolate(null);
      scene.setDisplay(name, next);
      this.render();
    }, { title: `How ${name} is drawn: shown, see-through (clicks pass through it) or hidden; click to change` });
  }

  private renderScenePrims(): void {
    const w = this.w;
    const host = this.scenePrims; host.innerHTML = '';
    const sel = w.ctx.selection.current;
    for (const key of w.ctx.scene.pieces.keys()) {
      const c = w.compat.get(key);
      const dim = !!w.pick && !!c && !c.ok;
      const type = w.primTypeOf(key) ?? '';
      const loose = w.isLooseKey(key);
      const bad = !!w.failed && (w.failed.conn.a === key || w.failed.conn.b === key);
      const li = el('li', {
        class: 'scene-prim' + (dim ? ' dim' : '') + (w.pick?.scene === key ? ' picked' : '') + (sel.piece === key ? ' selected' : '') + (bad ? ' bad' : ''),
        'data-testid': `scene-prim-${key}`, title: dim ? c!.reason : loose ? 'loose primitive: sizes are checked when you connect' : `${key}: click to pick it for a connect (same as clicking it in the view)`, role: 'button', tabindex: '0',
      }, el('span', {}, key), el('small', {}, type + (loose ? ' (loose)' : '') + (dim ? ' — cannot connect' : '') + (bad ? ' — failed connect' : '')));
      li.addEventListener('click', () => void w.ctx.track(w.pickScene(key)));
      li.addEventListener('mouseenter', () => w.ctx.scene.setHover(key));
      li.addEventListener('mouseleave', () => w.ctx.scene.setHover(null));
      host.append(li);
    }
  }

  private renderCheckDiags(): void {
    const w = this.w;
    const host = this.checkDiags; host.innerHTML = '';
    if (this.checkError) { host.textContent = this.checkError; return; }
    const c = w.lastCheck;
    if (!c) { host.append(el('p', { class: 'hint' }, w.design.environment.length ? 'not checked' : 'no environment yet')); return; }
    host.append(el('div', { 'data-testid': 'check-valid' }, c.valid ? 'design valid' : 'design has problems'));
    for (const d of c.diagnostics) host.append(el('div', { class: d.severity === 'error' ? 'diag' : 'hint' }, d.text));
    for (const s of c.steps) if (!s.text.startsWith('connect ')) for (const d of s.diagnostics) host.append(el('div', { class: 'diag' }, `${s.text}: ${d.message}`));
  }
}

export function button(text: string, testid: string, onClick: () => void, extra: Record<string, string> = {}): HTMLButtonElement {
  const b = el('button', { 'data-testid': testid, ...extra }, text) as HTMLButtonElement;
  b.addEventListener('click', onClick);
  return b;
}
