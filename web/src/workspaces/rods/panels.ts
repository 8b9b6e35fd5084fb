// The rods workspace's panels: tools, parameters (drag to set r, σ, h), the selection's
// coordinates, the live checks, Make it (build, downloads, cut plan) and the hover tooltip.
import { ApiError } from '../../shell/server';
import type { Vec3 } from '../../shell/scene';
import { el } from '../../shell/ui';
import { fileStem } from '../../shell/shell';
import type { BuildJob } from './api';
import './rods.css';
import { jointName, parseKey, rodName } from './model';
import type { RodsDesign } from './model';
import { centroid, postable, rampColor } from './workspace';
import type { RodsWorkspace, Tool } from './workspace';

const ROD_MATERIALS = ['hardwood', 'oak', 'pine', 'bamboo', 'aluminium', 'steel'];
const JOINT_MATERIALS = ['pla', 'petg', 'abs', 'asa', 'nylon'];
const PROFILES: [number, string][] = [[0, 'circle'], [3, 'triangle'], [4, 'square'], [5, 'pentagon'], [6, 'hexagon'], [8, 'octagon']];

/** A value set by dragging (the value drawn next to the cursor) or typed. */
interface ScrubSpec { id: string; label: string; unit: string; min: number; max: number; perPixel: number; get: (d: RodsDesign) => number; set: (d: RodsDesign, v: number) => void; title: string }

export class Panels {
  private tools: HTMLElement;
  private params: HTMLElement;
  private selection: HTMLElement;
  private checks: HTMLElement;
  private make: HTMLElement;
  readonly assembly: HTMLElement;
  job: BuildJob | null = null;
  private jobYaml = '';
  private tip = document.getElementById('tooltip')!;
  private scrubTip: HTMLElement;

  constructor(private w: RodsWorkspace) {
    const ctx = w.ctx;
    this.tools = ctx.panel('left', 'rods-tools', 'Tools', { hint: 'Add nodes on the floor grid (A), select (click, shift-click, box), move with the gizmo or the fields; Connect (C), Split (S), Delete.' });
    this.params = ctx.panel('left', 'rods-params', 'Rods and joints', { hint: 'Drag a value sideways to change it (or type it). Every change is one undoable step.' });
    this.selection = ctx.panel('left', 'rods-selection', 'Selection');
    this.checks = ctx.panel('right', 'rods-checks', 'Checks', { hint: 'Live, never blocking: red parts fail a check (hover one for the reason).' });
    this.make = ctx.panel('right', 'rods-make', 'Make it', { hint: 'The exact joints (booleans) are made on the server; then download everything.' });
    this.assembly = ctx.panel('right', 'rods-assembly', 'Assemble', { hint: 'Step through the order the parts go together (← → keys).' });
    this.scrubTip = el('div', { class: 'rods-scrub-tip', 'data-testid': 'scrub-tip', hidden: '' });
    document.body.append(this.scrubTip);
    const importInput = el('input', { type: 'file', accept: '.obj', hidden: '', 'data-testid': 'import-obj-input' }) as HTMLInputElement;
    importInput.addEventListener('change', () => {
      const f = importInput.files?.[0]; if (!f) return;
      void ctx.track(f.text().then((t) => this.importObj(t, f.name)).finally(() => { importInput.value = ''; }));
    });
    document.body.append(importInput);
    ctx.toolbarButton('file', 'Import OBJ', 'import-obj', 'Read an OBJ wireframe (l) or mesh (f): its vertices become joints, its edges rods (undoable)', () => importInput.click());
    this.renderAll();
  }

  renderAll(): void { this.renderTools(); this.render(); this.renderMake(); }
  render(): void { this.renderParams(); this.renderSelection(); this.renderChecks(); }

