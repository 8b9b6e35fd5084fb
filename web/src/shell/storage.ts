// The working copy in the browser's local storage: each workspace's document (as its design
// file text, with whether it was saved to a file), the last workspace used, and small
// workspace state (the inventory). Keys: `fabkit.<kit>.<name>`. Storage can be full or
// disabled (private windows): then nothing is kept and the editor still works.

export class LocalStore {
  private read(key: string): string | null {
    try { return localStorage.getItem(key); } catch { return null; }
  }
  private write(key: string, value: string): void {
    try { localStorage.setItem(key, value); } catch { /* full or disabled: the editor works without it */ }
  }
  get<T>(kit: string, key: string): T | undefined {
    const s = this.read(`fabkit.${kit}.${key}`);
    if (s === null) return undefined;
    try { return JSON.parse(s) as T; } catch { return undefined; }
  }
  set(kit: string, key: string, value: unknown): void { this.write(`fabkit.${kit}.${key}`, JSON.stringify(value)); }

  document(kit: string): { text: string; dirty: boolean } | undefined { return this.get(kit, 'document'); }
  setDocument(kit: string, text: string, dirty: boolean): void { this.set(kit, 'document', { text, dirty }); }
  /** Hash of the server's start-up design this working copy came from. */
  origin(kit: string): string | undefined { return this.get(kit, 'origin'); }
  setOrigin(kit: string, hash: string): void { this.set(kit, 'origin', hash); }
  lastKit(): string | null { return this.read('fabkit.workspace'); }
  setLastKit(kit: string): void { this.write('fabkit.workspace', kit); }
}
