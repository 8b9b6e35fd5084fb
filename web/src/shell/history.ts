// The command history shared by every workspace: unlimited undo/redo of whole document
// snapshots. A workspace never mutates the current document; it builds the next one and
// applies it as a command with a label ("connect a – b", "open file.yaml").

export type HistoryListener<D> = (doc: D, label: string) => void;

export class History<D> {
  private undoStack: { doc: D; label: string }[] = [];
  private redoStack: { doc: D; label: string }[] = [];
  private listeners: HistoryListener<D>[] = [];
  /** Bumped by every change; `savedAt` remembers the value at the last save or open. */
  private version = 0;
  private savedAt = 0;
  private nextVersion = 1;
  private versions: number[] = [];
  private redoVersions: number[] = [];
  /** Label of the command that produced the current document. */
  lastLabel = 'start';

  constructor(public current: D) {}

  onChange(listener: HistoryListener<D>): () => void {
    this.listeners.push(listener);
    return () => { this.listeners = this.listeners.filter((l) => l !== listener); };
  }

  private emit(label: string): void {
    this.lastLabel = label;
    for (const l of this.listeners) l(this.current, label);
  }

  /** Applies a command: `next` becomes current, the old document goes on the undo stack. */
  apply(next: D, label: string): void {
    this.undoStack.push({ doc: this.current, label });
    this.versions.push(this.version);
    this.redoStack = []; this.redoVersions = [];
    this.current = next;
    this.version = this.nextVersion++;
    this.emit(label);
  }

  /** Replaces the document and forgets the history (switching workspaces, restoring at start). */
  reset(doc: D, label = 'reset'): void {
    this.undoStack = []; this.redoStack = []; this.versions = []; this.redoVersions = [];
    this.current = doc;
    this.version = this.nextVersion++;
    this.savedAt = this.version;
    this.emit(label);
  }

  canUndo(): boolean { return this.undoStack.length > 0; }
  canRedo(): boolean { return this.redoStack.length > 0; }
  /** What Undo / Redo would do, for button tooltips. */
  undoLabel(): string | undefined { return this.undoStack[this.undoStack.length - 1]?.label; }
  redoLabel(): string | undefined { return this.redoStack[this.redoStack.length - 1]?.label; }

  undo(): void {
    const step = this.undoStack.pop(); if (!step) return;
    this.redoStack.push({ doc: this.current, label: step.label });
    this.redoVersions.push(this.version);
    this.current = step.doc;
    this.version = this.versions.pop()!;
    this.emit(`undo ${step.label}`);
  }

  redo(): void {
    const step = this.redoStack.pop(); if (!step) return;
    this.undoStack.push({ doc: this.current, label: step.label });
    this.versions.push(this.version);
    this.current = step.doc;
    this.version = this.redoVersions.pop()!;
    this.emit(`redo ${step.label}`);
  }

  /** Marks the current document as saved (downloaded or freshly opened). */
  markSaved(): void { this.savedAt = this.version; }
  /** Marks the current document as not saved to any file (a restored working copy). */
  markUnsaved(): void { this.savedAt = -1; }
  /** True when the current document differs from the last saved/opened one. */
  dirty(): boolean { return this.version !== this.savedAt; }
}