  // ---------------------------------------------------------------- tools
  renderTools(): void {
    const w = this.w;
    const b = this.tools;
    b.innerHTML = '';
    const toolBtn = (t: Tool, text: string, title: string) => {
      const x = el('button', { 'data-testid': `tool-${t}`, title, class: w.tool === t ? 'active' : '', 'aria-pressed': String(w.tool === t) }, text);
      x.addEventListener('click', () => w.setTool(w.tool === t && t !== 'select' ? 'select' : t));
      return x;
    };
    const act = (id: string, text: string, title: string, f: () => void) => { const x = el('button', { 'data-testid': id, title }, text); x.addEventListener('click', f); return x; };
    b.append(el('div', { class: 'row' },
      toolBtn('select', 'Select', 'Click a joint or rod; shift-click adds to the selection'),
      toolBtn('add', 'Add node (A)', 'Click the floor grid to add a joint there (connected to the selected joint when that box is ticked)'),
      toolBtn('box', 'Box select', 'Drag a rectangle: every joint inside is selected (shift adds)')));
    const mode = (m: 'translate' | 'rotate' | 'scale', text: string, title: string) => {
      const x = el('button', { 'data-testid': `gizmo-${m}`, title, class: w.gizmoMode === m ? 'active' : '' }, text);
      x.addEventListener('click', () => w.setGizmoMode(m));
      return x;
    };
    b.append(el('div', { class: 'row' }, el('span', {}, 'gizmo '), mode('translate', 'Move (G)', 'Drag an arrow or plane of the gizmo to move the selected joints'),
      mode('rotate', 'Rotate (R)', 'Rotate the selected joints about their centre (two or more)'), mode('scale', 'Scale (X)', 'Scale the selected joints about their centre (two or more)')));
    b.append(el('div', { class: 'row' },
      act('connect', 'Connect (C)', 'A new rod between two selected joints (with more: from the first picked to each of the others)', () => w.connectSelected()),
      act('split', 'Split (S)', 'Split the selected rod by a new joint at its midpoint', () => w.splitSelected()),
      act('delete', 'Delete', 'Delete the selected joints (with their rods) and rods (Delete key)', () => w.deleteSelected())));
    const grid = el('select', { 'data-testid': 'grid', title: 'Snap new nodes and gizmo moves to this grid (mm); rotations snap to 15°' }) as HTMLSelectElement;
    for (const g of [0, 1, 5, 10, 25, 50, 100]) grid.append(el('option', { value: String(g) }, g ? `${g} mm` : 'off'));
    grid.value = String(w.grid);
    grid.addEventListener('change', () => { w.grid = Number(grid.value); w.setSnapping(); });
    const axis = el('input', { type: 'checkbox', 'data-testid': 'axis-snap', title: 'Snap a rod onto the x, y or z direction when it comes within a few degrees of it' }) as HTMLInputElement;
    axis.checked = w.axisSnap;
    axis.addEventListener('change', () => { w.axisSnap = axis.checked; });
    b.append(el('div', { class: 'row' }, 'grid ', grid, el('label', {}, axis, ' snap to axes')));
    const z = el('input', { type: 'number', step: 'any', value: String(w.workZ), 'data-testid': 'work-z', style: 'width:70px', title: 'Height of the plane new nodes are added on (mm)' }) as HTMLInputElement;
    z.addEventListener('change', () => { const v = Number(z.value); if (Number.isFinite(v) && Math.abs(v) < 1e5) w.workZ = v; else z.value = String(w.workZ); });
    const conn = el('input', { type: 'checkbox', 'data-testid': 'connect-on-add', title: 'A new node gets a rod to the selected joint' }) as HTMLInputElement;
    conn.checked = w.connectOnAdd;
    conn.addEventListener('change', () => { w.connectOnAdd = conn.checked; });
    b.append(el('div', { class: 'row' }, 'add at z ', z, ' mm ', el('label', {}, conn, ' connect to selected')));
    const numbers = el('input', { type: 'checkbox', 'data-testid': 'show-numbers', title: 'Draw each joint\'s number (its engraved ID; rods are named by their two joints)' }) as HTMLInputElement;
    numbers.checked = w.showNumbers;
    numbers.addEventListener('change', () => { w.showNumbers = numbers.checked; w.drawNumbers(); w.ctx.scene.render(); });
    b.append(el('div', { class: 'row' }, el('label', {}, numbers, ' joint numbers')));
  }

