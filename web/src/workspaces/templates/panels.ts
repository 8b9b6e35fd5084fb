// The templates workspace's panels: the template library (search, category, thumbnails, the
// sub-templates of each design, dragged into the view), the model's hierarchy, the selected
// node's controls, the composition (snapping, connections, "no connection found"), stability,
// the bill of materials and the downloads.
import type { DragAnswer, LibraryDesign, ModelState } from './api';
import { lazyThumbnail } from './thumbs';
import { el } from '../../shell/ui';
import { DRAG_MIME, STABLE_GREEN, UNSTABLE_RED, keyOf } from './workspace';
import type { TemplatesWorkspace } from './workspace';

const mm = (x: number) => `${Math.round(x * 10) / 10}`;
const usd = (x: number | null | undefined) => (x === null || x === undefined ? '—' : `$${x.toFixed(2)}`);
const CONTROL_WORDS: Record<string, string> = {
  center_x: 'move along x (left/right)', center_y: 'move along y (front/back)', center_z: 'move along z (up/down)',
  size_x: 'width (x)', size_y: 'depth (y)', size_z: 'height (z)',
};

export class Panels {
  private search: HTMLInputElement;
  private category: HTMLSelectElement;
  private lib: HTMLElement;
  private tree: HTMLElement;
  private controlsBox: HTMLElement;
  private steps: HTMLElement;
  private stability: HTMLElement;
  private bom: HTMLElement;
  private downloads: HTMLElement;
  private live: HTMLElement;
  private loads: HTMLElement;

  constructor(private w: TemplatesWorkspace) {
    const p = w.ctx.panel.bind(w.ctx);
    const libBody = p('left', 'template-library', 'Template library', { hint: 'Drag a design or one of its parts (a shelf, the legs) into the 3D view; it snaps to the model and is joined with connectors from the database.' });
    this.search = el('input', { type: 'search', 'data-testid': 'template-search', placeholder: 'search templates…', title: 'Search design names, descriptions and their parts' }) as HTMLInputElement;
    this.category = el('select', { 'data-testid': 'template-category', title: 'Show one category of designs' }) as HTMLSelectElement;
    this.lib = el('div', { 'data-testid': 'template-list', class: 'tmpl-list' });
    libBody.append(el('div', { class: 'lib-filters' }, this.search, this.category), this.lib);
    this.search.addEventListener('input', () => this.renderLibrary());
    this.category.addEventListener('change', () => this.renderLibrary());

    this.tree = el('div', { 'data-testid': 'model-tree', class: 'tmpl-tree' });
    const up = el('button', { 'data-testid': 'select-parent', title: 'Select the group the selection belongs to (walk up the hierarchy)' }, 'Up the hierarchy');
    up.addEventListener('click', () => {
      const path = w.selectedPath();
      if (path === null || path === '') return;
      void w.selectNode(w.node(path)?.parent ?? '');
    });
    const remove = el('button', { 'data-testid': 'remove-selected', title: 'Remove the selected part or group with its connectors (Delete)' }, 'Remove');
    remove.addEventListener('click', () => w.removeSelected());
    p('right', 'model-tree', 'Model', { hint: 'Click a part in the view to select it; click it again to select its group.' })
      .append(el('div', { class: 'row' }, up, remove), this.tree);

    this.controlsBox = el('div', { 'data-testid': 'controls' });
    this.live = el('div', { 'data-testid': 'drag-live', class: 'hint' });
    p('right', 'controls', 'Controls', { hint: 'Arrows move the selection, spheres resize it; directions its constraints fix have no handle. Each drag is solved so that the model stays buildable.' })
      .append(this.controlsBox, this.live);

    this.steps = el('div', { 'data-testid': 'composition' });
    p('right', 'composition', 'Composition').append(this.steps);
    this.stability = el('div', { 'data-testid': 'stability' });
    p('right', 'stability', 'Stability').append(this.stability);
    this.loads = el('div', { 'data-testid': 'loads' });
    p('right', 'loads', 'Loads', { hint: 'Forces for the stability check: someone leaning on a corner of the top (N, at a point in mm; z up).' }).append(this.loads);
    this.bom = el('div', { 'data-testid': 'bom' });
    p('right', 'bom', 'Bill of materials').append(this.bom);
    this.downloads = el('div', { 'data-testid': 'downloads' });
    p('right', 'downloads', 'Downloads', { hint: 'Build makes the bill (CSV), the report (HTML), cut diagrams (SVG at true size) and the 3D model (glb, STL).' }).append(this.downloads);
  }

