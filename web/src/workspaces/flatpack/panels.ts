// The Flat-pack workspace's panels: the component library, the design's components with their
// parameters (sliders and numeric fields), design parameters and meta-parameters, constraints,
// connections (the 5-tuple), material and sheet on the left; the nested cut sheets, warnings
// and residuals, joints and the view on the right.
import { el } from '../../shell/ui';
import { JOINT_COLORS, connectionName, freshName, isNumber, parseNum, renameComponent, clone, splitRef } from './model';
import type { FpConnection, FpDesign, FpMaterial, Num, Vec3N } from './model';
import type { ParamSchema } from './api';
import { designToYaml as designToYamlOf } from './yamlio';
import { fileStem } from '../../shell/shell';
import type { FlatpackWorkspace } from './workspace';

const SVG = 'http://www.w3.org/2000/svg';
const svg = (tag: string, attrs: Record<string, string | number> = {}) => {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  return e;
};
const fmt = (v: number | undefined) => (v === undefined || !Number.isFinite(v) ? '?' : String(Math.round(v * 100) / 100));
const unitOf = (kind: string) => (kind === 'length' ? 'mm' : kind === 'angle' ? '°' : '');

/** A slider and a field for one value: the slider previews while dragged and commits on release; the field takes a number or an expression. */
function valueRow(id: string, label: string, title: string, value: Num | undefined, solved: number | undefined, range: [number, number, number],
                  onPreview: (v: number) => void, onCommit: (v: Num | null) => void): HTMLElement {
  const row = el('div', { class: 'fp-row', title });
  const field = el('input', { 'data-testid': id, value: value === undefined ? '' : String(value), placeholder: solved === undefined ? 'value or expression' : `solved: ${fmt(solved)}`, size: '9' }) as HTMLInputElement;
  const show = isNumber(value) ? value : solved ?? range[0];
  const [lo, hi, step] = [Math.min(range[0], show), Math.max(range[1], show), range[2]];
  const slider = el('input', { type: 'range', min: String(lo), max: String(hi), step: String(step), value: String(show), 'data-testid': `${id}-slider` }) as HTMLInputElement;
  slider.disabled = value !== undefined && !isNumber(value);
  if (slider.disabled) slider.title = 'set by an expression: type a number in the field to use the slider';
  slider.addEventListener('input', () => { field.value = slider.value; onPreview(Number(slider.value)); });
  slider.addEventListener('change', () => onCommit(Number(slider.value)));
  field.addEventListener('change', () => onCommit(parseNum(field.value)));
  const out = el('span', { class: 'fp-solved', 'data-testid': `${id}-solved` }, value !== undefined && !isNumber(value) && solved !== undefined ? `= ${fmt(solved)}` : '');
  row.append(el('span', { class: 'fp-label' }, label), slider, field, out);
  return row;
}

export class Panels {
  private left: Record<string, HTMLElement> = {};
  private right: Record<string, HTMLElement> = {};
  selectedConnection: number | null = null;
  private newName = '';

  constructor(private ws: FlatpackWorkspace) {
    const ctx = ws.ctx;
    this.left.library = ctx.panel('left', 'fp-library', 'Component library', { hint: 'Add a planar component; click two edges in the view to connect them.' });
    this.left.components = ctx.panel('left', 'fp-components', 'Components');
    this.left.parameters = ctx.panel('left', 'fp-parameters', 'Parameters', { hint: 'Meta-parameters (★) are the few that re-size the whole design.' });
    this.left.constraints = ctx.panel('left', 'fp-constraints', 'Constraints');
    this.left.material = ctx.panel('left', 'fp-material', 'Material & sheet', { hint: 'Δ kerf: removed on each side of a cut line; δ interference: how much wider a finger is than its opening.' });
    this.right.sheets = ctx.panel('right', 'fp-sheets', 'Cut sheets');
    this.right.diagnostics = ctx.panel('right', 'fp-diagnostics', 'Warnings & residuals');
    this.right.connections = ctx.panel('right', 'fp-connections', 'Connections', { hint: 'A.a → B.b lays A\'s edge a on B\'s edge b (midpoints together); offset in B\'s edge frame (x along b, y into B, z along B\'s front), rotation about A\'s edge axes.' });
    this.right.joints = ctx.panel('right', 'fp-joints', 'Joints');
    this.right.view = ctx.panel('right', 'fp-view', 'View');
    ctx.selection.onChange(() => { ws.restyle(); this.renderComponents(); this.highlightSheets(); });
  }