  // ---------------------------------------------------------------- parameters
  renderParams(): void {
    const w = this.w;
    const d = w.ctx.history.current;
    const b = this.params;
    b.innerHTML = '';
    const specs: ScrubSpec[] = [
      { id: 'diameter', label: '2r', unit: 'mm', min: 1, max: 100, perPixel: 0.05, get: (x) => 2 * x.rod.radius, set: (x, v) => { x.rod.radius = v / 2; }, title: 'Rod diameter 2r (a polygon: twice its circumradius)' },
      { id: 'wall', label: 'σ', unit: 'mm', min: 0.4, max: 20, perPixel: 0.02, get: (x) => x.joint.wall, set: (x, v) => { x.joint.wall = v; }, title: 'Joint wall thickness σ' },
      { id: 'socket', label: 'h', unit: 'mm', min: 2, max: 200, perPixel: 0.2, get: (x) => x.joint.socket, set: (x, v) => { x.joint.socket = v; }, title: 'Socket length h: how far a joint overhangs each rod' },
      { id: 'tolerance', label: 'ε', unit: 'mm', min: -1, max: 2, perPixel: 0.005, get: (x) => x.joint.tolerance, set: (x, v) => { x.joint.tolerance = v; }, title: 'Socket clearance ε (negative: press fit)' },
    ];
    for (const s of specs) b.append(this.scrubber(s, d));
    const prof = el('select', { 'data-testid': 'profile', title: 'Profile p: round, or a polygon with this many sides' }) as HTMLSelectElement;
    for (const [n, name] of PROFILES) prof.append(el('option', { value: String(n) }, n ? `${name} (p = ${n})` : 'circle'));
    if (!PROFILES.some(([n]) => n === d.rod.sides)) prof.append(el('option', { value: String(d.rod.sides) }, `p = ${d.rod.sides}`));
    prof.value = String(d.rod.sides);
    prof.addEventListener('change', () => w.setParams((x) => { x.rod.sides = Number(prof.value); }, `set profile to ${prof.selectedOptions[0].textContent}`));
    b.append(el('div', { class: 'row' }, el('span', { class: 'scrub-name' }, 'p'), prof));
    const mat = (id: string, options: string[], value: unknown, set: (x: RodsDesign, v: string) => void, title: string) => {
      const s = el('select', { 'data-testid': id, title }) as HTMLSelectElement;
      const current = typeof value === 'string' ? value : 'custom';
      for (const o of options) s.append(el('option', { value: o }, o));
      if (!options.includes(current)) s.append(el('option', { value: current }, current === 'custom' ? 'custom (from the file)' : current));
      s.value = current;
      s.addEventListener('change', () => { if (s.value !== 'custom') w.setParams((x) => set(x, s.value), `set ${id.replace('-', ' ')} to ${s.value}`); });
      return s;
    };
    b.append(el('div', { class: 'row' }, 'rods ', mat('rod-material', ROD_MATERIALS, d.rod.material, (x, v) => { x.rod.material = v; }, 'Rod material (density, stiffness and strength for balance and the frame analysis)'),
      ' joints ', mat('joint-material', JOINT_MATERIALS, d.joint.material, (x, v) => { x.joint.material = v; }, 'Printing material (its density)')));
  }