  // ---------------------------------------------------------------- library
  buildLibrary(): void {
    const lib = this.w.library;
    this.category.innerHTML = '';
    this.category.append(el('option', { value: '' }, 'all categories'));
    for (const c of lib?.categories ?? []) this.category.append(el('option', { value: c }, c));
    this.renderLibrary();
  }

  private renderLibrary(): void {
    const lib = this.w.library;
    this.lib.innerHTML = '';
    if (!lib) { this.lib.append(el('p', { class: 'hint' }, 'The library is not loaded.')); return; }
    const q = this.search.value.trim().toLowerCase();
    const cat = this.category.value;
    let shown = 0;
    for (const d of lib.designs) {
      if (cat && d.category !== cat) continue;
      const hay = `${d.name} ${d.title} ${d.description} ${d.category}`.toLowerCase();
      const nodeHits = q ? d.nodes.filter((n) => n.path && n.name.toLowerCase().includes(q)) : [];
      if (q && !hay.includes(q) && !nodeHits.length) continue;
      this.lib.append(this.designCard(d, nodeHits.length > 0, q));
      ++shown;
    }
    if (!shown) this.lib.append(el('p', { class: 'hint', 'data-testid': 'template-none' }, `No template matches “${this.search.value}”${cat ? ` in ${cat}` : ''}.`));
  }

  private designCard(d: LibraryDesign, open: boolean, q: string): HTMLElement {
    const img = el('img', { alt: d.title, 'data-testid': `template-thumb-${d.name}`, class: 'tmpl-thumb' }) as HTMLImageElement;
    lazyThumbnail(this.w.api, d.name, img);
    const head = this.entry(d.name, d.name, el('span', {}, img, el('span', { class: 'tmpl-title' }, el('strong', {}, d.title), el('br'), `${d.category} · ${d.parts} parts`)));
    head.title = d.description;
    const details = el('details', { 'data-testid': `template-parts-${d.name}` }) as HTMLDetailsElement;
    details.open = open;
    details.append(el('summary', {}, 'parts of it'));
    const list = el('ul', { class: 'tmpl-nodes' });
    for (const n of d.nodes) {
      if (!n.path) continue;
      const row = this.entry(`${d.name}/${n.path}`, n.name, el('span', {}, `${n.name}`, el('span', { class: 'hint' }, n.leaf ? '' : ` (${n.elements})`)));
      row.style.paddingLeft = `${(n.depth - 1) * 12}px`;
      if (q && n.name.toLowerCase().includes(q)) row.classList.add('match');
      list.append(el('li', {}, row));
    }
    details.append(list);
    return el('div', { class: 'tmpl-card', 'data-testid': `template-${d.name}` }, head, details);
  }

