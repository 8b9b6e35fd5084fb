// What is selected and what is under the pointer, shared by the scene, the panels and the
// selection label. Keys are the workspace's own: an object ("eyehook1") and optionally one of
// its pickable pieces ("eyehook1.hook"); the scene uses the same keys for its pickables.

export interface SelectionState { object: string | null; piece: string | null }

export class Selection {
  current: SelectionState = { object: null, piece: null };
  hover: string | null = null;
  private listeners: (() => void)[] = [];

  onChange(l: () => void): () => void {
    this.listeners.push(l);
    return () => { this.listeners = this.listeners.filter((x) => x !== l); };
  }
  private emit(): void { for (const l of this.listeners) l(); }

  set(object: string | null, piece: string | null = null): void {
    if (this.current.object === object && this.current.piece === piece) return;
    this.current = { object, piece };
    this.emit();
  }
  clear(): void { this.set(null, null); }
  setHover(key: string | null): void {
    if (this.hover === key) return;
    this.hover = key;
    this.emit();
  }
  /** Drops a selection whose object no longer exists (after undo, open, delete). */
  keepOnly(exists: (object: string) => boolean): void {
    if (this.current.object && !exists(this.current.object)) this.clear();
    if (this.hover && !exists(this.hover.split('.')[0])) this.setHover(null);
  }
}