  buildLibrary(): void {
    const box = this.left.library; box.innerHTML = '';
    const name = el('input', { 'data-testid': 'new-component-name', placeholder: 'name (optional)', size: '12', title: 'Name of the next component you add (A, B, … when empty)' }) as HTMLInputElement;
    name.value = this.newName;
    name.addEventListener('input', () => { this.newName = name.value.trim(); });
    box.append(el('div', { class: 'fp-row' }, 'name ', name));
    for (const t of this.ws.types) {
      const own = t.constraints.length ? ` (${t.constraints.join(', ')})` : '';
      const params = t.params.map((p) => p.name).join(', ');
      const item = el('div', { class: 'lib-item fp-lib', 'data-testid': `lib-${t.name}`, role: 'button', tabindex: '0', title: `${t.description}${own}` },
        el('span', {}, el('b', {}, t.name), el('small', {}, t.takes_points ? 'points; edges e0 …' : `${params}; edges ${t.edges.join(', ')}`)));
      const add = el('button', { 'data-testid': `add-${t.name}`, title: `Add a ${t.name} to the design (undoable)` }, 'Add');
      add.addEventListener('click', (e) => { e.stopPropagation(); this.ws.addComponent(t.name, this.newName || undefined); this.newName = ''; name.value = ''; });
      item.addEventListener('click', () => add.click());
      item.append(add);
      box.append(item);
    }
  }

  /** Everything: after a command (the design changed). */
  render(): void {
    this.renderComponents();
    this.renderParameters();
    this.renderConstraints();
    this.renderMaterial();
    this.renderResults();
  }

  /** What the server computed: sheets, diagnostics, joints, solved values (also during a preview). */
  renderResults(): void {
    this.renderSheets();
    this.renderDiagnostics();
    this.renderConnections();
    this.renderJoints();
    this.renderView();
    for (const e of document.querySelectorAll<HTMLElement>('[data-fp-solved]')) {
      const v = this.ws.asm?.values[e.dataset.fpSolved!];
      e.textContent = v === undefined ? '' : `= ${fmt(v)}`;
    }
  }

  hover(key: string | null): void {
    for (const e of document.querySelectorAll('.fp-hover')) e.classList.remove('fp-hover');
    if (!key) return;
    const [comp] = splitRef(key);
    for (const e of document.querySelectorAll(`[data-fp-piece="${CSS.escape(this.ws.pieceOf(comp))}"]`)) e.classList.add('fp-hover');
  }

  // ---------------------------------------------------------------- components
  private rangeFor(p: ParamSchema | undefined, kind: string): [number, number, number] {
    if (kind === 'count') return [Math.max(3, p?.min ?? 3), 64, 1];
    if (kind === 'angle') return [p?.min ?? -180, p?.max ?? 180, 0.5];
    return [Math.max(0, p?.min ?? 0), Math.min(p?.max ?? 1500, 1500), 1];
  }

