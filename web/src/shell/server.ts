// The client of `fabkit serve` shared by every workspace: JSON requests, errors with the
// server's diagnostics, and one client per kit rooted at `api/<kit>/` (server/src/kit_api.h).

export interface Diagnostic { severity: string; code?: string; message: string; line?: number; column?: number; text: string }

/** A request the server refused: the HTTP status (400 input, 422 infeasible, 503 time limit), its message and diagnostics. */
export class ApiError extends Error {
  constructor(public status: number, message: string, public diagnostics: Diagnostic[] = []) { super(message); }
}

/** A request cancelled by the user (AbortController); not an error to report. */
export const isAbort = (e: unknown) => e instanceof DOMException && e.name === 'AbortError';

async function parse<T>(res: Response): Promise<T> {
  const text = await res.text();
  let body: any = null;
  try { body = JSON.parse(text); } catch { /* not JSON */ }
  if (!res.ok) {
    const diags: Diagnostic[] = body?.diagnostics ?? [];
    const msg = body?.error ?? (diags.map((d) => d.message).join('; ') || text || res.statusText);
    throw new ApiError(res.status, msg, diags);
  }
  return body as T;
}

export type Query = Record<string, string | number>;
const qs = (q?: Query) => (q && Object.keys(q).length ? '?' + new URLSearchParams(Object.entries(q).map(([k, v]) => [k, String(v)])) : '');

const yamlType = { 'Content-Type': 'application/x-yaml' };

/** Requests under `api/<kit>/`; paths are relative ("parts", "check"). */
export class KitClient {
  constructor(readonly kit: string, private root = 'api') {}
  url(path: string, query?: Query): string { return `${this.root}/${this.kit}/${path}${qs(query)}`; }
  async get<T>(path: string, query?: Query, signal?: AbortSignal): Promise<T> { return parse<T>(await fetch(this.url(path, query), { signal })); }
  /** POSTs a body (a design's YAML text, or an object sent as JSON) and reads JSON back. The
   * server reads bodies only with a YAML or JSON type: a plain-text POST is what any web page
   * may send to 127.0.0.1 without asking (docs/security.md). */
  async post<T>(path: string, body: string | object, query?: Query, signal?: AbortSignal): Promise<T> {
    const init: RequestInit = typeof body === 'string' ? { method: 'POST', body, headers: yamlType, signal }
      : { method: 'POST', body: JSON.stringify(body), headers: { 'Content-Type': 'application/json' }, signal };
    return parse<T>(await fetch(this.url(path, query), init));
  }
  /** POSTs and returns the raw answer (binary downloads such as .glb). */
  async postBlob(path: string, body: string, query?: Query, signal?: AbortSignal): Promise<Blob> {
    const res = await fetch(this.url(path, query), { method: 'POST', body, headers: yamlType, signal });
    if (!res.ok) await parse(res);
    return res.blob();
  }
}

/** What is common to every kit: which kits the server has, and the design it was started with. */
export const server = {
  kits: async (): Promise<string[]> => {
    try { return (await parse<{ kits: string[] }>(await fetch('api/kits'))).kits; } catch { return []; }
  },
  /** The YAML the server was started with (`fabkit serve DESIGN.yaml`), or null. */
  design: async (): Promise<string | null> => {
    const res = await fetch('api/design');
    return res.ok ? res.text() : null;
  },
  kit: (kit: string) => new KitClient(kit),
};
