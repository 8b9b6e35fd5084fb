// Browser tests of the fabkit web editor: node web/tests/run.mjs
// Starts `fabkit serve --port 0` (which serves web/dist; run `npm run build` first), drives Debian's
// chromium with playwright-core and exits non-zero when a test fails.
// FABKIT_UPDATE_GOLDEN=1 rewrites tests/golden/basket.png.
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, existsSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const fabkit = process.env.FABKIT || path.join(repo, 'build/bin/fabkit');
const example = path.join(repo, 'examples/hacks/basket_between_rods.yaml');
const golden = path.join(here, 'golden/basket.png');
const only = process.argv.slice(2);

function startServer(args = []) {
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

function assert(cond, msg) { if (!cond) throw new Error(msg); }

const results = [];
async function test(name, fn) {
  if (only.length && !only.some((o) => name.startsWith(o))) return;
  const t0 = Date.now();
  try { await fn(); results.push([name, 'ok', Date.now() - t0]); console.log(`ok   ${name} (${Date.now() - t0} ms)`); }
  catch (e) { results.push([name, 'FAIL', Date.now() - t0]); console.log(`FAIL ${name}: ${e.stack || e}`); }
}

// ------------------------------------------------------------------ page helpers
async function idle(page) {
  await page.waitForFunction(() => window.__fabkit && window.__fabkit.ready && window.__fabkit.idle(), null, { timeout: 60000 });
}
async function click(page, testid) { await page.getByTestId(testid).click(); await idle(page); }
async function setField(page, testid, value) {
  const f = page.getByTestId(testid);
  await f.fill(String(value));
  await f.dispatchEvent('change');
  await idle(page);
}
async function selectLibPart(page, search, part) {
  await page.getByTestId('part-search').fill(search);
  await click(page, `lib-part-${part}`);
}
async function setFrame(page, id, pos, rot) {
  const names = ['x', 'y', 'z'], rnames = ['rx', 'ry', 'rz'];
  for (let i = 0; i < 3; ++i) if (pos[i] !== 0) await setField(page, `frame-${id}-${names[i]}`, pos[i]);
  for (let i = 0; i < 3; ++i) if (rot[i] !== 0) await setField(page, `frame-${id}-${rnames[i]}`, rot[i]);
}
async function connectNew(page, part, name, prim, sceneKey, { canvas = false } = {}) {
  await selectLibPart(page, part, part);
  await page.getByTestId('new-instance-name').fill(name);
  await click(page, `lib-prim-${prim}`);
  if (canvas) {
    const p = await page.evaluate((k) => window.__fabkit.screenPointOf(k), sceneKey);
    assert(p, `no visible point of ${sceneKey} on the canvas`);
    await page.mouse.click(p.x, p.y);
    await idle(page);
  } else await click(page, `scene-prim-${sceneKey}`);
}
async function connectScene(page, a, b) { await click(page, `scene-prim-${a}`); await click(page, `scene-prim-${b}`); }
async function connectionTexts(page) { return page.locator('[data-testid^="connection-text-"]').allTextContents(); }

/** The paper's Task 1 (Fig. 8), built by clicking. */
async function buildBasket(page) {
  await selectLibPart(page, 'TowelRack', 'ClosetRods');
  await click(page, 'set-environment');
  await setField(page, 'frame-env-0-name', 'rods');
  await setFrame(page, 'env-0', [0, 0, 200], [0, 0, -90]);
  await selectLibPart(page, 'basket', 'RoundHandleBasket');
  await click(page, 'set-target');
  await setField(page, 'frame-target-name', 'basket');
  await setFrame(page, 'target', [0, 0, 100], [-75, 0, 90]);
  await page.evaluate(() => document.getElementById('view-all').click());
  await connectNew(page, 'HookEyeConnector', 'eyehook1', 'ring', 'rods.rod1');
  await click(page, 'flip-0');
  await connectNew(page, 'HookEyeConnector', 'eyehook2', 'ring', 'rods.rod2', { canvas: true });
  await connectScene(page, 'eyehook1.hook', 'basket.hook');
  await connectScene(page, 'eyehook2.hook', 'basket.hook');
}

function decodePng(buf) { return PNG.sync.read(buf); }
async function canvasPng(page) {
  const url = await page.evaluate(() => document.querySelector('[data-testid=scene-canvas]').toDataURL('image/png'));
  return Buffer.from(url.split(',')[1], 'base64');
}

// ------------------------------------------------------------------ main
if (!existsSync(path.join(here, '../dist/index.html'))) {
  console.log('web/dist is missing: run `npm ci && npm run build` in web/ first');
  process.exit(1);
}
const { proc: server, url } = await startServer();
const { proc: server2, url: url2 } = await startServer([example]);
const userDir = mkdtempSync(path.join(tmpdir(), 'fabkit-chromium-'));
const context = await chromium.launchPersistentContext(userDir, {
  executablePath: '/usr/bin/chromium', headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  viewport: { width: 1400, height: 900 }, deviceScaleFactor: 1, reducedMotion: 'reduce', acceptDownloads: true,
});
async function freshPage(u = url) {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log('  page error:', e.message));
  await page.goto(u);
  await idle(page);
  return page;
}

