// What every browser test file of the web editor shares: a `fabkit serve` on a free port, a
// tiny test runner (name prefixes on the command line pick tests) and the page helpers that
// wait for the editor to be idle. The files: run.mjs (hacks and the shell), rods_, flatpack_
// and templates_workspace.mjs.
import { spawn } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const fabkit = process.env.FABKIT || path.join(repo, 'build/bin/fabkit');

/** Starts `fabkit serve --port 0 ...args`; resolves to { proc, url } once it listens. */
export function startServer(args = []) {
  return new Promise((resolve, reject) => {
    const proc = spawn(fabkit, ['serve', '--port', '0', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    const timer = setTimeout(() => reject(new Error(`server did not start: ${out}`)), 15000);
    proc.stdout.on('data', (b) => {
      out += b;
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) { clearTimeout(timer); resolve({ proc, url: `http://127.0.0.1:${m[1]}/` }); }
    });
    proc.stderr.on('data', (b) => { out += b; });
    proc.on('exit', (code) => reject(new Error(`server exited (${code}): ${out}`)));
  });
}

export function assert(cond, msg) { if (!cond) throw new Error(msg); }
export const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};

/** A runner: test(name, fn) runs fn unless the command line names other tests; finish() prints
 * the count and exits non-zero when one failed. */
export function makeTests(only = process.argv.slice(2)) {
  const results = [];
  async function test(name, fn) {
    if (only.length && !only.some((o) => name.startsWith(o))) return;
    const t0 = Date.now();
    try { await fn(); results.push([name, 'ok']); console.log(`ok   ${name} (${Date.now() - t0} ms)`); }
    catch (e) { results.push([name, 'FAIL']); console.log(`FAIL ${name}: ${e.stack || e}`); }
  }
  function finish() {
    const failed = results.filter((r) => r[1] !== 'ok');
    console.log(`${results.length - failed.length} passed, ${failed.length} failed`);
    process.exit(failed.length ? 1 : 0);
  }
  return { test, finish };
}

// ------------------------------------------------------------------ page helpers
export async function idle(page) {
  await page.waitForFunction(() => window.__fabkit && window.__fabkit.ready && window.__fabkit.idle(), null, { timeout: 120000 });
}
export async function click(page, testid) { await page.getByTestId(testid).click(); await idle(page); }
export async function setField(page, testid, value) {
  const f = page.getByTestId(testid);
  await f.fill(String(value));
  await f.dispatchEvent('change');
  await idle(page);
}
