// How a workspace plugs into the shell (docs/editor.md, "Adding a workspace").
//
// A workspace is the editor of one kit's designs (hacks, rods, flatpack, templates). The shell
// owns what every workspace shares — the document's command history, files (open, save,
// download, the working copy in local storage), the server client, the selection and the 3D
// view — and hands a workspace a ShellContext when it is mounted. The workspace owns its
// document type D, its panels, its scene layers and its commands.
import type { History } from './history';
import type { KitClient } from './server';
import type { SceneView } from './scene';
import type { Selection, SelectionState } from './selection';

/** What a workspace module exports (registered in src/workspaces/index.ts). */
export interface WorkspaceModule<D = any> {
  /** The kit: the server's route prefix (`/api/<kit>/...`) and the `fabkit: <kit>/1` file header. */
  kit: string;
  /** Shown in the workspace switcher ("Hacks"). */
  title: string;
  /** One line for the switcher's tooltip. */
  summary: string;
  /** A new, empty document. */
  empty(): D;
  /** Reads a design file's text; throws an Error whose message says what is wrong. */
  parse(text: string): D;
  /** Writes the document as the kit's design file (YAML with `fabkit: <kit>/1`). */
  serialize(doc: D): string;
  /** The design's name, used for download file names. */
  nameOf(doc: D): string;
  /** A copy of the document with another name (the toolbar's design-name field; without it the field is read-only). */
  withName?(doc: D, name: string): D;
  /** Builds the workspace's panels and layers; called when the user switches to it. */
  mount(ctx: ShellContext<D>): MountedWorkspace;
}

/** A mounted workspace: what the shell calls while it is active. */
export interface MountedWorkspace {
  /** The yellow selection label's text ("Selected: primitive eyehook1.hook (hook) of part …"). */
  describeSelection(sel: SelectionState): string;
  /** Whether an object key still exists in the document (stale selections are dropped). */
  exists(object: string): boolean;
  /** The Delete key with a selection: delete it as one command. */
  deleteSelection?(): void;
  /** Esc: cancel the workspace's pending action; true if there was one. */
  cancel?(): boolean;
  /** The view's hide / see-through / isolate state changed (Show all): re-render lists that show it. */
  onDisplayChange?(): void;
  /** Extra test/scripting hooks merged into `window.__fabkit`. */
  hooks?: Record<string, unknown>;
  /** Removes listeners; the shell empties the panels and scene layers itself. */
  unmount(): void;
}

/** Where a panel goes: the left or the right column. */
export type PanelSide = 'left' | 'right';

export interface ShellContext<D> {
  kit: string;
  /** Requests under `/api/<kit>/` (get, post, postBlob). */
  server: KitClient;
  /** The document and its undo/redo. Apply every change as a command: `history.apply(next, label)`. */
  history: History<D>;
  selection: Selection;
  /** The shared 3D view: draw into `scene.layer(name)`, make meshes `pickable`, set `onPick`. */
  scene: SceneView;
  /** A titled section in a side column; returns its body. `id` becomes `data-testid="panel-<id>"`. */
  panel(side: PanelSide, id: string, title: string, opts?: { hint?: string; collapsed?: boolean }): HTMLElement;
  /** A button in the toolbar: `group` 'file' (next to Save) or 'run' (after Undo/Redo). */
  toolbarButton(group: 'file' | 'run', text: string, testid: string, title: string, onClick: () => void, opts?: { primary?: boolean }): HTMLButtonElement;
  /** The status line in the toolbar ("solving…"); empty clears it. */
  status(text: string): void;
  /** A message banner over the 3D view; empty hides it. */
  message(text: string, kind?: 'error' | 'info'): void;
  /** Counts a running operation so the UI (and the tests' idle()) know when the editor is busy. */
  track<T>(p: Promise<T>): Promise<T>;
  /** Workspace state kept in local storage across reloads (e.g. the inventory). */
  store: { get<T>(key: string): T | undefined; set(key: string, value: unknown): void };
  /** Asks the user before something discards unsaved work; resolves true to go ahead. */
  confirmDiscard(what: string): Promise<boolean>;
  /** Re-renders the selection label (after the workspace's names changed). */
  refreshSelectionLabel(): void;
}