try {
  const apiSolve = await (await fetch(`${url}api/solve`, { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: readFileSync(example) })).json();
  const expectedError = `${apiSolve.target.pos_error_mm.toFixed(1)} mm, ${apiSolve.target.rot_error_deg.toFixed(1)}°`;
  let page;

  await test('a task1-basket-solve', async () => {
    page = await freshPage();
    await buildBasket(page);
    const texts = await connectionTexts(page);
    assert(texts.length === 4, `expected 4 connections, got ${JSON.stringify(texts)}`);
    const yaml = await page.evaluate(() => window.__fabkit.designYaml());
    assert(/alignment: flip/.test(yaml), 'flip missing:\n' + yaml);
    await click(page, 'solve');
    const verdict = await page.getByTestId('verdict').textContent();
    assert(verdict === 'STABLE', `verdict ${verdict}`);
    const err = await page.getByTestId('target-error').textContent();
    assert(err.includes(expectedError), `target error "${err}" vs API "${expectedError}"`);
    assert(expectedError.startsWith('18.0 mm, 0.0'), `API error ${expectedError}`);
  });

  await test('e connection-tree', async () => {
    const conns = await connectionTexts(page);
    const edges = await page.locator('[data-testid^="tree-edge-"]').allTextContents();
    assert(conns.length === 4 && JSON.stringify(conns) === JSON.stringify(edges), `tree ${JSON.stringify(edges)} vs ${JSON.stringify(conns)}`);
    for (const n of ['rods', 'eyehook1', 'eyehook2', 'basket']) assert(await page.getByTestId(`tree-node-${n}`).count() === 1, `node ${n}`);
    await page.getByTestId('tree-node-eyehook2').click();
    const label = await page.getByTestId('selection-label').textContent();
    assert(label.includes('eyehook2'), `selection label ${label}`);
  });

  await test('f screenshot-golden', async () => {
    await page.mouse.move(0, 0);
    await page.evaluate(() => window.__fabkit.setCamera([700, -900, 600], [0, 0, 80]));
    await page.getByTestId('tree-node-rods').click(); // deterministic selection highlight
    await page.evaluate(() => window.__fabkit.setCamera([700, -900, 600], [0, 0, 80]));
    const png = await canvasPng(page);
    await page.screenshot({ path: path.join(tmpdir(), 'fabkit-editor.png') });
    if (process.env.FABKIT_UPDATE_GOLDEN === '1') {
      writeFileSync(golden, png); console.log(`  wrote ${golden}`); return;
    }
    assert(existsSync(golden), `missing ${golden} (run with FABKIT_UPDATE_GOLDEN=1 to create it)`);
    const a = decodePng(png), b = decodePng(readFileSync(golden));
    assert(a.width === b.width && a.height === b.height, `size ${a.width}x${a.height} vs ${b.width}x${b.height}`);
    let bad = 0;
    for (let i = 0; i < a.data.length; i += 4) {
      const d = Math.max(Math.abs(a.data[i] - b.data[i]), Math.abs(a.data[i + 1] - b.data[i + 1]), Math.abs(a.data[i + 2] - b.data[i + 2]));
      if (d > 16) bad++;
    }
    const frac = bad / (a.width * a.height);
    if (frac > 0.002) { writeFileSync(path.join(tmpdir(), 'basket-actual.png'), png); }
    assert(frac <= 0.002, `${(frac * 100).toFixed(3)}% pixels differ (actual written to ${path.join(tmpdir(), 'basket-actual.png')})`);
  });

  await test('c undo-redo', async () => {
    const full = await page.evaluate(() => window.__fabkit.designYaml());
    let n = 0;
    while (await page.getByTestId('undo').isEnabled()) { await click(page, 'undo'); n++; }
    const empty = await page.evaluate(() => window.__fabkit.designYaml());
    assert(!empty.includes('eyehook') && !empty.includes('rods'), 'undo to start left:\n' + empty);
    for (let i = 0; i < n; ++i) await click(page, 'redo');
    assert(!(await page.getByTestId('redo').isEnabled()), 'redo still enabled');
    const again = await page.evaluate(() => window.__fabkit.designYaml());
    assert(again === full, `redo differs:\n${again}\nvs\n${full}`);
    await click(page, 'undo');
    assert((await connectionTexts(page)).length === 3, 'one undo should leave 3 connections');
    await click(page, 'redo');
    assert((await page.evaluate(() => window.__fabkit.designYaml())) === full, 'undo+redo differs');
    // delete a part (and its connections), then undo it
    await click(page, 'delete-eyehook2');
    assert((await connectionTexts(page)).length === 2, 'deleting eyehook2 removes its 2 connections');
    await click(page, 'undo');
    assert((await page.evaluate(() => window.__fabkit.designYaml())) === full, 'undo of delete differs');
  });

  await test('g export-python-runs', async () => {
    const py = await page.evaluate(() => window.__fabkit.python());
    assert(py.startsWith('from fabkit.hacks import *') && py.includes('alignment="flip"') && py.includes('end_with'), py);
    const dir = mkdtempSync(path.join(tmpdir(), 'fabkit-py-'));
    writeFileSync(path.join(dir, 'basket.py'), py + '\nresult = assembly.solve()\nprint("stable", result.stable)\n');
    const out = execFileSync(fabkit, ['run', path.join(dir, 'basket.py')], { encoding: 'utf8', timeout: 120000 });
    assert(/stable True/.test(out), out);
  });
  await test('i files-save-open-glb', async () => {
    const full = await page.evaluate(() => window.__fabkit.designYaml());
    const [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('save-yaml').click()]);
    const saved = readFileSync(await dl.path(), 'utf8');
    assert(saved === full, 'saved YAML differs from the design');
    const check = await (await fetch(`${url}api/check`, { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: saved })).json();
    assert(check.valid, 'saved YAML does not check: ' + JSON.stringify(check.diagnostics));
    const [glb] = await Promise.all([page.waitForEvent('download', { timeout: 120000 }), page.getByTestId('download-glb').click()]);
    const bin = readFileSync(await glb.path());
    assert(bin.subarray(0, 4).toString() === 'glTF', 'not a glb');
    const p2 = await freshPage();
    await p2.getByTestId('open-file').setInputFiles(await dl.path());
    await idle(p2);
    assert((await p2.evaluate(() => window.__fabkit.designYaml())) === full, 'opened YAML differs');
    assert((await connectionTexts(p2)).length === 4, 'opened design lacks connections');
    await p2.close();
  });

  await test('j flip-resolves', async () => {
    await click(page, 'solve');
    await click(page, 'flip-1');
    await idle(page);
    assert((await page.getByTestId('flip-1').textContent()) === 'flip', 'alignment not flipped');
    assert((await page.evaluate(() => window.__fabkit.designYaml())).match(/alignment: flip/g).length === 2, 'flip not in design');
    const v = await page.getByTestId('verdict').textContent();
    assert(v === 'STABLE' || v === 'FALLS APART' || v === 'Infeasible', `verdict after flip: ${v}`);
    await click(page, 'undo');
  });
  if (page) await page.close();

  await test('b failing-connect', async () => {
    const p = await freshPage();
    await selectLibPart(p, 'LongTension', 'LongTensionRod');
    await click(p, 'set-environment');
    await connectNew(p, 'DoubleHook', 'dh1', 'hook1', 'env1.rod');
    const msg = await p.getByTestId('failed-connect-message').textContent();
    assert(msg.includes('hook opening 9.6 mm is smaller than rod radius 12.7 mm'), msg);
    assert((await connectionTexts(p)).length === 0, 'failed connect was kept');
    // two-way filtering: with DoubleHook.hook1 picked, the rod is dimmed with the reason
    await click(p, 'lib-prim-hook1');
    const rod = p.getByTestId('scene-prim-env1.rod');
    assert((await rod.getAttribute('class')).includes('dim'), 'rod not dimmed');
    assert((await rod.getAttribute('title')).includes('smaller than rod radius'), 'no reason tooltip');
    // hovering the dimmed rod in the 3D view shows the reason
    const pt = await p.evaluate(() => window.__fabkit.screenPointOf('env1.rod'));
    assert(pt, 'rod not visible on the canvas');
    await p.mouse.move(pt.x, pt.y);
    const tip = await p.getByTestId('tooltip').textContent();
    assert(tip.includes('hook opening 9.6 mm is smaller than rod radius 12.7 mm'), `tooltip: ${tip}`);
    await p.close();
  });

  await test('k cycle-cannot-close', async () => {
    const p = await freshPage();
    await selectLibPart(p, 'TowelHanging', 'TowelHangingEnv');
    await click(p, 'set-environment');
    await connectNew(p, 'DoubleHook', 's', 'hook1', 'env1.hook1');
    assert((await connectionTexts(p)).length === 1, 'first hook not connected');
    await connectScene(p, 's.hook2', 'env1.hook2');
    const msg = await p.getByTestId('failed-connect-message').textContent();
    assert(msg.includes('cannot close cycle env1.hook1 – s – env1.hook2'), msg);
    assert((await connectionTexts(p)).length === 1, 'failed cycle was kept');
    for (const k of ['s.hook2', 'env1.hook2']) assert((await p.getByTestId(`scene-prim-${k}`).getAttribute('class')).includes('bad'), `${k} not highlighted`);
    assert((await p.getByTestId('failed-connect').textContent()).includes('closest configuration'), 'best frames not shown');
    await p.screenshot({ path: path.join(tmpdir(), 'fabkit-cycle.png') });
    await p.close();
  });

  await test('d inventory-limit', async () => {
    const p = await freshPage();
    await selectLibPart(p, 'TowelRack', 'ClosetRods');
    await click(p, 'set-environment');
    await selectLibPart(p, 'HookEyeConnector', 'HookEyeConnector');
    await setField(p, 'owned-count', 3);
    const rods = ['env1.rod1', 'env1.rod2', 'env1.rod1', 'env1.rod2'];
    for (let i = 0; i < 3; ++i) await connectNew(p, 'HookEyeConnector', `eyehook${i + 1}`, 'hook', rods[i]);
    assert((await connectionTexts(p)).length === 3, `3 connections expected: ${await connectionTexts(p)} ${await p.getByTestId('failed-connect').textContent()}`);
    await connectNew(p, 'HookEyeConnector', 'eyehook4', 'hook', rods[3]);
    const msg = await p.getByTestId('message').textContent();
    assert(/own 3 HookEyeConnector/.test(msg), `message: ${msg}`);
    assert((await connectionTexts(p)).length === 3, 'fourth eye hook was added');
    await p.close();
  });

  await test('l falls-apart-slipping', async () => {
    const p = await freshPage();
    await p.getByTestId('open-file').setInputFiles(path.join(repo, 'examples/failing/hook_on_tilted_rod.yaml'));
    await idle(p);
    await click(p, 'solve');
    assert((await p.getByTestId('verdict').textContent()) === 'FALLS APART', 'verdict');
    assert((await p.getByTestId('connection-0').getAttribute('class')).includes('slipping'), 'connection 0 not marked slipping');
    assert(!(await p.getByTestId('connection-1').getAttribute('class')).includes('slipping'), 'connection 1 marked slipping');
    assert((await p.getByTestId('slipping').first().textContent()).includes('slides off'), 'slipping text');
    await p.close();
  });

  await test('m loose-primitive-environment', async () => {
    const p = await freshPage();
    await p.getByTestId('open-file').setInputFiles(path.join(repo, 'examples/hacks/toothbrush_holder.yaml'));
    // The file is read asynchronously: wait for the design to show up, then for the editor.
    const item = p.getByTestId('scene-prim-table.surface');
    await item.waitFor({ timeout: 30000 }).catch(() => {});
    await idle(p);
    assert(await item.count() === 1, 'table.surface not in the scene-primitives list');
    const meshes = await p.evaluate(() => window.__fabkit.sceneMeshes());
    assert(meshes['table.surface'] > 0, `no mesh for table.surface: ${JSON.stringify(meshes)}`);
    assert((await item.getAttribute('title')).includes('sizes are checked when you connect'), 'loose tooltip');
    // pickable: clicking it selects it and filters by Table 1 (a hemisphere may touch it, a hook may not)
    await click(p, 'scene-prim-table.surface');
    assert((await p.getByTestId('selection-label').textContent()).includes('table.surface (surface)'), 'selection label');
    assert(!(await p.getByTestId('scene-prim-clip.hemisphere1').getAttribute('class')).includes('dim'), 'hemisphere dimmed');
    assert((await p.getByTestId('scene-prim-clip.clip').getAttribute('class')).includes('dim'), 'clip not dimmed');
    await p.keyboard.press('Escape'); await idle(p);
    await click(p, 'solve');
    assert((await p.getByTestId('verdict').textContent()) === 'STABLE', 'verdict');
    const py = await p.evaluate(() => window.__fabkit.python());
    assert(py.includes('surface = Surface({"width": 400, "length": 400})') && py.includes('table = Environment({"surface": surface})'), py);
    const dir = mkdtempSync(path.join(tmpdir(), 'fabkit-py-'));
    writeFileSync(path.join(dir, 'toothbrush.py'), py + '\nresult = assembly.solve()\nprint("stable", result.stable)\n');
    const out = execFileSync(fabkit, ['run', path.join(dir, 'toothbrush.py')], { encoding: 'utf8', timeout: 120000 });
    assert(/stable True/.test(out), out);
    await p.close();
  });

  await test('n part-parameters', async () => {
    const p = await freshPage();
    await selectLibPart(p, 'CeilingHook', 'CeilingHook');
    await click(p, 'set-environment');
    await selectLibPart(p, 'ParamTurnbuckle', 'ParamTurnbuckle');
    await setField(p, 'new-param-extended_length', 25.135);
    await connectNew(p, 'ParamTurnbuckle', 'tb1', 'hook1', 'env1.hook');
    assert((await connectionTexts(p)).length === 1, `not connected: ${await p.getByTestId('failed-connect').textContent()}`);
    let yaml = await p.evaluate(() => window.__fabkit.designYaml());
    assert(yaml.includes('extended_length: 25.135'), yaml);
    assert((await p.evaluate(() => window.__fabkit.python())).includes('ParamTurnbuckle({"extended_length": 25.135})'), 'python params');
    // per-instance edit is an undoable command
    await setField(p, 'param-tb1-extended_length', 40);
    yaml = await p.evaluate(() => window.__fabkit.designYaml());
    assert(yaml.includes('extended_length: 40'), yaml);
    await click(p, 'undo');
    yaml = await p.evaluate(() => window.__fabkit.designYaml());
    assert(yaml.includes('extended_length: 25.135'), 'undo of parameter edit: ' + yaml);
    await click(p, 'undo');
    yaml = await p.evaluate(() => window.__fabkit.designYaml());
    assert(!yaml.includes('tb1') && !yaml.includes('ParamTurnbuckle'), 'undo did not remove the part: ' + yaml);
    await p.close();
  });

  await test('h load-design-from-server', async () => {
    const p = await freshPage(url2);
    assert((await connectionTexts(p)).length === 4, 'design from the server not loaded');
    await p.close();
  });
} finally {
  await context.close();
  server.kill(); server2.kill();
  rmSync(userDir, { recursive: true, force: true });
}
const failedTests = results.filter((r) => r[1] !== 'ok');
console.log(`${results.length - failedTests.length} passed, ${failedTests.length} failed`);
process.exit(failedTests.length ? 1 : 0);