  renderComponents(): void {
    const box = this.left.components; box.innerHTML = '';
    const ws = this.ws, d = ws.design;
    if (!d.components.length) { box.append(el('p', { class: 'hint' }, 'No components yet: add one from the library.')); return; }
    const selected = ws.ctx.selection.current.object;
    const list = el('ul', { class: 'fp-list', 'data-testid': 'component-list' });
    for (const c of d.components) {
      const info = ws.placed(c.name);
      const size = info ? Object.entries(info.values).filter(([k]) => !k.includes('.')).map(([k, v]) => `${k} ${fmt(v)}`).join(', ') : '';
      const li = el('li', { class: c.name === selected ? 'selected' : '', 'data-testid': `component-${c.name}`, 'data-fp-piece': ws.pieceOf(c.name), role: 'button', tabindex: '0' },
        el('b', {}, c.name), ` ${c.type}`, el('small', {}, ` ${size}`));
      li.addEventListener('click', () => ws.ctx.selection.set(c.name, null));
      list.append(li);
    }
    box.append(list);
    const c = selected ? ws.component(selected) : undefined;
    if (!c) return;
    const t = ws.typeByName.get(c.type);
    const info = ws.placed(c.name);
    const ed = el('div', { class: 'fp-editor', 'data-testid': `component-editor-${c.name}` });
    const nameField = el('input', { value: c.name, 'data-testid': `component-${c.name}-name`, size: '10' }) as HTMLInputElement;
    nameField.addEventListener('change', () => {
      const n = nameField.value.trim();
      if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(n) || d.components.some((x) => x.name === n)) { ws.ctx.message(`"${n}" cannot name a component: use letters, digits and _ (not starting with a digit), and a name not yet used.`); nameField.value = c.name; return; }
      ws.apply(renameComponent(d, c.name, n), `rename ${c.name} to ${n}`);
      ws.ctx.selection.set(n, null);
    });
    const del = el('button', { 'data-testid': `component-${c.name}-delete`, title: `Delete ${c.name} and its connections (undoable)` }, 'delete');
    del.addEventListener('click', () => ws.deleteComponent(c.name));
    ed.append(el('div', { class: 'fp-row' }, el('b', {}, `${c.type} `), nameField, ' ', del));
    if (t?.description) ed.append(el('p', { class: 'hint' }, t.description));
    const own = new Map((t?.constraints ?? []).map((x) => [x.split('=')[0].trim(), x]));
    for (const p of t?.params ?? []) {
      const kind = p.kind;
      const solved = info?.values[p.name];
      if (own.has(p.name) && c.params[p.name] === undefined) {
        ed.append(el('div', { class: 'fp-row', title: p.description }, el('span', { class: 'fp-label' }, `${p.name} ${unitOf(kind)}`), el('span', {}, `${own.get(p.name)} = ${fmt(solved)}`)));
        continue;
      }
      ed.append(valueRow(`param-${c.name}-${p.name}`, `${p.name} ${unitOf(kind)}`, `${p.description}${p.default !== null ? ` (default ${p.default})` : ''}; a number or an expression over the parameters`,
        c.params[p.name], solved, this.rangeFor(p, kind),
        (v) => ws.setComponentParam(c.name, p.name, v, true),
        (v) => ws.setComponentParam(c.name, p.name, v)));
    }
    // Its edges: the same as clicking them in the view (keyboard access, small edges).
    if (info?.edges.length) {
      const row = el('div', { class: 'fp-row fp-edges', title: 'Pick an edge to connect (like clicking it in the view): first the edge that moves, then the edge to lay it on' }, el('span', { class: 'fp-label' }, 'edges'));
      for (const e of info.edges) {
        const key = `${c.name}.${e.name}`;
        const len = Math.hypot(e.end[0] - e.start[0], e.end[1] - e.start[1], e.end[2] - e.start[2]);
        const b = el('button', { 'data-testid': `edge-${c.name}-${e.name}`, class: ws.pick === key ? 'on' : '', title: `${key}, ${fmt(len)} mm` }, e.name);
        b.addEventListener('click', () => ws.pickEdge(key));
        b.addEventListener('pointerenter', () => { ws.ctx.scene.setHover(key); });
        b.addEventListener('pointerleave', () => { ws.ctx.scene.setHover(null); });
        row.append(b);
      }
      ed.append(row);
    }
    // Material of this piece: the design's or one of its named materials.
    const sel = el('select', { 'data-testid': `component-${c.name}-material`, title: 'The board this component is cut from' }) as HTMLSelectElement;
    sel.append(el('option', { value: '' }, `design's (${d.material.name}, ${d.material.thickness} mm)`));
    for (const m of d.materials) sel.append(el('option', { value: m.name }, `${m.name} (${m.thickness} mm)`));
    sel.value = c.material ?? '';
    sel.addEventListener('change', () => {
      const n = clone(d); const x = n.components.find((y) => y.name === c.name)!;
      if (sel.value) x.material = sel.value; else delete x.material;
      ws.apply(n, `${c.name} from ${sel.value || 'the design\'s material'}`);
    });
    const own_ = el('button', { 'data-testid': `component-${c.name}-own-material`, title: `Give ${c.name} its own material (a copy of the design's, to change its thickness, kerf or interference)` }, 'own material');
    own_.addEventListener('click', () => {
      const n = clone(d);
      const name = freshName(n.materials.map((m) => m.name).concat(n.material.name), `${c.name}_board`);
      n.materials.push({ ...n.material, name });
      n.components.find((y) => y.name === c.name)!.material = name;
      ws.apply(n, `${c.name} from its own material ${name}`);
    });
    ed.append(el('div', { class: 'fp-row' }, el('span', { class: 'fp-label' }, 'material'), sel, own_));
    const piece = ws.asm?.pieces.find((p) => p.name === ws.pieceOf(c.name));
    if (piece) ed.append(el('p', { class: 'hint', 'data-testid': `component-${c.name}-piece` }, `piece ${piece.name}: ${fmt(piece.size_mm[0])} × ${fmt(piece.size_mm[1])} mm, ${piece.material.thickness} mm ${piece.material.name}${piece.sheet ? `, sheet ${piece.sheet}` : ''}`));
    for (const dg of ws.diagnosticsOf(ws.pieceOf(c.name))) ed.append(el('div', { class: dg.severity === 'error' ? 'diag' : 'fp-warn' }, `${dg.severity}: ${dg.message}`));
    box.append(ed);
  }

  // ---------------------------------------------------------------- parameters and constraints
  renderParameters(): void {
    const box = this.left.parameters; box.innerHTML = '';
    const ws = this.ws, d = ws.design;
    const ordered = [...d.parameters].sort((a, b) => Number(b.meta) - Number(a.meta));
    for (const p of ordered) {
      const drives = ws.asm?.meta.find((m) => m.name === p.name)?.drives ?? [];
      const r: [number, number, number] = p.type === 'angle' ? [-180, 180, 0.5] : p.type === 'count' ? [1, 64, 1] : [0, Math.max(1000, 2 * (p.value ?? 0)), 1];
      const row = valueRow(`dparam-${p.name}`, `${p.meta ? '★ ' : ''}${p.name} ${unitOf(p.type)}`, p.description ?? `parameter ${p.name}`, p.value ?? undefined, ws.asm?.values[p.name], r,
        (v) => ws.setParameter(p.name, { value: v }, true),
        (v) => { if (typeof v === 'number' || v === null) ws.setParameter(p.name, { value: v }); else ws.ctx.message(`${p.name}: a parameter's value is a number; put expressions into constraints or component values.`); });
      const meta = el('input', { type: 'checkbox', 'data-testid': `dparam-${p.name}-meta`, title: 'meta-parameter: one of the few that re-size the design' }) as HTMLInputElement;
      meta.checked = p.meta;
      meta.addEventListener('change', () => ws.setParameter(p.name, { meta: meta.checked }));
      const del = el('button', { 'data-testid': `dparam-${p.name}-delete`, title: `Delete parameter ${p.name}` }, '×');
      del.addEventListener('click', () => { const n = clone(d); n.parameters = n.parameters.filter((x) => x.name !== p.name); ws.apply(n, `delete parameter ${p.name}`); });
      row.append(el('label', { title: 'meta-parameter' }, meta, '★'), del);
      box.append(row);
      if (p.meta && drives.length) box.append(el('div', { class: 'hint', 'data-testid': `dparam-${p.name}-drives` }, `drives ${drives.join(', ')}`));
    }
    const name = el('input', { 'data-testid': 'new-param-name', placeholder: 'name', size: '8' }) as HTMLInputElement;
    const value = el('input', { 'data-testid': 'new-param-value', placeholder: 'value', size: '6' }) as HTMLInputElement;
    const meta = el('input', { type: 'checkbox', 'data-testid': 'new-param-meta' }) as HTMLInputElement;
    const add = el('button', { 'data-testid': 'add-param', title: 'Add a design parameter (mm); use it in component values, offsets and constraints' }, 'Add parameter');
    add.addEventListener('click', () => {
      const n = name.value.trim(), v = Number(value.value);
      if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(n) || d.parameters.some((p) => p.name === n)) { ws.ctx.message(`"${n}" cannot name a parameter: letters, digits and _, not yet used.`); return; }
      if (!Number.isFinite(v)) { ws.ctx.message(`the value of ${n} must be a number (mm)`); return; }
      const next = clone(d);
      next.parameters.push({ name: n, value: v, type: 'length', meta: meta.checked });
      ws.apply(next, `add parameter ${n} = ${v}`);
    });
    box.append(el('div', { class: 'fp-row' }, name, value, el('label', {}, meta, '★'), add));
  }

  renderConstraints(): void {
    const box = this.left.constraints; box.innerHTML = '';
    const ws = this.ws, d = ws.design;
    d.constraints.forEach((c, i) => {
      const f = el('input', { value: c, 'data-testid': `constraint-${i}`, size: '22' }) as HTMLInputElement;
      f.addEventListener('change', () => { const n = clone(d); if (f.value.trim()) n.constraints[i] = f.value.trim(); else n.constraints.splice(i, 1); ws.apply(n, `constraint ${f.value.trim() || 'deleted'}`); });
      const del = el('button', { 'data-testid': `constraint-${i}-delete` }, '×');
      del.addEventListener('click', () => { const n = clone(d); n.constraints.splice(i, 1); ws.apply(n, `delete constraint ${c}`); });
      box.append(el('div', { class: 'fp-row' }, f, del));
    });
    const f = el('input', { 'data-testid': 'new-constraint', placeholder: 'B.l = A.l', size: '22', title: 'left = right: a parameter or component value, and an expression' }) as HTMLInputElement;
    f.addEventListener('change', () => { if (!f.value.includes('=')) { ws.ctx.message('a constraint is left = right, e.g. B.w = 2*l2 + 10'); return; } const n = clone(d); n.constraints.push(f.value.trim()); ws.apply(n, `constraint ${f.value.trim()}`); });
    box.append(f);
  }

  renderMaterial(): void {
    const box = this.left.material; box.innerHTML = '';
    const ws = this.ws, d = ws.design;
    const editor = (m: FpMaterial, id: string, set: (m: FpMaterial, label: string) => void) => {
      const row = el('div', { class: 'fp-material', 'data-testid': id });
      const name = el('input', { value: m.name, 'data-testid': `${id}-name`, size: '11', title: 'material name' }) as HTMLInputElement;
      name.addEventListener('change', () => set({ ...m, name: name.value.trim() || m.name }, `material ${name.value}`));
      row.append(name);
      for (const [k, label, title] of [['thickness', 't mm', 'board thickness'], ['kerf', 'Δ mm', 'kerf: removed on each side of a cut line'], ['interference', 'δ mm', 'interference: a finger is this much wider than its opening']] as const) {
        const f = el('input', { type: 'number', step: 'any', value: String(m[k]), 'data-testid': `${id}-${k}`, title, style: 'width:58px' }) as HTMLInputElement;
        f.addEventListener('change', () => {
          const v = Number(f.value);
          const ok = Number.isFinite(v) && (k === 'thickness' ? v > 0 && v <= 100 : k === 'kerf' ? v >= 0 && v <= 2 : v >= -1 && v <= 1);
          if (!ok) { ws.ctx.message(`${title}: ${f.value} is out of range (thickness 0–100 mm, kerf 0–2 mm, interference −1–1 mm)`); f.value = String(m[k]); return; }
          set({ ...m, [k]: v }, `${m.name} ${k} ${v} mm`);
        });
        row.append(el('label', { title }, ` ${label} `, f));
      }
      return row;
    };
    box.append(el('div', { class: 'hint' }, 'design material (every piece unless it names another):'),
      editor(d.material, 'mat', (m, label) => { const n = clone(d); n.material = m; ws.apply(n, label); }));
    d.materials.forEach((m, i) => {
      const row = editor(m, `mat-${i}`, (mm, label) => {
        const n = clone(d); n.materials[i] = mm;
        if (mm.name !== m.name) for (const c of n.components) if (c.material === m.name) c.material = mm.name;
        ws.apply(n, label);
      });
      const users = d.components.filter((c) => c.material === m.name).map((c) => c.name);
      const del = el('button', { 'data-testid': `mat-${i}-delete`, title: 'Delete this material (its components go back to the design\'s)' }, '×');
      del.addEventListener('click', () => { const n = clone(d); n.materials.splice(i, 1); for (const c of n.components) if (c.material === m.name) delete c.material; ws.apply(n, `delete material ${m.name}`); });
      row.append(del, el('small', {}, users.length ? ` for ${users.join(', ')}` : ' (unused)'));
      box.append(row);
    });
    const add = el('button', { 'data-testid': 'add-material', title: 'Add a named material that components can pick' }, 'Add material');
    add.addEventListener('click', () => { const n = clone(d); n.materials.push({ ...d.material, name: freshName(d.materials.map((m) => m.name), 'board') }); ws.apply(n, 'add material'); });
    box.append(add);
    // The sheet size the pieces are nested on.
    const sheet = (d.extra.sheet ?? {}) as Record<string, unknown>;
    const sizes = el('div', { class: 'fp-row' }, 'sheet ');
    for (const [k, dflt] of [['width', 600], ['height', 400]] as const) {
      const f = el('input', { type: 'number', value: String(sheet[k] ?? dflt), 'data-testid': `sheet-${k}`, style: 'width:64px', title: `sheet ${k} (mm)` }) as HTMLInputElement;
      f.addEventListener('change', () => {
        const v = Number(f.value);
        if (!Number.isFinite(v) || v < 10 || v > 10000) { ws.ctx.message(`sheet ${k}: ${f.value} mm is out of range (10–10000 mm)`); return; }
        const n = clone(d); n.extra.sheet = { ...sheet, [k]: v }; ws.apply(n, `sheet ${k} ${v} mm`);
      });
      sizes.append(f, k === 'width' ? ' × ' : ' mm');
    }
    box.append(sizes);
  }

  // ---------------------------------------------------------------- connections
  renderConnections(): void {
    const box = this.right.connections; box.innerHTML = '';
    const ws = this.ws, d = ws.design;
    if (!d.connections.length) { box.append(el('p', { class: 'hint' }, 'No connections: click an edge in the view, then the edge to lay it on.')); return; }
    const list = el('ol', { class: 'fp-list', 'data-testid': 'connection-list' });
    d.connections.forEach((c, i) => {
      const name = connectionName(c, i);
      const joint = ws.asm?.joints.filter((j) => j.connection === i) ?? [];
      const merged = ws.asm?.merging_connections.includes(i);
      const res = ws.asm?.residuals.find((r) => r.connection === i);
      const made = joint.length ? joint.map((j) => `j${j.id} ${j.kind}`).join(', ') : merged ? 'merged into one piece' : c.joint === 'none' ? 'places only' : ws.asm?.placed ? 'no joint' : '';
      const li = el('li', { class: this.selectedConnection === i ? 'selected' : '', 'data-testid': `connection-${i}` });
      const text = el('span', { class: 'conn-text', 'data-testid': `connection-text-${i}`, role: 'button', tabindex: '0', title: 'Select this connection' }, `${name}: ${c.a} → ${c.b}`);
      text.addEventListener('click', () => { this.selectedConnection = i; ws.ctx.selection.set(splitRef(c.a)[0], null); this.renderConnections(); });
      li.append(text, el('small', { 'data-testid': `connection-${i}-made` }, ` ${made}`));
      if (res) li.append(el('div', { class: res.closes ? 'hint' : 'diag', 'data-testid': `connection-${i}-residual` }, res.closes ? `closes a cycle (residual ${res.position_mm.toFixed(3)} mm, ${res.angle_deg.toFixed(3)}°)` : `closes a cycle that misses by ${res.position_mm.toFixed(2)} mm and ${res.angle_deg.toFixed(2)}° at ${res.component}`));
      if (this.selectedConnection === i || d.connections.length <= 6) li.append(this.connectionEditor(c, i));
      list.append(li);
    });
    box.append(list);
  }

  private connectionEditor(c: FpConnection, i: number): HTMLElement {
    const ws = this.ws;
    const box = el('div', { class: 'fp-conn' });
    const align = el('select', { 'data-testid': `conn-${i}-alignment`, title: 'front-front: A beside B with the same front; front-back: A flipped over the edge' }) as HTMLSelectElement;
    for (const a of ['front-front', 'front-back']) align.append(el('option', { value: a }, a));
    align.value = c.alignment;
    align.addEventListener('change', () => ws.setConnection(i, { alignment: align.value as FpConnection['alignment'] }, `${c.a} → ${c.b} ${align.value}`));
    const none = el('input', { type: 'checkbox', 'data-testid': `conn-${i}-places-only`, title: 'joint: none — only places A (a lid resting on a box); no joint is cut' }) as HTMLInputElement;
    none.checked = c.joint === 'none';
    none.addEventListener('change', () => ws.setConnection(i, { joint: none.checked ? 'none' : undefined }, `${c.a} → ${c.b} ${none.checked ? 'places only' : 'joins'}`));
    const del = el('button', { 'data-testid': `conn-${i}-delete`, title: 'Delete this connection (undoable)' }, 'delete');
    del.addEventListener('click', () => ws.deleteConnection(i));
    box.append(el('div', { class: 'fp-row' }, align, el('label', {}, none, ' places only'), del));
    for (const [key, label, unit] of [['offset', 'offset', 'mm'], ['rotation', 'rotation', '°']] as const) {
      const row = el('div', { class: 'fp-row fp-vec' }, el('span', { class: 'fp-label' }, `${label} ${unit}`));
      (['x', 'y', 'z'] as const).forEach((axis, k) => {
        const f = el('input', { 'data-testid': `conn-${i}-${key}-${axis}`, value: String(c[key][k]), size: '6', title: `${label} ${axis} (${unit}): a number or an expression` }) as HTMLInputElement;
        f.addEventListener('change', () => {
          const v = parseNum(f.value) ?? 0;
          const vec = [...c[key]] as Vec3N; vec[k] = v;
          ws.setConnection(i, { [key]: vec } as Partial<FpConnection>, `${c.a} → ${c.b} ${label} ${axis} ${v}`);
        });
        row.append(f);
      });
      box.append(row);
    }
    return box;
  }

  // ---------------------------------------------------------------- results
  renderDiagnostics(): void {
    const box = this.right.diagnostics; box.innerHTML = '';
    const ws = this.ws, asm = ws.asm;
    const list = el('ul', { class: 'fp-list', 'data-testid': 'diagnostics' });
    const err = ws.readError;
    if (err) {
      const diags = err.diagnostics.length ? err.diagnostics.map((x) => x.text ?? x.message) : [err.message];
      for (const t of diags) list.append(el('li', { class: 'diag' }, t));
    }
    for (const r of asm?.residuals ?? []) {
      if (r.closes) continue;
      list.append(el('li', { class: 'diag', 'data-testid': `residual-${r.name}` }, `residual of ${r.name}: ${r.position_mm.toFixed(2)} mm, ${r.angle_deg.toFixed(2)}° at ${r.piece}`));
    }
    for (const dg of asm?.diagnostics ?? []) {
      const li = el('li', { class: dg.severity === 'error' ? 'diag' : 'fp-warn', 'data-testid': 'diagnostic' }, `${dg.severity}: ${dg.message}`);
      if (dg.pieces.length) {
        li.append(el('small', {}, ` — ${dg.pieces.join(', ')}`));
        li.setAttribute('role', 'button'); li.tabIndex = 0;
        li.addEventListener('click', () => ws.ctx.selection.set(ws.asm?.pieces.find((p) => p.name === dg.pieces[0])?.components[0] ?? dg.pieces[0], null));
      }
      list.append(li);
    }
    if (!list.children.length) list.append(el('li', { class: 'fp-ok' }, asm ? (asm.placed ? 'No warnings: every connection makes its joint, every joint fits.' : '') : 'Add components to see the model.'));
    box.append(list);
    if (asm?.placed && asm.assembly_order.length) box.append(el('p', { class: 'hint', 'data-testid': 'assembly-order' }, `press-fit order: ${asm.assembly_order.map((s) => s.piece).join(' → ')}`));
  }

  renderJoints(): void {
    const box = this.right.joints; box.innerHTML = '';
    const asm = this.ws.asm;
    if (!asm?.joints.length) { box.append(el('p', { class: 'hint' }, 'No joints yet.')); return; }
    const count = (k: string) => asm.joints.filter((j) => j.kind === k).length;
    box.append(el('p', { class: 'hint', 'data-testid': 'joint-summary' }, `${asm.pieces.length} pieces, ${asm.joints.length} joints: ${count('finger-finger')} finger–finger, ${count('finger-hole')} finger–hole, ${count('slot-slot')} slot–slot; ${asm.joints.filter((j) => j.automatic).length} automatic`));
    const list = el('ul', { class: 'fp-list' });
    for (const j of asm.joints) {
      const sw = el('span', { class: 'swatch' }); sw.style.background = `#${JOINT_COLORS[j.kind].toString(16).padStart(6, '0')}`;
      list.append(el('li', { 'data-testid': `joint-${j.id}`, 'data-fp-piece': j.pieces[0] }, sw, ` j${j.id} ${j.kind} ${j.pieces.join(' – ')}, ${fmt(j.length_mm)} mm, ${j.fingers} ${j.kind === 'slot-slot' ? 'slots' : 'fingers'}`, j.automatic ? el('b', { class: 'fp-auto-tag' }, ' auto') : ''));
    }
    box.append(list);
  }

  renderView(): void {
    const box = this.right.view; box.innerHTML = '';
    const slider = el('input', { type: 'range', min: '0', max: '1', step: '0.05', value: String(this.ws.explode), 'data-testid': 'explode', title: 'Pull the pieces apart from the model\'s centre' }) as HTMLInputElement;
    slider.addEventListener('input', () => this.ws.setExplode(Number(slider.value)));
    box.append(el('div', { class: 'fp-row' }, el('span', { class: 'fp-label' }, 'exploded'), slider));
  }

  renderSheets(): void {
    const box = this.right.sheets; box.innerHTML = '';
    const ws = this.ws, asm = ws.asm;
    if (!asm?.placed) { box.append(el('p', { class: 'hint' }, asm ? 'The design is not placed: see Warnings.' : 'No pieces yet.')); return; }
    const { width: W, height: H } = asm.sheets;
    box.append(el('p', { class: 'hint', 'data-testid': 'sheet-summary' }, `${asm.sheets.count} sheet${asm.sheets.count === 1 ? '' : 's'} of ${W} × ${H} mm, ${(asm.sheets.utilisation * 100).toFixed(1)} % used`));
    asm.sheets.list.forEach((s, k) => {
      const root = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'fp-sheet', 'data-testid': `sheet-${k + 1}` });
      root.append(svg('rect', { x: 0, y: 0, width: W, height: H, class: 'fp-sheet-bg' }));
      const g = svg('g', { transform: `matrix(1 0 0 -1 0 ${H})` });
      for (const p of s.pieces) {
        const dpath = p.rings.map((r) => `M${r.map(([x, y]) => `${x} ${y}`).join('L')}Z`).join('');
        const path = svg('path', { d: dpath, class: 'fp-sheet-piece', 'fill-rule': 'evenodd', 'data-testid': `sheet-piece-${p.piece}`, 'data-fp-piece': p.piece });
        path.append(svg('title'));
        path.lastChild!.textContent = `${p.piece} (sheet ${k + 1}, turned ${p.rotation_deg}°)`;
        path.addEventListener('click', () => ws.ctx.selection.set(asm.pieces.find((x) => x.name === p.piece)?.components[0] ?? p.piece, null));
        path.addEventListener('pointerenter', () => { ws.ctx.scene.setHover(p.piece); this.hover(p.piece); });
        path.addEventListener('pointerleave', () => { ws.ctx.scene.setHover(null); this.hover(null); });
        g.append(path);
      }
      root.append(g);
      for (const l of s.labels) {
        const x = l.at[0], y = H - l.at[1];
        const t = svg('text', { x, y, 'font-size': l.height, class: l.text.startsWith('→') ? 'fp-sheet-mark' : 'fp-sheet-label', 'text-anchor': 'middle', 'dominant-baseline': 'middle', transform: `rotate(${-l.rotation} ${x} ${y})`, 'data-testid': 'sheet-label' });
        t.textContent = l.text;
        root.append(t);
      }
      const head = el('div', { class: 'fp-row' }, el('b', {}, `sheet ${k + 1}`), ` ${(s.utilisation * 100).toFixed(0)} % `);
      for (const kind of ['svg', 'dxf']) {
        const b = el('button', { 'data-testid': `sheet-${k + 1}-${kind}`, title: `Download sheet ${k + 1} as ${kind.toUpperCase()} (mm)` }, kind.toUpperCase());
        b.addEventListener('click', () => void ws.ctx.track(ws.downloadFiles(designToYamlOf(ws.design), fileStemOf(ws.design), [`sheet-${k + 1}.${kind}`])));
        head.append(b);
      }
      box.append(head, root);
    });
    this.highlightSheets();
  }

  private highlightSheets(): void {
    const sel = this.ws.ctx.selection.current.object;
    const piece = sel ? this.ws.pieceOf(sel) : null;
    for (const e of document.querySelectorAll('.fp-sheet-piece')) e.classList.toggle('selected', e.getAttribute('data-fp-piece') === piece);
  }
}

const fileStemOf = (d: FpDesign) => fileStem(d.name);