  private scrubber(s: ScrubSpec, d: RodsDesign): HTMLElement {
    const w = this.w;
    const value = s.get(d);
    const name = el('span', { class: 'scrub-name', 'data-testid': `scrub-${s.id}`, title: `${s.title}: drag sideways to change`, role: 'slider', 'aria-valuenow': String(value), tabindex: '0' }, s.label);
    const field = el('input', { type: 'number', step: 'any', value: String(+value.toFixed(4)), 'data-testid': `param-${s.id}`, style: 'width:70px', title: s.title }) as HTMLInputElement;
    const clamp = (v: number) => Math.min(s.max, Math.max(s.min, Math.round(v * 1000) / 1000));
    field.addEventListener('change', () => {
      const v = Number(field.value);
      if (!Number.isFinite(v) || v < s.min || v > s.max) { w.ctx.message(`${s.label} must be between ${s.min} and ${s.max} ${s.unit}, not ${field.value}.`); field.value = String(value); return; }
      w.setParams((x) => s.set(x, v), `set ${s.label} to ${v} ${s.unit}`);
    });
    name.addEventListener('pointerdown', (e) => {
      e.preventDefault();
      (name as HTMLElement).setPointerCapture(e.pointerId);
      const x0 = e.clientX;
      let v = value;
      const show = (ev: PointerEvent) => {
        this.scrubTip.hidden = false;
        this.scrubTip.textContent = `${s.label} = ${v.toFixed(2)} ${s.unit}`;
        this.scrubTip.style.left = `${ev.clientX + 14}px`; this.scrubTip.style.top = `${ev.clientY - 24}px`;
      };
      show(e);
      const move = (ev: PointerEvent) => {
        v = clamp(value + (ev.clientX - x0) * s.perPixel);
        field.value = String(v);
        show(ev);
        w.setParams((x) => s.set(x, v), null);
      };
      const up = () => {
        name.removeEventListener('pointermove', move as EventListener);
        name.removeEventListener('pointerup', up);
        this.scrubTip.hidden = true;
        if (v !== value) w.setParams((x) => s.set(x, v), `set ${s.label} to ${v} ${s.unit}`);
        else { w.draft = null; w.requestPreview(w.ctx.history.current); }
      };
      name.addEventListener('pointermove', move as EventListener);
      name.addEventListener('pointerup', up);
    });
    name.addEventListener('keydown', (e) => {
      if (e.key !== 'ArrowLeft' && e.key !== 'ArrowRight') return;
      e.preventDefault();
      const v = clamp(value + (e.key === 'ArrowRight' ? 1 : -1) * s.perPixel * 10);
      w.setParams((x) => s.set(x, v), `set ${s.label} to ${v} ${s.unit}`);
    });
    return el('div', { class: 'row scrub' }, name, field, ` ${s.unit}`);
  }

  // ---------------------------------------------------------------- selection
  renderSelection(): void {
    const w = this.w;
    const d = w.doc;
    const b = this.selection;
    b.innerHTML = '';
    const { nodes, rods } = w.sel;
    if (!nodes.length && !rods.length) { b.append(el('p', { class: 'hint' }, 'Click a joint or a rod in the view.')); return; }
    if (nodes.length) {
      const c = centroid(nodes.map((i) => d.nodes[i]));
      b.append(el('div', {}, el('b', {}, nodes.length === 1 ? jointName(d, nodes[0]) : `${nodes.length} joints (their centre)`)));
      const row = el('div', { class: 'row' });
      (['x', 'y', 'z'] as const).forEach((axis, k) => {
        const f = el('input', { type: 'number', step: 'any', value: String(+c[k].toFixed(3)), 'data-testid': `node-${axis}`, style: 'width:72px', title: `${axis} (mm)` }) as HTMLInputElement;
        f.addEventListener('change', () => {
          const v = Number(f.value);
          if (!Number.isFinite(v) || Math.abs(v) > 1e5) { w.ctx.message(`${axis} must be a number of mm within ±100 m, not ${f.value}.`); return; }
          const next = [...c] as Vec3; next[k] = v;
          w.moveSelectionTo(next);
        });
        row.append(`${axis} `, f, ' ');
      });
      b.append(row, el('span', { class: 'hint' }, 'mm'));
      for (const i of nodes.length === 1 ? nodes : []) {
        const j = w.previewJoint(i);
        if (j) b.append(el('div', { class: 'hint' }, `${j.rods.length} rod${j.rods.length === 1 ? '' : 's'}, smallest angle ${j.smallest_angle.toFixed(1)}°, largest offset ${j.max_offset.toFixed(1)} mm`));
      }
    }
    for (const e of rods.slice(0, 4)) {
      const r = w.preview?.rods[e];
      b.append(el('div', { 'data-testid': `selected-rod-${e}` }, el('b', {}, rodName(d, e)), r ? `: cut ${r.length.toFixed(1)} mm (edge ${r.edge_length.toFixed(1)} mm)` : ''));
    }
  }

