// Browser tests of the Rods workspace (issue 15): node web/tests/rods_workspace.mjs [test-prefix ...]
// Starts `fabkit serve --port 0` (serving web/dist; run `npm run build` first), drives Debian's
// chromium with playwright-core and exits non-zero when a test fails (ctest: web.rods).
// FABKIT_UPDATE_GOLDEN=1 rewrites tests/golden/rods_coffee_table.png; FABKIT_DOCS_SHOTS=1 writes
// the screenshots of docs/rods-editor.md into docs/rods-editor/.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, existsSync, rmSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { startServer, assert, median, makeTests, idle, click, setField } from './harness.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const fabkit = process.env.FABKIT || path.join(repo, 'build/bin/fabkit');
const examples = path.join(repo, 'examples/rods');
const golden = path.join(here, 'golden/rods_coffee_table.png');
const only = process.argv.slice(2);

const { test, finish } = makeTests(only);
const preview = (page) => page.evaluate(() => window.__fabkit.preview());
const design = (page) => page.evaluate(() => window.__fabkit.designYaml());
const counts = async (page) => {
  const p = await preview(page);
  return p ? { joints: p.joints.length, rods: p.rods.length } : { joints: 0, rods: 0 };
};
async function rodsPage(file) {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log('  page error:', e.message));
  if (process.env.DEBUG_CONSOLE) page.on('console', (m) => console.log('  console:', m.text()));
  await page.goto(url);
  await idle(page);
  await page.getByTestId('workspace-switcher').selectOption('rods');
  await idle(page);
  assert((await page.evaluate(() => window.__fabkit.kit())) === 'rods', 'not in the rods workspace');
  if (file) {
    await page.getByTestId('open-file').setInputFiles(path.join(examples, file));
    await idle(page);
  }
  return page;
}
/** Clicks a world point (mm) of the 3D view. */
async function clickWorld(page, p, opts = {}) {
  const s = await page.evaluate((q) => window.__fabkit.screenOf(q), p);
  await page.mouse.click(s.x, s.y, opts);
  await idle(page);
}
/** Clicks a joint or rod in the 3D view (a point of it that picks it). */
async function clickPart(page, key, { shift = false } = {}) {
  const s = await page.evaluate((k) => window.__fabkit.pointOf(k), key);
  assert(s, `${key} is not visible in the view`);
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.click(s.x, s.y);
  if (shift) await page.keyboard.up('Shift');
  await idle(page);
}
const colorOf = (page, key) => page.evaluate((k) => window.__fabkit.styleOf(k)?.color, key);
const docsShots = process.env.FABKIT_DOCS_SHOTS === '1';
async function shot(page, name) {
  await page.mouse.move(0, 0);
  const dir = docsShots ? path.join(repo, 'docs/rods-editor') : tmpdir();
  mkdirSync(dir, { recursive: true });
  await page.screenshot({ path: path.join(dir, `${name}.png`) });
}
async function canvasPng(page) {
  const u = await page.evaluate(() => document.querySelector('[data-testid=scene-canvas]').toDataURL('image/png'));
  return Buffer.from(u.split(',')[1], 'base64');
}

// ------------------------------------------------------------------ main
if (!existsSync(path.join(here, '../dist/index.html'))) {
  console.log('web/dist is missing: run `npm ci && npm run build` in web/ first');
  process.exit(1);
}
const { proc: server, url } = await startServer();
const userDir = mkdtempSync(path.join(tmpdir(), 'fabkit-chromium-'));
const context = await chromium.launchPersistentContext(userDir, {
  executablePath: '/usr/bin/chromium', headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  viewport: { width: 1400, height: 900 }, deviceScaleFactor: 1, reducedMotion: 'reduce', acceptDownloads: true,
});
await context.addInitScript(() => {
  if (!sessionStorage.getItem('fabkit-test-tab')) { localStorage.clear(); sessionStorage.setItem('fabkit-test-tab', '1'); }
});
const work = mkdtempSync(path.join(tmpdir(), 'fabkit-rods-web-'));