  /** A draggable library entry (Enter or the + button adds it under the model's middle). */
  private entry(spec: string, name: string, content: HTMLElement): HTMLElement {
    const row = el('div', { class: 'tmpl-entry', draggable: 'true', tabindex: '0', 'data-testid': `template-entry-${spec}`, title: `Drag ${name} into the 3D view (or press Enter)` }, content);
    const add = el('button', { class: 'tmpl-add', 'data-testid': `template-add-${spec}`, title: `Add ${name} to the model` }, '+');
    add.addEventListener('click', (e) => { e.stopPropagation(); this.w.addTemplate(spec, null); });
    row.append(add);
    row.addEventListener('dragstart', (e) => {
      e.dataTransfer!.setData(DRAG_MIME, spec);
      e.dataTransfer!.setData('text/plain', spec);
      e.dataTransfer!.effectAllowed = 'copy';
    });
    row.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); this.w.addTemplate(spec, null); } });
    return row;
  }

  // ---------------------------------------------------------------- model panels
  render(): void {
    this.renderTree(); this.renderControls(); this.renderSteps(); this.renderStability(this.w.view); this.renderBom();
    this.renderLoads(); this.renderDownloads();
    this.live.textContent = '';
    this.w.ctx.refreshSelectionLabel();
  }

  /** During a drag: the step's outcome, stability and (if sent) the bill, without a compose. */
  renderLive(a: DragAnswer): void {
    this.live.textContent = `${a.control} ${mm(a.start)} → ${mm(a.achieved)} mm (asked ${mm(a.requested)})${a.message ? ` — ${a.message}` : ''}; constraints hold to ${a.max_violation.toExponential(1)} mm; QP ${a.qp_milliseconds.toFixed(1)} ms`;
    if (a.stability) this.renderStability(a);
    else this.live.textContent += '; stability under the loads is checked when you let go';
  }

  private renderTree(): void {
    const w = this.w;
    this.tree.innerHTML = '';
    const nodes = w.view?.nodes ?? [];
    if (!nodes.length) {
      this.tree.append(el('p', { class: 'hint' }, w.composeError ? `The model cannot be composed: ${w.composeError}` : 'Empty: drag a template from the library into the 3D view.'));
      return;
    }
    const sel = w.selectedPath();
    const byPath = new Map(nodes.map((n) => [n.path, n]));
    const ul = el('ul', { class: 'tree-list' });
    const add = (path: string, depth: number) => {
      const n = byPath.get(path); if (!n) return;
      if (n.connection) return; // connectors are listed under Composition
      const label = path === '' ? `${w.model.name} (whole model)` : n.element ? n.element : n.name;
      const li = el('li', { 'data-testid': `node-${keyOf(path)}`, tabindex: '0', class: sel === path ? 'selected' : '', title: path || 'the whole model' }, label);
      li.style.paddingLeft = `${depth * 12}px`;
      li.addEventListener('click', () => void w.selectNode(path));
      li.addEventListener('keydown', (e) => { if (e.key === 'Enter') void w.selectNode(path); });
      ul.append(li);
      for (const c of n.children) add(c, depth + 1);
    };
    add('', 0);
    this.tree.append(ul);
  }

  private renderControls(): void {
    const w = this.w;
    this.controlsBox.innerHTML = '';
    const path = w.selectedPath();
    const c = w.controls;
    if (path === null || !c || c.node !== path) { this.controlsBox.append(el('p', { class: 'hint' }, 'Select a part or a group to see its handles.')); return; }
    const table = el('table', { class: 'controls' });
    for (const ctl of c.controls) {
      const cell = el('td');
      if (ctl.hidden) cell.append(el('span', { class: 'hint', 'data-testid': `control-fixed-${ctl.control}`, title: 'fully constrained: the template\'s relations fix it (no handle)' }, `${mm(ctl.value)} mm (fixed)`));
      else {
        const f = el('input', { type: 'number', step: '1', value: mm(ctl.value), 'data-testid': `control-${ctl.control}`, title: `Set ${CONTROL_WORDS[ctl.control]} (mm); the nearest buildable shape is taken` }) as HTMLInputElement;
        f.addEventListener('change', () => w.setControl(ctl.control, Number(f.value)));
        cell.append(f, ' mm');
      }
      table.append(el('tr', {}, el('th', { title: CONTROL_WORDS[ctl.control] }, ctl.control), cell));
    }
    this.controlsBox.append(table);
  }

  private renderSteps(): void {
    const w = this.w;
    this.steps.innerHTML = '';
    const c = w.composed;
    if (!c) { this.steps.append(el('p', { class: 'hint' }, 'Nothing composed yet.')); return; }
    const ol = el('ol', {});
    c.steps.forEach((s, i) => {
      const li = el('li', { 'data-testid': `step-${i}`, class: s.ok ? '' : 'bad' }, el('div', {}, s.text), el('div', { class: 'hint' }, s.outcome));
      const step = i < w.model.steps.length ? w.model.steps[i] : null;
      if (step && i > 0) li.append(this.sizeBeforeSnapping(i));
      if (step && i > 0 && s.links && !s.links.length) {
        li.append(el('div', { class: 'error', 'data-testid': `not-touching-${step.as}` },
          `${step.as} touches no part of the model after snapping, so nothing joins it: set its size near the space it should fill (the fields above; it snaps again), or drop it closer.`));
      }
      for (const l of s.links ?? []) {
        if (l.connected) continue;
        const tried = l.tried.map((t) => `${t.source}: ${t.feasible ? `moves parts ${t.error_mm?.toFixed(0)} mm` : 'infeasible'}`);
        li.append(el('div', { class: 'error', 'data-testid': `no-connection-${l.added}-${l.existing}` },
          l.message || `no connection found between '${l.added}' and '${l.existing}'`,
          tried.length ? el('div', { class: 'hint' }, `tried: ${tried.join('; ')}`) : ''));
      }
      ol.append(li);
    });
    this.steps.append(ol);
    const conns = el('details', { 'data-testid': 'connections' });
    conns.append(el('summary', {}, `${c.connections.length} connections`));
    const ul = el('ul', {});
    for (const k of c.connections) ul.append(el('li', {}, `${k.principal.join(' + ')}: ${k.connecting.join(', ') || '—'} (${k.source})`));
    conns.append(ul);
    this.steps.append(conns);
    const shown = c.diagnostics.filter((d) => d.severity === 'error' || d.severity === 'warning');
    if (shown.length) {
      const box = el('ul', { class: 'diags', 'data-testid': 'model-diagnostics' });
      for (const d of shown) box.append(el('li', { class: d.severity === 'error' ? 'error' : 'hint' }, d.text || d.message));
      this.steps.append(box);
    }
  }

  /** The added template's size before it is snapped (a step's `set:`): editing it snaps and connects it again. */
  private sizeBeforeSnapping(i: number): HTMLElement {
    const w = this.w;
    const step = w.model.steps[i];
    const [design, ...rest] = step.use.split('/');
    const node = w.library?.designs.find((d) => d.name === design)?.nodes.find((n) => n.path === rest.join('/'));
    const row = el('div', { class: 'row hint', title: 'The size of this template before it is snapped and joined (mm); the snapped size is shown in the model' }, 'size before snapping:');
    ['x', 'y', 'z'].forEach((a, k) => {
      const key = `size_${a}`;
      const dflt = node ? node.box.max[k] - node.box.min[k] : 0;
      const f = el('input', { type: 'number', step: '1', value: mm(step.set?.[key] ?? dflt), 'data-testid': `step-${step.as}-${key}`, style: 'width:58px', title: `${key} of ${step.as} before snapping (mm)` }) as HTMLInputElement;
      f.addEventListener('change', () => {
        const v = Number(f.value);
        if (!Number.isFinite(v) || v <= 0) { w.ctx.message(`${key} must be a positive number of mm.`); return; }
        const m = w.model;
        if (m.steps[i]?.set?.[key] === v) return; // the same value again (a second change event)
        const steps = m.steps.map((s, j) => (j === i ? { ...s, set: { ...(s.set ?? {}), [key]: v } } : s));
        w.ctx.history.apply({ ...m, steps }, `set ${step.as} ${key} to ${v} mm before snapping`);
      });
      row.append(` ${a} `, f);
    });
    for (const key of ['snap', 'connect'] as const) {
      const box = el('input', { type: 'checkbox', 'data-testid': `step-${step.as}-${key}`, title: key === 'snap' ? 'Snap it to the model\'s planes when it is dropped' : 'Join it to the parts it touches with connectors from the database' }) as HTMLInputElement;
      box.checked = step[key] !== false;
      box.addEventListener('change', () => {
        const m = w.model;
        const steps = m.steps.map((s, j) => (j === i ? { ...s, [key]: box.checked } : s));
        w.ctx.history.apply({ ...m, steps }, `${key} ${step.as}: ${box.checked ? 'on' : 'off'}`);
      });
      row.append(el('label', {}, box, key));
    }
    return row;
  }

  private renderStability(v: ModelState | null): void {
    const w = this.w;
    this.stability.innerHTML = '';
    if (!v || !v.stability) return;
    const s = v.stability;
    const unstable = s.bodies.filter((b) => !b.stable);
    this.stability.append(el('p', { 'data-testid': 'stability-verdict', class: s.stable ? 'ok' : 'error' },
      s.stable ? `Stable: ${s.bodies.length} rigid bod${s.bodies.length === 1 ? 'y' : 'ies'} at rest${w.model.loads.length ? ' and under the loads' : ''}`
        : `Unstable: ${unstable.map((b) => `${b.elements.slice(0, 4).join(', ')}${b.elements.length > 4 ? ', …' : ''} ${b.verdict}`).join('; ')}`));
    this.stability.append(el('p', { 'data-testid': 'constraints', class: v.max_violation < 1e-6 ? 'hint' : 'error' },
      v.max_violation < 1e-6 ? `Every constraint holds (largest violation ${v.max_violation.toExponential(1)} mm).` : `Constraints violated by up to ${mm(v.max_violation)} mm.`));
    const toggle = el('div', { class: 'row' });
    for (const [mode, text] of [['materials', 'Colour by material'], ['stability', 'Colour by stability']] as const) {
      const b = el('button', { 'data-testid': `color-${mode}`, class: w.colorBy === mode ? 'active' : '', title: mode === 'stability' ? 'Stable parts green, unstable red (paper §4.6)' : 'Parts in their materials, connectors blue, unstable parts red' }, text);
      b.addEventListener('click', () => { w.colorBy = mode; w.setLegend(); w.draw(); this.renderStability(w.view); });
      toggle.append(b);
    }
    this.stability.append(toggle);
    void STABLE_GREEN; void UNSTABLE_RED;
  }

  private renderBom(): void {
    const w = this.w;
    this.bom.innerHTML = '';
    const b = w.composed?.bom;
    if (!b) return;
    if (!b.lines.length) {
      for (const d of b.diagnostics) this.bom.append(el('p', { class: 'error' }, d.text || d.message));
      return;
    }
    const table = el('table', { class: 'bom', 'data-testid': 'bom-table' });
    table.append(el('tr', {}, el('th', {}, 'item'), el('th', {}, 'parts'), el('th', {}, 'cut sizes'), el('th', {}, 'buy'), el('th', {}, 'total')));
    for (const l of b.lines) {
      table.append(el('tr', { 'data-testid': `bom-row-${l.item}`, title: `${l.name}; ${l.supplier} ${l.part_number}` },
        el('td', {}, l.item), el('td', { 'data-testid': `bom-parts-${l.item}` }, String(l.parts)), el('td', { 'data-testid': `bom-sizes-${l.item}` }, l.sizes),
        el('td', {}, l.buy), el('td', { class: 'num' }, usd(l.total))));
    }
    table.append(el('tr', { class: 'total' }, el('th', {}, 'total'), el('td'), el('td'), el('td'), el('th', { class: 'num', 'data-testid': 'bom-total' }, usd(b.total))));
    this.bom.append(table);
  }

  private renderLoads(): void {
    const w = this.w;
    this.loads.innerHTML = '';
    const m = w.model;
    const ul = el('ul', {});
    m.loads.forEach((l, i) => {
      const x = el('button', { 'data-testid': `load-remove-${i}`, title: 'Remove this load' }, '×');
      x.addEventListener('click', () => w.ctx.history.apply({ ...m, loads: m.loads.filter((_, j) => j !== i) }, `remove the load on ${l.part}`));
      ul.append(el('li', { 'data-testid': `load-${i}` }, `${l.part}: [${l.force.join(', ')}] N at [${l.at.map(mm).join(', ')}] mm `, x));
    });
    this.loads.append(ul);
    // a new load: on the selected part, at the top corner of it farthest from the model's centre
    const sel = w.selectedPath();
    const n = sel !== null ? w.node(sel) : undefined;
    const part = el('input', { 'data-testid': 'load-part', size: '10', placeholder: 'part', value: n?.element ?? '', title: 'The part the force acts on (a part name, e.g. top)' }) as HTMLInputElement;
    const at = ['x', 'y', 'z'].map((a, i) => el('input', { type: 'number', 'data-testid': `load-at-${a}`, value: n ? mm(i === 2 ? n.box.max[2] : n.box.max[i]) : '0', title: `point of application, ${a} (mm)`, style: 'width:60px' }) as HTMLInputElement);
    const force = el('input', { type: 'number', 'data-testid': 'load-force', value: '-300', title: 'force along z (N); −300 N is a person leaning on it', style: 'width:60px' }) as HTMLInputElement;
    const add = el('button', { 'data-testid': 'load-add', title: 'Add this load to the stability check' }, 'Add load');
    add.addEventListener('click', () => {
      const p = part.value.trim();
      const v = at.map((f) => Number(f.value));
      const fz = Number(force.value);
      if (!p || v.some((x) => !Number.isFinite(x)) || !Number.isFinite(fz)) { w.ctx.message('A load needs a part name, a point (mm) and a force (N).'); return; }
      w.ctx.history.apply({ ...m, loads: [...m.loads, { part: p, at: [v[0], v[1], v[2]], force: [0, 0, fz] }] }, `load ${p} with ${fz} N`);
    });
    this.loads.append(el('div', { class: 'row' }, part, ...at, force, ' N ', add));
  }

  renderDownloads(): void {
    const w = this.w;
    this.downloads.innerHTML = '';
    const a = w.buildAnswer?.answer;
    if (!a) { this.downloads.append(el('p', { class: 'hint' }, 'Press Build to list the outputs.')); return; }
    this.downloads.append(el('p', { 'data-testid': 'build-message' }, a.message));
    const ul = el('ul', {});
    for (const f of a.files) {
      const b = el('button', { 'data-testid': `download-${f.name}`, title: `${f.type}, ${f.bytes} bytes` }, f.name);
      b.addEventListener('click', () => w.downloadFile(f));
      ul.append(el('li', {}, b));
    }
    this.downloads.append(ul);
  }
}