  // ---------------------------------------------------------------- checks
  renderChecks(): void {
    const w = this.w;
    const b = this.checks;
    b.innerHTML = '';
    const p = w.preview;
    if (w.previewError) b.append(el('div', { class: 'finding error', 'data-testid': 'preview-error' }, `cannot be made: ${w.previewError}`));
    if (!p) { b.append(el('p', { class: 'hint' }, 'Add nodes and connect them: the checks appear here.')); return; }
    const list = el('div', { 'data-testid': 'findings' });
    const shown = p.findings.filter((f) => f.severity !== 'note' || f.code === 'rods-intersect' || f.code === 'unbalanced');
    for (const f of shown) {
      const item = el('div', { class: `finding ${f.severity}`, 'data-testid': `finding-${f.code}`, title: 'Click to select the parts it names' }, f.message);
      item.addEventListener('mouseenter', () => { const k = f.rods.length ? `r${f.rods[0]}` : null; w.ctx.scene.setHover(k); });
      item.addEventListener('mouseleave', () => w.ctx.scene.setHover(null));
      item.addEventListener('click', () => w.select(f.joints.map((k) => w.kept[k]).filter((i) => i !== undefined), f.rods));
      list.append(item);
    }
    const errors = p.findings.filter((f) => f.severity === 'error').length;
    b.append(el('div', { 'data-testid': 'checks-summary', class: errors ? 'finding error' : 'finding ok' }, errors ? `${errors} check${errors === 1 ? '' : 's'} failed (the design can still be built)` : 'every check passes'));
    b.append(list);
    const lengths = p.rods.map((r) => r.length);
    if (lengths.length) b.append(el('div', { class: 'hint', 'data-testid': 'rod-lengths' }, `${p.joints.length} joints, ${p.rods.length} rods, cut ${Math.min(...lengths).toFixed(1)} to ${Math.max(...lengths).toFixed(1)} mm (${(lengths.reduce((a, x) => a + Math.max(0, x), 0) / 1000).toFixed(2)} m)`));
    const f = p.frame;
    if (f.solved) {
      const worst = f.critical_rod >= 0 ? p.rods[f.critical_rod] : null;
      const ramp = el('input', { type: 'checkbox', 'data-testid': 'ramp-toggle', title: 'Colour every rod by how much of its strength (or buckling load) it uses' }) as HTMLInputElement;
      ramp.checked = w.ramp;
      ramp.addEventListener('change', () => { w.ramp = ramp.checked; w.legend(); w.draw(); });
      const sw = el('span', { class: 'rods-swatch', style: `background:#${rampColor(f.max_utilisation).toString(16).padStart(6, '0')}` });
      b.append(el('div', { 'data-testid': 'frame-summary' }, sw, ` structure: largest utilisation ${f.max_utilisation.toFixed(2)}${worst ? ` (${worst.name}, ${worst.governing})` : ''}, largest deflection ${f.max_deflection.toFixed(2)} mm`),
        el('label', {}, ramp, ' colour rods by utilisation'));
    }
    const t = p.timings;
    b.append(el('div', { class: 'hint', 'data-testid': 'preview-timing' }, `library ${t.library_ms.toFixed(1)} ms, server ${t.server_ms.toFixed(1)} ms`));
  }

  // ---------------------------------------------------------------- hover
  hover(key: string | null, x: number, y: number): void {
    const t = this.tip;
    const k = parseKey(key);
    const w = this.w;
    if (!k || !w.preview) { t.hidden = true; return; }
    const d = w.doc;
    const lines: string[] = [];
    if (k.kind === 'rod') {
      const r = w.preview.rods[k.index]; if (!r) { t.hidden = true; return; }
      lines.push(`${rodName(d, k.index)}: cut ${r.length.toFixed(1)} mm`);
      lines.push(`edge ${r.edge_length.toFixed(1)} mm, offsets ${r.offsets[0].toFixed(1)} + ${r.offsets[1].toFixed(1)} mm`);
      if (r.utilisation !== undefined) lines.push(`utilisation ${r.utilisation.toFixed(2)} (${r.governing}), axial ${r.axial!.toFixed(1)} N`);
    } else {
      const j = w.previewJoint(k.index);
      if (!j) lines.push(`${jointName(d, k.index)}: no rod yet — select it and another joint, then Connect`);
      else lines.push(`${jointName(d, k.index)}: ${j.rods.length} rod${j.rods.length === 1 ? '' : 's'}, smallest angle ${j.smallest_angle.toFixed(1)}°, largest offset ${j.max_offset.toFixed(1)} mm`);
    }
    const reasons = w.findingsOf(key!);
    t.innerHTML = '';
    for (const l of lines) t.append(el('div', {}, l));
    for (const f of reasons) t.append(el('div', { class: 'tip-error' }, f.message));
    t.dataset.key = key!;
    t.hidden = false;
    t.style.left = `${x + 14}px`; t.style.top = `${y + 14}px`;
  }