try {
  await test('a open-shows-fabricated-geometry', async () => {
    const p = await rodsPage('coffee_table.yaml');
    const pv = await preview(p);
    assert(pv.joints.length === 9 && pv.rods.length === 12, `coffee table: ${pv.joints.length} joints, ${pv.rods.length} rods`);
    // joints white, rods wood-brown, from the server's hulls and prisms
    assert((await colorOf(p, 'j0')) === 0xf4f4f0, `joint colour ${(await colorOf(p, 'j0'))?.toString(16)}`);
    assert((await colorOf(p, 'r0')) === 0xa0703c, `rod colour ${(await colorOf(p, 'r0'))?.toString(16)}`);
    // every rod's length is the library's (check against the CLI's report of the same file)
    const api = await (await fetch(`${url}api/rods/preview`, { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: readFileSync(path.join(examples, 'coffee_table.yaml')) })).json();
    assert(api.rods.every((r, e) => Math.abs(r.length - pv.rods[e].length) < 1e-9), 'lengths differ from the API');
    // rod length on hover
    const s = await p.evaluate(() => window.__fabkit.pointOf('r0'));
    await p.mouse.move(s.x, s.y);
    const tip = await p.getByTestId('tooltip').textContent();
    assert(tip.includes(`cut ${pv.rods[0].length.toFixed(1)} mm`), `tooltip: ${tip}`);
    await shot(p, 'coffee-table');
    await p.close();
  });

  await test('b stand-from-nothing', async () => {
    const p = await rodsPage();
    await click(p, 'view-top');
    await click(p, 'tool-add');
    // three feet on the floor: each new node is connected to the one selected before it
    await clickWorld(p, [0, 0, 0]);
    await clickWorld(p, [300, 0, 0]);
    await clickWorld(p, [150, 260, 0]);
    let c = await counts(p);
    assert(c.joints === 3 && c.rods === 2, `after three clicks: ${JSON.stringify(c)}\n${await design(p)}\n${await p.getByTestId('message').textContent()}`);
    // close the triangle: shift-click the first foot, Connect
    await click(p, 'tool-select');
    await clickPart(p, 'j0', { shift: true });
    await click(p, 'connect');
    c = await counts(p);
    assert(c.rods === 3, `triangle: ${JSON.stringify(c)}`);
    // the top, above the middle: added on a raised work plane, connected to the three feet
    await clickPart(p, 'j1'); // (the gizmo's arrows point away from the joints still to pick)
    await clickPart(p, 'j2', { shift: true });
    await clickPart(p, 'j0', { shift: true });
    const sel3 = await p.evaluate(() => window.__fabkit.selection());
    assert(sel3.nodes.length === 3, `shift-click selection: ${JSON.stringify(sel3)}`);
    await setField(p, 'work-z', 200);
    await click(p, 'tool-add');
    await clickWorld(p, [150, 90, 200]);
    c = await counts(p);
    assert(c.joints === 4 && c.rods === 6, `tetrahedron: ${JSON.stringify(c)}`);
    let pv = await preview(p);
    assert(pv.balance.stands, `the stand tips: ${JSON.stringify(pv.balance)}`);
    // drag the top up with the gizmo's z arrow (seen from the front)
    await click(p, 'tool-select');
    await click(p, 'view-front');
    const z0 = JSON.parse(JSON.stringify(pv.joints[3].position))[2];
    const h = await p.evaluate(() => window.__fabkit.gizmoHandle('Z'));
    assert(h, 'no gizmo on the selected joint');
    await p.mouse.move(h.x, h.y); await p.mouse.down();
    await p.mouse.move(h.x, h.y - 40, { steps: 4 }); await p.mouse.move(h.x, h.y - 80, { steps: 4 });
    await p.mouse.up();
    await idle(p);
    pv = await preview(p);
    const z1 = pv.joints[3].position[2];
    assert(z1 > z0 + 20, `the drag did not raise the top: z ${z0} → ${z1}`);
    assert(z1 % 10 === 0, `the move did not snap to the 10 mm grid: z = ${z1}`);
    // one drag is one undoable step
    await click(p, 'undo');
    assert((await preview(p)).joints[3].position[2] === z0, 'undo did not undo the drag');
    await click(p, 'redo');
    assert((await preview(p)).joints[3].position[2] === z1, 'redo did not redo the drag');
    // box select: every joint
    await click(p, 'view-top');
    await click(p, 'tool-box');
    const cv = await p.getByTestId('scene-canvas').boundingBox();
    await p.mouse.move(cv.x + 5, cv.y + 5); await p.mouse.down();
    await p.mouse.move(cv.x + cv.width - 5, cv.y + cv.height - 5, { steps: 5 }); await p.mouse.up();
    await idle(p);
    const sel = await p.evaluate(() => window.__fabkit.selection());
    assert(sel.nodes.length === 4 && sel.rods.length === 6, `box select: ${JSON.stringify(sel)}`);
    await click(p, 'tool-select');
    await click(p, 'view-iso');
    await shot(p, 'stand');
    await p.close();
  });

  await test('c collision-turns-red-and-clears', async () => {
    const p = await rodsPage('failing/rods_intersect.yaml');
    // rods 03-04 and 05-06 cross: both red, with the reason on hover and a label in the view
    const pv = await preview(p);
    const e34 = pv.rods.findIndex((r) => r.name === 'rod 03-04'), e56 = pv.rods.findIndex((r) => r.name === 'rod 05-06');
    assert(pv.intersections.length === 1, `intersections ${JSON.stringify(pv.intersections)}`);
    assert((await colorOf(p, `r${e34}`)) === 0xff0000 && (await colorOf(p, `r${e56}`)) === 0xff0000, 'crossing rods are not red');
    assert((await colorOf(p, 'r0')) === 0xa0703c, 'a rod that passes is red');
    assert(await p.getByTestId('collision-label').count() === 1, 'no collision label in the view');
    const finding = await p.getByTestId('finding-rods-intersect').first().textContent();
    assert(/rod 03-04 and rod 05-06 intersect: their axes come [\d.]+ mm apart, less than 2r = 9.50 mm/.test(finding), `finding: ${finding}`);
    const s = await p.evaluate((k) => window.__fabkit.pointOf(k), `r${e34}`);
    await p.mouse.move(s.x, s.y);
    const tip = await p.getByTestId('tooltip').textContent();
    assert(tip.includes('intersect') && tip.includes('mm'), `hover: ${tip}`);
    // the joint numbers the messages use are drawn in the view (and can be hidden)
    assert(await p.locator('[data-testid^=joint-number-]').count() === 8 && (await p.getByTestId('joint-number-4').textContent()) === '04', 'joint numbers');
    await shot(p, 'collision');
    // raise joint 04 by 150 mm: rod 03-04 passes above 05-06
    await clickPart(p, 'j3');
    await setField(p, 'node-z', 450);
    const after = await preview(p);
    assert(after.intersections.length === 0, `still intersecting: ${JSON.stringify(after.intersections)}`);
    assert((await colorOf(p, `r${e34}`)) === 0xa0703c, 'rod 03-04 still red');
    assert(await p.getByTestId('collision-label').count() === 0, 'collision label stayed');
    // and back with undo
    await click(p, 'show-numbers');
    assert(await p.locator('[data-testid^=joint-number-]').count() === 0, 'joint numbers not hidden');
    await click(p, 'undo');
    assert((await preview(p)).intersections.length === 1, `undo did not bring the collision back:\n${await design(p)}\n${await p.getByTestId('undo').getAttribute('title')}`);
    await p.close();
  });

  await test('d split-and-delete-with-undo', async () => {
    const p = await rodsPage('coffee_table.yaml');
    await clickPart(p, 'r0');
    const len0 = (await preview(p)).rods[0].edge_length;
    await click(p, 'split');
    let c = await counts(p);
    assert(c.joints === 10 && c.rods === 13, `split: ${JSON.stringify(c)}`);
    const pv = await preview(p);
    assert(Math.abs(pv.rods[0].edge_length + pv.rods[1].edge_length - len0) < 1e-6, 'the split is not at a point of the rod');
    assert(Math.abs(pv.rods[0].edge_length - pv.rods[1].edge_length) < 1e-6, 'the split is not at the midpoint');
    await p.keyboard.press('Delete'); await idle(p); // the new joint is selected: Delete deletes it and its two rods
    c = await counts(p);
    assert(c.joints === 9 && c.rods === 11, `delete: ${JSON.stringify(c)}`);
    await click(p, 'undo');
    assert(JSON.stringify(await counts(p)) === JSON.stringify({ joints: 10, rods: 13 }), 'undo delete');
    await click(p, 'undo');
    assert(JSON.stringify(await counts(p)) === JSON.stringify({ joints: 9, rods: 12 }), 'undo split');
    await click(p, 'redo'); await click(p, 'redo');
    assert(JSON.stringify(await counts(p)) === JSON.stringify({ joints: 9, rods: 11 }), 'redo both');
    // deleting a rod keeps its joints
    await click(p, 'undo'); await click(p, 'undo');
    await clickPart(p, 'r4');
    await click(p, 'delete');
    assert(JSON.stringify(await counts(p)) === JSON.stringify({ joints: 9, rods: 11 }), 'delete a rod');
    await p.close();
  });

  await test('e radius-changes-lengths', async () => {
    const p = await rodsPage('coffee_table.yaml');
    const before = (await preview(p)).rods.map((r) => r.length);
    await setField(p, 'param-diameter', 25.4);
    const after = (await preview(p)).rods.map((r) => r.length);
    assert(after.every((l, e) => l < before[e]), 'a larger r must shorten every rod (larger offsets)');
    assert((await design(p)).includes('diameter: 25.4'), 'r not in the design file');
    // drag the 2r value: the value is drawn next to the cursor, one undo step at the end
    const h = await p.getByTestId('scrub-diameter').boundingBox();
    await p.mouse.move(h.x + h.width / 2, h.y + h.height / 2); await p.mouse.down();
    await p.mouse.move(h.x + h.width / 2 - 100, h.y + h.height / 2, { steps: 5 });
    const tip = await p.getByTestId('scrub-tip').textContent();
    assert(/2r = 20\.40 mm/.test(tip), `value next to the cursor: ${tip}`);
    await p.mouse.up(); await idle(p);
    const dragged = (await preview(p)).rods.map((r) => r.length);
    assert(dragged.every((l, e) => l > after[e] && l < before[e]), 'lengths after dragging 2r to 20.4 mm');
    await click(p, 'undo');
    assert((await preview(p)).rods.every((r, e) => r.length === after[e]), 'undo of the drag');
    // σ, h and the profile
    await setField(p, 'param-socket', 40);
    assert((await design(p)).includes('socket: 40'), 'h');
    await p.getByTestId('profile').selectOption('6'); await idle(p);
    assert((await preview(p)).parameters.sides === 6, 'p = 6');
    await p.close();
  });

  await test('f build-and-download', async () => {
    const p = await rodsPage('coffee_table.yaml');
    // progress over joints while the exact booleans run
    let sawProgress = false;
    await p.getByTestId('build').click();
    for (let k = 0; k < 2000; ++k) {
      const job = await p.evaluate(() => window.__fabkit.buildJob());
      if (job && job.state === 'running' && await p.getByTestId('build-progress').count()) sawProgress = true;
      if (job && job.state !== 'running') break;
      await p.waitForTimeout(50);
    }
    await idle(p);
    assert(sawProgress, 'no progress bar while building');
    const summary = await p.getByTestId('build-summary').textContent();
    assert(/9 joints \(9 closed solids\)/.test(summary), `summary: ${summary}`);
    // a joint STL that admesh calls closed
    const [dl] = await Promise.all([p.waitForEvent('download'), p.getByTestId('download-joint_01.stl').click()]);
    assert(dl.suggestedFilename() === 'joint_01.stl', dl.suggestedFilename());
    const stl = path.join(work, 'joint_01.stl');
    await dl.saveAs(stl);
    const report = execFileSync('admesh', [stl], { encoding: 'utf8' });
    const field = (name) => Number(report.match(new RegExp(`${name}\\s*:\\s*(\\d+)`))[1]);
    assert(field('Number of parts') === 1, `admesh parts\n${report}`);
    // closed: every facet has its three neighbours, one shell, nothing to fix or add, no flipped facet
    for (const f of ['Total disconnected facets', 'Edges fixed', 'Facets added', 'Backwards edges']) assert(field(f) === 0, `admesh ${f}\n${report}`);
    // (zero-area facets from rounding to the STL's 32-bit floats are the library's, see the docs)
    console.log(`  admesh: joint_01.stl closed, 1 part, ${field('Degenerate facets')} degenerate facets`);
    // the other downloads
    for (const name of ['joints.3mf', 'cut_plan.svg', 'cut_list.csv', 'assembly.json']) {
      const [d] = await Promise.all([p.waitForEvent('download'), p.getByTestId(`download-${name}`).click()]);
      const file = path.join(work, name);
      await d.saveAs(file);
      const bytes = readFileSync(file);
      if (name === 'joints.3mf') assert(bytes.subarray(0, 2).toString() === 'PK', '3MF is not a zip');
      if (name === 'cut_list.csv') assert(bytes.toString().startsWith('label,length_mm,stock,position_mm') && bytes.toString().trim().split('\n').length === 13, 'cut list');
      if (name === 'assembly.json') assert(JSON.parse(bytes.toString()).steps.length === 21, 'assembly steps');
      if (name === 'cut_plan.svg') assert(bytes.toString().includes('<svg'), 'cut plan');
    }
    // the cut plan is drawn in the page
    await p.getByTestId('cut-plan-image').waitFor();
    assert(await p.getByTestId('cut-plan-image').evaluate((img) => img.complete && img.naturalWidth > 100), 'cut plan image not drawn');
    const bars = await p.locator('[data-testid=cut-plan-bars] title').allTextContents();
    assert(bars.length === 12 && bars.every((t) => /^rod \d\d-\d\d: [\d.]+ mm$/.test(t)), `cut plan bars: ${bars}`);
    await shot(p, 'make-it');
    await p.close();
  });

  await test('g assembler-coffee-table', async () => {
    const p = await rodsPage('coffee_table.yaml');
    const pv = await preview(p);
    const n = pv.assembly.length;
    assert(n === 21, `coffee table: ${n} steps (9 joints + 12 rods)`);
    await click(p, 'assemble-start');
    const seen = new Set();
    let lastTarget = null, moves = 0;
    for (let k = 0; k < n; ++k) {
      const st = await p.evaluate(() => window.__fabkit.assembly());
      assert(st.active && st.step === k && st.count === n, `state ${JSON.stringify(st)}`);
      const text = await p.getByTestId('assemble-step').textContent();
      assert(text.startsWith(`Step ${k + 1} of ${n}: `) && text.includes(pv.assembly[k].text), `step text: ${text}`);
      const label = await p.getByTestId('assembly-current-label').textContent();
      const s = pv.assembly[k];
      if (s.kind === 'joint') assert(label === s.label, `joint label ${label}, want ${s.label}`);
      else assert(label.includes(`${pv.rods[s.rod].length.toFixed(1)} mm`), `rod label ${label}`);
      seen.add(s.kind === 'joint' ? `j${s.joint}` : `r${s.rod}`);
      if (lastTarget && JSON.stringify(lastTarget) !== JSON.stringify(st.camera)) moves++;
      lastTarget = st.camera;
      if (k === 5) await shot(p, 'assembler');
      if (k < n - 1) { if (k % 2) await click(p, 'assemble-next'); else { await p.keyboard.press('ArrowRight'); await idle(p); } }
    }
    assert(seen.size === 21, `every part once: ${seen.size}`);
    assert(moves >= n / 2, `the camera followed the current part only ${moves} times`);
    assert(await p.getByTestId('assemble-next').isDisabled(), 'Next at the last step');
    await click(p, 'assemble-back');
    assert((await p.evaluate(() => window.__fabkit.assembly())).step === n - 2, 'Back');
    // the printable guide: one picture and one line per step
    const html = await p.evaluate(() => window.__fabkit.guideHtml());
    const steps = html.match(/<li class="step"><img src="data:image\/png;base64,/g) ?? [];
    assert(steps.length === n, `guide has ${steps.length} steps`);
    writeFileSync(path.join(work, 'guide.html'), html);
    const g = await context.newPage();
    await g.goto(`file://${path.join(work, 'guide.html')}`);
    const imgs = await g.locator('li.step img').evaluateAll((xs) => xs.filter((i) => i.complete && i.naturalWidth === 220).length);
    assert(imgs === n, `guide pictures that load: ${imgs}`);
    if (docsShots) await g.screenshot({ path: path.join(repo, 'docs/rods-editor/guide.png') });
    await g.close();
    await p.keyboard.press('Escape'); await idle(p);
    assert(!(await p.evaluate(() => window.__fabkit.assembly())).active, 'Esc leaves the assembler');
    await p.close();
  });

  await test('h golden-screenshot', async () => {
    const p = await rodsPage('coffee_table.yaml');
    await p.evaluate(() => window.__fabkit.setCamera([900, -1100, 800], [0, 0, 180]));
    await p.mouse.move(0, 0);
    await p.waitForTimeout(100);
    const png = await canvasPng(p);
    if (process.env.FABKIT_UPDATE_GOLDEN === '1' || !existsSync(golden)) {
      writeFileSync(golden, png);
      console.log(`  wrote ${golden}`);
    } else {
      const a = PNG.sync.read(png), b = PNG.sync.read(readFileSync(golden));
      assert(a.width === b.width && a.height === b.height, `size ${a.width}x${a.height} vs ${b.width}x${b.height}`);
      let differ = 0;
      for (let i = 0; i < a.data.length; i += 4) {
        if (Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) + Math.abs(a.data[i + 2] - b.data[i + 2]) > 48) differ++;
      }
      const frac = differ / (a.width * a.height);
      assert(frac < 0.01, `${(frac * 100).toFixed(2)} % of the pixels differ from ${golden}`);
    }
    await p.close();
  });

  await test('i edit-round-trip-52-rods', async () => {
    const p = await rodsPage('wolf_head_52.yaml');
    assert((await counts(p)).rods === 52, '52 rods');
    const t = await p.evaluate(() => window.__fabkit.timeEdits(21));
    assert(t.length === 21, `timed ${t.length} edits`);
    const m = (k) => median(t.map((x) => x[k]));
    console.log(`  52 rods, one edit (median of 21): round trip ${m('total_ms').toFixed(1)} ms = request ${m('fetch_ms').toFixed(1)} ms (server ${m('server_ms').toFixed(1)} ms, library ${m('library_ms').toFixed(1)} ms) + draw ${m('draw_ms').toFixed(1)} ms + waiting for the GPU ${m('gpu_ms').toFixed(1)} ms`);
    const direct = await p.evaluate(async (body) => {
      const out = [];
      for (let k = 0; k < 21; ++k) { const t0 = performance.now(); const r = await fetch('api/rods/preview', { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body }); JSON.parse(await r.text()); out.push(performance.now() - t0); }
      return out;
    }, await design(p));
    console.log(`  the same request alone (fetch + JSON.parse, no drawing; median of 21): ${median(direct).toFixed(1)} ms`);
    console.log(`  drawing the view once (SwiftShader, 1400 × 900 window): ${(await p.evaluate(() => window.__fabkit.timeRender(9))).toFixed(1)} ms`);
    assert(t.every((x) => x.total_ms > 0 && x.library_ms > 0 && x.total_ms >= x.fetch_ms), 'timings');
    await p.close();
  });

  await test('j files-yaml-and-obj', async () => {
    const p = await rodsPage('stool.yaml');
    const before = await preview(p);
    await setField(p, 'design-name', 'My stool');
    const [y] = await Promise.all([p.waitForEvent('download'), p.getByTestId('save-yaml').click()]);
    assert(y.suggestedFilename() === 'My_stool.yaml', y.suggestedFilename());
    const text = readFileSync(await y.path(), 'utf8');
    assert(text.startsWith('fabkit: rods/1\nname: My stool\n'), text.slice(0, 60));
    // the saved file is the same design for the library
    const api = await (await fetch(`${url}api/rods/preview`, { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: text })).json();
    assert(api.rods.length === before.rods.length && api.rods.every((r, e) => Math.abs(r.length - before.rods[e].length) < 1e-6), 'saved design differs');
    const p2 = await rodsPage();
    await p2.getByTestId('open-file').setInputFiles(await y.path()); await idle(p2);
    assert((await design(p2)) === text, 'open(save(design)) is not the same file');
    // an OBJ mesh: a cube's 8 vertices and 12 edges (each face edge once)
    const obj = path.join(work, 'cube.obj');
    writeFileSync(obj, 'v 0 0 0\nv 300 0 0\nv 300 300 0\nv 0 300 0\nv 0 0 300\nv 300 0 300\nv 300 300 300\nv 0 300 300\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n');
    await p2.getByTestId('import-obj-input').setInputFiles(obj); await idle(p2);
    assert(JSON.stringify(await counts(p2)) === JSON.stringify({ joints: 8, rods: 12 }), `OBJ: ${JSON.stringify(await counts(p2))}`);
    await click(p2, 'undo');
    assert((await counts(p2)).rods === before.rods.length, 'undo the import');
    // a bad OBJ says why
    writeFileSync(obj, 'v 0 0 0\nv 1 x 0\nl 1 2\n');
    await p2.getByTestId('import-obj-input').setInputFiles(obj); await idle(p2);
    const msg = await p2.getByTestId('message').textContent();
    assert(/cannot import cube.obj: .*import.obj:2/.test(msg), `message: ${msg}`);
    await p.close(); await p2.close();
  });

  await test('k checks-balance-and-frame', async () => {
    const p = await rodsPage('failing/unbalanced.yaml');
    const pv = await preview(p);
    assert(!pv.balance.stands, 'unbalanced.yaml stands');
    const label = await p.getByTestId('balance-label').textContent();
    assert(/tips over: [\d.]+ mm outside/.test(label), `balance label: ${label}`);
    assert((await p.getByTestId('finding-unbalanced').first().textContent()).includes('tips over'), 'no unbalanced finding');
    const p2 = await rodsPage('failing/overstressed.yaml');
    const pv2 = await preview(p2);
    assert(pv2.frame.max_utilisation > 1, 'overstressed.yaml not overstressed');
    const fs = await p2.getByTestId('frame-summary').textContent();
    assert(fs.includes(pv2.rods[pv2.frame.critical_rod].name), `worst rod not named: ${fs}`);
    await click(p2, 'ramp-toggle');
    const worst = await colorOf(p2, `r${pv2.frame.critical_rod}`);
    assert(worst !== 0xa0703c, 'ramp did not colour the worst rod');
    await shot(p2, 'utilisation');
    await p.close(); await p2.close();
  });
  await test('l rotate-and-scale-gizmo', async () => {
    const p = await rodsPage('coffee_table.yaml');
    await click(p, 'view-top');
    // the four top joints and the middle one: a box around the top, inside the feet
    await click(p, 'tool-box');
    const a = await p.evaluate(() => window.__fabkit.screenOf([-275, 275, 420]));
    const b = await p.evaluate(() => window.__fabkit.screenOf([275, -275, 420]));
    await p.mouse.move(a.x, a.y); await p.mouse.down(); await p.mouse.move(b.x, b.y, { steps: 4 }); await p.mouse.up(); await idle(p);
    const sel = (await p.evaluate(() => window.__fabkit.selection())).nodes.sort();
    assert(JSON.stringify(sel) === JSON.stringify([0, 1, 2, 3, 8]), `box: ${sel}`);
    await click(p, 'tool-select');
    const nodes = async () => (await preview(p)).joints.map((j) => j.position);
    const dist = (u, v) => Math.hypot(u[0] - v[0], u[1] - v[1], u[2] - v[2]);
    const before = await nodes();
    // rotate about z: drag the blue ring sideways (in perspective: three's rotate gizmo turns by
    // the drag's length over the camera's distance, which is slow from an orthographic camera far away)
    await click(p, 'view-iso');
    await click(p, 'gizmo-rotate');
    const h = await p.evaluate(() => window.__fabkit.gizmoHandle('Z'));
    assert(h, 'no rotate ring');
    await p.mouse.move(h.x, h.y);
    assert((await p.evaluate(() => window.__fabkit.gizmoAxis())) === 'Z', `the pointer is on gizmo handle ${await p.evaluate(() => window.__fabkit.gizmoAxis())}, not the z ring`);
    await p.mouse.down();
    for (let k = 1; k <= 8; ++k) await p.mouse.move(h.x + k * 15, h.y + k * 4);
    await p.mouse.up(); await idle(p);
    const rotated = await nodes();
    assert(sel.some((i) => dist(rotated[i], before[i]) > 10), 'the rotation moved nothing');
    for (const i of sel) for (const j of sel) assert(Math.abs(dist(rotated[i], rotated[j]) - dist(before[i], before[j])) < 1e-3, `rotation changed a distance (${i}, ${j})`);
    for (let i = 4; i < 8; ++i) assert(dist(rotated[i], before[i]) === 0, `foot ${i} moved`);
    const angle = Math.atan2(rotated[0][1], rotated[0][0]) - Math.atan2(before[0][1], before[0][0]);
    const deg = ((angle * 180) / Math.PI + 360) % 360;
    assert(Math.abs(deg / 15 - Math.round(deg / 15)) < 1e-3, `not snapped to 15°: ${deg}°`);
    await click(p, 'undo');
    assert(JSON.stringify(await nodes()) === JSON.stringify(before), 'undo the rotation');
    // scale along x: the red handle
    await click(p, 'gizmo-scale');
    const x = await p.evaluate(() => window.__fabkit.gizmoHandle('X'));
    assert(x, 'no scale handle');
    // drag outward, away from the gizmo's centre (the selection's centre)
    const centre = sel.reduce((acc, i) => acc.map((v, k) => v + before[i][k] / sel.length), [0, 0, 0]);
    const o = await p.evaluate((q) => window.__fabkit.screenOf(q), centre);
    const ux = (x.x - o.x) / Math.hypot(x.x - o.x, x.y - o.y), uy = (x.y - o.y) / Math.hypot(x.x - o.x, x.y - o.y);
    await p.mouse.move(x.x, x.y); await p.mouse.down();
    for (let k = 1; k <= 6; ++k) await p.mouse.move(x.x + ux * k * 10, x.y + uy * k * 10);
    await p.mouse.up(); await idle(p);
    const scaled = await nodes();
    const f = scaled[0][0] / before[0][0];
    assert(f > 1.04, `x scale ${f}`);
    for (const i of sel) {
      assert(Math.abs(scaled[i][0] - before[i][0] * f) < 1e-3 && scaled[i][1] === before[i][1] && scaled[i][2] === before[i][2], `joint ${i + 1} not scaled along x by ${f}`);
    }
    await p.close();
  });

  await test('m acute-angle-explodes', async () => {
    // two rods 1.9° apart at joint 01: its offsets g = (r + ε) / tan(θ / 2) outgrow the rods
    const file = path.join(work, 'acute.yaml');
    writeFileSync(file, 'fabkit: rods/1\nname: acute\nrod: {diameter: 12.7}\nnodes:\n  - [0, 0, 0]\n  - [300, 0, 0]\n  - [300, 10, 0]\n  - [0, 300, 0]\nedges:\n  - [1, 2]\n  - [1, 3]\n  - [2, 3]\n  - [1, 4]\n  - [3, 4]\n');
    const p = await rodsPage();
    await p.getByTestId('open-file').setInputFiles(file); await idle(p);
    const pv = await preview(p);
    assert(pv.joints[0].red && pv.joints[0].smallest_angle < 2, `joint 01: ${JSON.stringify({ red: pv.joints[0].red, angle: pv.joints[0].smallest_angle })}`);
    assert((await colorOf(p, 'j0')) === 0xff0000, 'joint 01 is not drawn red');
    const pt = await p.evaluate(() => window.__fabkit.pointOf('j0'));
    await p.mouse.move(pt.x, pt.y);
    const tip = await p.getByTestId('tooltip').textContent();
    assert(/smallest angle 1\.9°/.test(tip) && /offsets [\d.]+ mm \(at joint 01\)/.test(tip) && tip.includes('leave no rod'), `hover: ${tip}`);
    await p.close();
  });
  await test('n refused-edit-keeps-the-view', async () => {
    const p = await rodsPage('guitar_stand.yaml');
    const before = await preview(p);
    // joint 02 onto joint 01: the library refuses the design (a zero-length rod); the view keeps
    // the last good state and the banner quotes the library
    await clickPart(p, 'j1');
    await setField(p, 'node-x', before.joints[0].position[0]);
    await setField(p, 'node-y', before.joints[0].position[1]);
    await setField(p, 'node-z', before.joints[0].position[2]);
    const msg = await p.getByTestId('message').textContent();
    assert(/The library cannot make this design: design\.yaml:\d+:\d+: error: /.test(msg), `message: ${msg}`);
    assert(await p.getByTestId('preview-error').count() === 1, 'no error in the Checks panel');
    assert(JSON.stringify((await preview(p)).joints.map((j) => j.position)) === JSON.stringify(before.joints.map((j) => j.position)), 'the view did not keep the last good state');
    await click(p, 'undo');
    assert(!(await p.getByTestId('message').isVisible()) && await p.getByTestId('preview-error').count() === 0, 'undo did not clear the refusal');
    await p.close();
  });
} finally {
  await context.close();
  server.kill();
  rmSync(userDir, { recursive: true, force: true });
  rmSync(work, { recursive: true, force: true });
}
finish();
