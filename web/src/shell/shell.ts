// The shell: the toolbar, the two side columns, the 3D view, the workspace switcher, files
// (open, save, the working copy in local storage), undo/redo, keyboard and the test hooks.
// Everything kit-specific is in a workspace module (./workspace.ts).
import { History } from './history';
import { SceneView } from './scene';
import type { Vec3 } from './scene';
import { Selection } from './selection';
import { server } from './server';
import { download, el } from './ui';
import { LocalStore } from './storage';
import type { MountedWorkspace, PanelSide, ShellContext, WorkspaceModule } from './workspace';

const $ = (id: string) => document.getElementById(id)!;

/** The kit of a design file from its `fabkit: <kit>/<version>` header, if it has one. */
export function kitOfFile(text: string): string | null {
  const m = text.match(/^\s*fabkit:\s*["']?([A-Za-z0-9_]+)\//m);
  return m ? m[1] : null;
}

/** The four kits the editor is planned for, in switcher order (others the server reports follow). */
const PLANNED = [
  { kit: 'hacks', title: 'Hacks' }, { kit: 'rods', title: 'Rods' },
  { kit: 'flatpack', title: 'Flat-pack' }, { kit: 'templates', title: 'Templates' },
];

export class Shell {
  readonly scene: SceneView;
  readonly selection = new Selection();
  private modules = new Map<string, WorkspaceModule>();
  private serverKits: string[] = [];
  private active: { module: WorkspaceModule; mounted: MountedWorkspace; history: History<any>; offs: (() => void)[] } | null = null;
  private pending = 0;
  private storage = new LocalStore();
  ready = false;

  constructor(modules: WorkspaceModule[]) {
    for (const m of modules) this.modules.set(m.kit, m);
    this.scene = new SceneView($('view'));
    this.wire();
  }

  /** Counts running async operations; `idle()` is true when none is running. */
  track<T>(p: Promise<T>): Promise<T> {
    this.pending++;
    return p.finally(() => { this.pending--; });
  }
  idle(): boolean { return this.pending === 0; }

  status(text: string): void { $('status').textContent = text; }
  message(text: string, kind: 'error' | 'info' = 'error'): void {
    const m = $('message');
    m.textContent = text; m.className = kind; m.hidden = !text;
  }

  get history(): History<any> | null { return this.active?.history ?? null; }
  get kit(): string | null { return this.active?.module.kit ?? null; }

  /** A kit is available when the server has its routes and the editor has its workspace. */
  available(kit: string): boolean { return this.modules.has(kit) && this.serverKits.includes(kit); }

  private renderSwitcher(): void {
    const sel = $('workspace-switcher') as HTMLSelectElement;
    sel.innerHTML = '';
    const kits = [...PLANNED];
    for (const k of [...this.serverKits, ...this.modules.keys()]) if (!kits.some((p) => p.kit === k)) kits.push({ kit: k, title: this.modules.get(k)?.title ?? k });
    for (const k of kits) {
      const ok = this.available(k.kit);
      const why = !this.modules.has(k.kit) ? 'not yet available in the editor' : 'the server has no routes for it';
      const o = el('option', { value: k.kit, 'data-testid': `workspace-${k.kit}`, title: ok ? this.modules.get(k.kit)!.summary : why },
        ok ? k.title : `${k.title} (not yet available)`) as HTMLOptionElement;
      o.disabled = !ok;
      sel.append(o);
    }
    sel.value = this.kit ?? '';
  }

  /** Mounts the workspace of `kit` with its working copy from local storage (or an empty document). */
  switchTo(kit: string): void {
    const module = this.modules.get(kit);
    if (!module || !this.available(kit)) { this.message(`The ${kit} workspace is not available yet.`); this.renderSwitcher(); return; }
    if (this.active) {
      for (const off of this.active.offs) off();
      this.active.mounted.unmount();
    }
    $('left').innerHTML = ''; $('right').innerHTML = '';
    $('toolbar-file').innerHTML = ''; $('toolbar-run').innerHTML = '';
    $('pick-label').textContent = '';
    this.message('');
    this.scene.clearAll();
    this.selection.clear();
    const saved = this.storage.document(kit);
    let doc = module.empty();
    if (saved) {
      try { doc = module.parse(saved.text); } catch (e) { this.message(`The working copy in this browser could not be read (${(e as Error).message}); starting empty.`); }
    }
    const history = new History<any>(doc);
    if (saved?.dirty) history.markUnsaved(); // restored work that was never saved to a file
    const offs: (() => void)[] = [];
    offs.push(history.onChange((d) => {
      this.storage.setDocument(kit, module.serialize(d), history.dirty());
      this.renderUndo();
      this.renderName();
    }));
    offs.push(this.selection.onChange(() => this.renderSelectionLabel()));
    const ctx = this.context(module, history);
    const mounted = module.mount(ctx);
    this.active = { module, mounted, history, offs };
    this.storage.setLastKit(kit);
    this.renderSwitcher();
    this.renderUndo();
    this.renderSelectionLabel();
    this.renderName();
    this.exposeHooks();
  }

  private context<D>(module: WorkspaceModule<D>, history: History<D>): ShellContext<D> {
    const kit = module.kit;
    return {
      kit, history, selection: this.selection, scene: this.scene,
      server: server.kit(kit),
      panel: (side: PanelSide, id: string, title: string, opts = {}) => {
        const body = el('div', { class: 'panel-body', id: `panel-${id}-body` });
        const section = el('section', { class: 'panel', 'data-testid': `panel-${id}`, id: `panel-${id}` }, el('h2', {}, title));
        if (opts.hint) section.append(el('p', { class: 'hint' }, opts.hint));
        section.append(body);
        $(side).append(section);
        return body;
      },
      toolbarButton: (group, text, testid, title, onClick, opts = {}) => {
        const b = el('button', { 'data-testid': testid, id: testid, title, ...(opts.primary ? { class: 'primary' } : {}) }, text) as HTMLButtonElement;
        b.addEventListener('click', onClick);
        $(group === 'file' ? 'toolbar-file' : 'toolbar-run').append(b);
        return b;
      },
      status: (t) => this.status(t),
      message: (t, k) => this.message(t, k),
      track: (p) => this.track(p),
      store: { get: (key) => this.storage.get(kit, key), set: (key, v) => this.storage.set(kit, key, v) },
      confirmDiscard: (what) => this.confirmDiscard(what),
      refreshSelectionLabel: () => this.renderSelectionLabel(),
    };
  }

  private renderUndo(): void {
    const h = this.history;
    const u = $('undo') as HTMLButtonElement, r = $('redo') as HTMLButtonElement;
    u.disabled = !h?.canUndo(); r.disabled = !h?.canRedo();
    u.title = h?.canUndo() ? `Undo ${h.undoLabel()} (Ctrl+Z)` : 'Nothing to undo (Ctrl+Z)';
    r.title = h?.canRedo() ? `Redo ${h.redoLabel()} (Ctrl+Shift+Z)` : 'Nothing to redo (Ctrl+Shift+Z)';
  }

  private renderSelectionLabel(): void {
    if (!this.active) return;
    const m = this.active.mounted;
    this.selection.keepOnly((o) => m.exists(o));
    $('selection-label').textContent = m.describeSelection(this.selection.current);
  }

  private renderName(): void {
    const f = $('design-name') as HTMLInputElement;
    if (this.active && document.activeElement !== f) f.value = this.active.module.nameOf(this.active.history.current);
    f.readOnly = !this.active?.module.withName;
  }

  /** Column widths: dragging a splitter (or ←/→ on it) resizes its column; kept in local storage. */
  private wireSplitters(): void {
    const main = document.querySelector('main') as HTMLElement;
    const widths = this.storage.get<{ left?: number; right?: number }>('shell', 'columns') ?? {};
    const apply = () => {
      if (widths.left) main.style.setProperty('--left-w', `${widths.left}px`);
      if (widths.right) main.style.setProperty('--right-w', `${widths.right}px`);
    };
    apply();
    for (const side of ['left', 'right'] as const) {
      const sp = $(`splitter-${side}`);
      const col = $(side);
      const set = (w: number) => {
        const max = Math.max(200, window.innerWidth - 240 - (side === 'left' ? $('right') : $('left')).offsetWidth - 10);
        widths[side] = Math.round(Math.min(max, Math.max(160, w)));
        apply(); this.storage.set('shell', 'columns', widths);
      };
      sp.addEventListener('pointerdown', (e) => {
        e.preventDefault();
        const x0 = e.clientX, w0 = col.offsetWidth;
        sp.classList.add('dragging'); sp.setPointerCapture(e.pointerId);
        const move = (ev: PointerEvent) => set(side === 'left' ? w0 + ev.clientX - x0 : w0 - (ev.clientX - x0));
        const up = () => { sp.classList.remove('dragging'); sp.removeEventListener('pointermove', move); sp.removeEventListener('pointerup', up); };
        sp.addEventListener('pointermove', move); sp.addEventListener('pointerup', up);
      });
      sp.addEventListener('keydown', (e) => {
        if (e.key !== 'ArrowLeft' && e.key !== 'ArrowRight') return;
        e.preventDefault();
        const d = (e.key === 'ArrowRight' ? 20 : -20) * (side === 'left' ? 1 : -1);
        set(col.offsetWidth + d);
      });
    }
  }

  private renderProjection(): void {
    $('view-projection').textContent = this.scene.camera === this.scene.orthographic ? 'Orthographic' : 'Perspective';
  }

  /** Fits the selected piece or object in the view ("Frame selection", F). */
  frameSelection(): void {
    const s = this.selection.current;
    const keys = [s.piece, s.object].filter((k): k is string => !!k);
    if (!keys.length) { this.message('Select a part first (click it in the view or in a list), then Frame selection.', 'info'); return; }
    this.scene.frameKeys(s.piece ? [s.piece] : keys);
  }

  /** Asks before discarding unsaved work; resolves true when there is none or the user agrees. */
  confirmDiscard(what: string): Promise<boolean> {
    if (!this.history?.dirty()) return Promise.resolve(true);
    const dlg = $('confirm') as HTMLDialogElement;
    $('confirm-text').textContent = `${what} The current design has changes that are not saved to a file (Save YAML). You can also undo this afterwards.`;
    dlg.showModal();
    return new Promise((resolve) => {
      const done = (v: boolean) => { dlg.close(); ok.removeEventListener('click', yes); cancel.removeEventListener('click', no); dlg.removeEventListener('cancel', no); resolve(v); };
      const ok = $('confirm-ok'), cancel = $('confirm-cancel');
      const yes = () => done(true), no = () => done(false);
      ok.addEventListener('click', yes); cancel.addEventListener('click', no); dlg.addEventListener('cancel', no);
      (ok as HTMLButtonElement).focus();
    });
  }

  /** Opens a design file's text: switches to its kit's workspace if needed; an undoable step. */
  async openText(text: string, name: string): Promise<void> {
    const kit = kitOfFile(text) ?? this.kit ?? 'hacks';
    if (!this.available(kit)) { this.message(`cannot open ${name}: it is a ${kit} design, and the ${kit} workspace is not available yet`); return; }
    const module = this.modules.get(kit)!;
    let doc: unknown;
    try { doc = module.parse(text); } catch (e) { this.message(`cannot open ${name}: ${(e as Error).message}`); return; }
    if (kit !== this.kit) this.switchTo(kit);
    if (!(await this.confirmDiscard(`Open ${name}?`))) return;
    this.message('');
    this.selection.clear(); // the previous design's selection means nothing in this one
    this.history!.apply(doc, `open ${name}`);
    this.history!.markSaved();
    this.storage.setDocument(kit, module.serialize(doc), false);
  }

  /** An empty design as an undoable step (asks first when the current one is unsaved). */
  async newDesign(): Promise<void> {
    const a = this.active; if (!a) return;
    if (!(await this.confirmDiscard('Start a new, empty design?'))) return;
    this.selection.clear();
    a.history.apply(a.module.empty(), 'new design');
    a.history.markSaved();
    this.storage.setDocument(a.module.kit, a.module.serialize(a.history.current), false);
  }

  private save(): void {
    const a = this.active; if (!a) return;
    download(`${fileStem(a.module.nameOf(a.history.current))}.yaml`, a.module.serialize(a.history.current), 'application/x-yaml');
    a.history.markSaved();
    this.storage.setDocument(a.module.kit, a.module.serialize(a.history.current), false);
  }

  private wire(): void {
    this.wireSplitters();
    const nameField = $('design-name') as HTMLInputElement;
    nameField.addEventListener('change', () => {
      const a = this.active; const name = nameField.value.trim();
      if (!a || !a.module.withName || !name || name === a.module.nameOf(a.history.current)) { this.renderName(); return; }
      a.history.apply(a.module.withName(a.history.current, name), `rename design to ${name}`);
    });
    $('open-label').addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); ($('open-file') as HTMLInputElement).click(); } });
    // Keyboard access: Enter or Space on anything marked role="button" acts like a click.
    document.addEventListener('keydown', (e) => {
      const t = e.target as HTMLElement;
      if ((e.key === 'Enter' || e.key === ' ') && t.getAttribute?.('role') === 'button' && t.tagName !== 'BUTTON' && t.id !== 'open-label' && !(t instanceof SVGElement)) { e.preventDefault(); t.click(); }
    });
    $('undo').addEventListener('click', () => this.history?.undo());
    $('redo').addEventListener('click', () => this.history?.redo());
    $('save-yaml').addEventListener('click', () => this.save());
    $('new-design').addEventListener('click', () => void this.track(this.newDesign()));
    $('view-all').addEventListener('click', () => this.scene.frameAll());
    for (const v of ['top', 'front', 'side', 'iso'] as const) $(`view-${v}`).addEventListener('click', () => { this.scene.view(v); this.renderProjection(); });
    $('view-selection').addEventListener('click', () => this.frameSelection());
    $('view-projection').addEventListener('click', () => { this.scene.setOrthographic(this.scene.camera !== this.scene.orthographic); this.renderProjection(); });
    $('view-show-all').addEventListener('click', () => { this.scene.showAll(); this.active?.mounted.onDisplayChange?.(); });
    ($('workspace-switcher') as HTMLSelectElement).addEventListener('change', (e) => this.switchTo((e.target as HTMLSelectElement).value));
    const input = $('open-file') as HTMLInputElement;
    input.addEventListener('change', () => {
      const f = input.files?.[0]; if (!f) return;
      // Counted as busy until the file is read and opened (tests wait on idle()).
      void this.track(f.text().then((text) => this.openText(text, f.name)).finally(() => { input.value = ''; }));
    });
    document.addEventListener('keydown', (e) => {
      const tag = (e.target as HTMLElement).tagName;
      if (tag === 'INPUT' || tag === 'SELECT' || tag === 'TEXTAREA' || ($('confirm') as HTMLDialogElement).open) return;
      if (e.key === 'Escape') this.active?.mounted.cancel?.();
      if ((e.key === 'Delete' || e.key === 'Backspace') && !e.ctrlKey && !e.metaKey) { e.preventDefault(); this.active?.mounted.deleteSelection?.(); }
      if ((e.key === 'f' || e.key === 'F') && !e.ctrlKey && !e.metaKey) this.frameSelection();
      if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'z') { e.preventDefault(); if (e.shiftKey) this.history?.redo(); else this.history?.undo(); }
      if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'y') { e.preventDefault(); this.history?.redo(); }
    });
    const hooks = {
      ready: false,
      idle: () => this.idle(),
      kit: () => this.kit,
      screenPointOf: (key: string) => this.scene.screenPointOf(key),
      camera: () => ({
        type: this.scene.camera.type, zoom: this.scene.camera.zoom,
        position: this.scene.camera.position.toArray(), target: this.scene.controls.target.toArray(),
      }),
      /** Client coordinates of the centre of a piece's or object's meshes. */
      project: (key: string) => this.scene.projectKey(key),
      displayOf: (object: string) => this.scene.displayOf(object),
      setCamera: (pos: Vec3, target: Vec3) => { this.scene.camera.position.set(...pos); this.scene.controls.target.set(...target); this.scene.controls.update(); this.scene.render(); },
    };
    (window as any).__fabkit = hooks;
  }

  /** Test and scripting hooks: the shell's, then the active workspace's. */
  private exposeHooks(): void {
    const w = (window as any).__fabkit;
    Object.assign(w, this.active?.mounted.hooks ?? {});
  }

  /** Starts the editor: the server's kits, then the design the server was started with, else the working copy. */
  async start(): Promise<void> {
    this.status('loading…');
    this.serverKits = await server.kits();
    const initial = await server.design();
    const initialKit = initial ? kitOfFile(initial) ?? 'hacks' : null;
    const last = this.storage.lastKit();
    const kit = [initialKit, last, 'hacks', ...this.modules.keys()].find((k) => k && this.available(k));
    if (!kit) { this.status('error: the server offers no kit this editor knows'); this.renderSwitcher(); return; }
    this.switchTo(kit);
    this.status('');
    // A design given on the command line opens unless this browser's working copy started from it.
    if (initial && initialKit === kit && this.storage.origin(kit) !== hashText(initial)) {
      this.storage.setOrigin(kit, hashText(initial));
      const doc = this.active!.module.parse(initial);
      this.history!.apply(doc, 'open the server\'s design');
      this.history!.markSaved();
    }
    await this.waitIdle();
    this.ready = true;
    (window as any).__fabkit.ready = true;
    document.body.dataset.ready = '1';
  }

  private async waitIdle(): Promise<void> {
    while (!this.idle()) await new Promise((r) => setTimeout(r, 10));
  }
}

/** A file name from a design name ("Reading nook" → "Reading_nook"). */
export function fileStem(name: string): string {
  return (name || 'design').trim().replace(/[^\p{L}\p{N}._-]+/gu, '_').replace(/^_+|_+$/g, '') || 'design';
}

function hashText(s: string): string {
  let h = 2166136261;
  for (let i = 0; i < s.length; ++i) { h ^= s.charCodeAt(i); h = Math.imul(h, 16777619); }
  return (h >>> 0).toString(16);
}