  // ---------------------------------------------------------------- files
  private async importObj(text: string, name: string): Promise<void> {
    const w = this.w;
    try {
      const r = await w.api.importObj(text);
      const next = JSON.parse(JSON.stringify(w.ctx.history.current)) as RodsDesign;
      next.nodes = r.nodes; next.edges = r.edges; next.loads = []; next.supports = []; next.assemblyStart = null;
      if (next.name === 'untitled') next.name = name.replace(/\.obj$/i, '');
      w.sel = { nodes: [], rods: [] };
      w.ctx.message(r.diagnostics.length ? r.diagnostics.map((x) => x.message).join('; ') : '', 'info');
      w.ctx.history.apply(next, `import ${name} (${r.nodes.length} joints, ${r.edges.length} rods)`);
    } catch (e) {
      if (e instanceof ApiError) w.ctx.message(`cannot import ${name}: ${e.message}`); else throw e;
    }
  }

  // ---------------------------------------------------------------- make it
  async build(): Promise<void> {
    const w = this.w;
    const d = w.ctx.history.current;
    if (!d.edges.length) { w.ctx.message('Nothing to build yet: add joints and connect them.', 'info'); return; }
    const { yaml } = postable(d);
    this.jobYaml = yaml;
    const run = async () => {
      try {
        this.cutPlanUrl = null;
        this.job = await w.api.startBuild(yaml);
        this.renderMake();
        while (this.job.state === 'running') {
          await new Promise((r) => setTimeout(r, 150));
          this.job = await w.api.job(this.job.job);
          this.renderMake();
        }
        if (this.job.state === 'done') await this.showCutPlan();
      } catch (e) {
        if (e instanceof ApiError) { w.ctx.message(`cannot build: ${e.message}`); this.job = null; this.renderMake(); } else throw e;
      }
    };
    await w.ctx.track(run());
  }

  private async showCutPlan(): Promise<void> {
    const job = this.job; if (!job?.result) return;
    if (!job.result.files.some((f) => f.name === 'cut_plan.svg')) return;
    const svg = await (await fetch(this.w.api.fileUrl(job.job, 'cut_plan.svg'))).text();
    if (this.cutPlanUrl) URL.revokeObjectURL(this.cutPlanUrl);
    this.cutPlanUrl = URL.createObjectURL(new Blob([svg], { type: 'image/svg+xml' }));
    this.renderMake();
  }
  private cutPlanUrl: string | null = null;

  renderMake(): void {
    const w = this.w;
    const b = this.make;
    b.innerHTML = '';
    const btn = el('button', { 'data-testid': 'build-panel', class: 'primary', title: 'Build the exact joints, 3MF, cut plan and assembly guide' }, 'Build everything');
    btn.addEventListener('click', () => void this.build());
    b.append(btn);
    const job = this.job;
    if (!job) return;
    const stale = this.jobYaml !== postable(w.ctx.history.current).yaml;
    if (job.state === 'running') {
      b.append(el('div', {}, el('progress', { max: String(Math.max(1, job.total)), value: String(job.done), 'data-testid': 'build-progress' }),
        el('span', { 'data-testid': 'build-progress-text' }, ` joint ${job.done} of ${job.total} (exact booleans, ${job.seconds.toFixed(1)} s)`)));
      return;
    }
    const r = job.result!;
    if (job.state === 'failed') { b.append(el('div', { class: 'finding error', 'data-testid': 'build-error' }, r.error ?? r.message)); return; }
    const closed = r.joints?.filter((j) => j.closed && !j.self_intersecting).length ?? 0;
    b.append(el('div', { 'data-testid': 'build-summary', class: r.termination === 'built' ? 'finding ok' : 'finding warning' },
      `${r.message}: ${r.joints?.length ?? 0} joints (${closed} closed solids)${r.cut_plan ? `, ${r.cut_plan.summary}` : ''} in ${job.seconds.toFixed(1)} s`));
    if (stale) b.append(el('div', { class: 'hint', 'data-testid': 'build-stale' }, 'The design changed since this build: build again for its files.'));
    const stem = fileStem(w.ctx.history.current.name);
    const list = el('div', { class: 'downloads', 'data-testid': 'downloads' });
    const order = (n: string) => (n.endsWith('.3mf') ? 0 : n.startsWith('cut_') ? 1 : n === 'assembly.json' ? 2 : n.endsWith('.stl') ? 4 : 3);
    for (const f of [...r.files].sort((a, x) => order(a.name) - order(x.name) || a.name.localeCompare(x.name))) {
      const a = el('a', { href: w.api.fileUrl(job.job, f.name), download: f.name.endsWith('.stl') || f.name === 'joints.3mf' || f.name === 'scene.glb' ? f.name : `${stem}_${f.name}`, 'data-testid': `download-${f.name}`, title: `${(f.bytes / 1024).toFixed(1)} kB` }, f.name);
      list.append(a, ' ');
    }
    b.append(list);
    const guide = el('button', { 'data-testid': 'guide-open', title: 'A printable page: one small picture and one line per assembly step (print it from the browser)' }, 'Printable assembly guide');
    guide.addEventListener('click', () => void w.ctx.track(w.assembler.openGuide()));
    const guideDl = el('button', { 'data-testid': 'guide-download', title: 'The same guide as an HTML file' }, 'Download guide (HTML)');
    guideDl.addEventListener('click', () => void w.ctx.track(w.assembler.downloadGuide()));
    b.append(el('div', { class: 'row' }, guide, guideDl));
    const plan = el('div', { 'data-testid': 'cut-plan', class: 'cut-plan' }, el('b', {}, 'Cut plan'), r.cut_plan ? ` ${r.cut_plan.summary}` : '');
    if (r.cut_plan) plan.append(cutPlanDrawing(r.cut_plan));
    // the server's true-size SVG, as an image (an <img> never runs what is in it): click for full size
    if (this.cutPlanUrl) {
      const a = el('a', { href: this.cutPlanUrl, target: '_blank', title: 'cut_plan.svg at full size' },
        el('img', { alt: 'cut plan (true size)', 'data-testid': 'cut-plan-image', src: this.cutPlanUrl, style: 'width:100%' }));
      plan.append(a);
    }
    b.append(plan);
  }
}

/** The cut plan as bars: one per stock rod, its pieces labelled, end padding and remainder grey. */
function cutPlanDrawing(plan: NonNullable<import('./api').BuildResult['cut_plan']>): SVGSVGElement {
  const ns = 'http://www.w3.org/2000/svg';
  const W = 320, row = 26, L = plan.stock_length, sx = W / L;
  const svg = document.createElementNS(ns, 'svg');
  svg.setAttribute('viewBox', `0 0 ${W} ${plan.stock.length * row + 4}`);
  svg.setAttribute('width', '100%');
  svg.dataset.testid = 'cut-plan-bars';
  const add = (tag: string, attrs: Record<string, string | number>, text?: string) => {
    const e = document.createElementNS(ns, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
    if (text) e.textContent = text;
    svg.append(e);
    return e;
  };
  plan.stock.forEach((cut, i) => {
    const y = i * row + 2;
    add('rect', { x: 0, y, width: W, height: row - 8, fill: '#e8e8e8', stroke: '#889', 'stroke-width': 0.5 });
    for (const piece of cut.pieces) {
      const x = (plan.end_padding + piece.start) * sx, w = piece.length * sx;
      add('rect', { x, y, width: w, height: row - 8, fill: '#c89b66', stroke: '#5a3a14', 'stroke-width': 0.6 }).append(
        Object.assign(document.createElementNS(ns, 'title'), { textContent: `${piece.label}: ${piece.length.toFixed(1)} mm` }));
      add('text', { x: x + w / 2, y: y + 12, 'font-size': 7.5, 'text-anchor': 'middle', fill: '#2b1a08' }, `${piece.label.replace('rod ', '')} ${piece.length.toFixed(1)}`);
    }
    add('text', { x: W - 2, y: y + row - 1, 'font-size': 6.5, 'text-anchor': 'end', fill: '#667' }, `stock ${i + 1}: ${cut.remainder.toFixed(0)} mm left`);
  });
  return svg;
}
