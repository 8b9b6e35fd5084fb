// Browser tests of the editor's Flat-pack workspace: node web/tests/flatpack_workspace.mjs [test-prefix...]
// (ctest web.flatpack). Starts `fabkit serve --port 0` (serving web/dist; run `npm run build`
// first), drives Debian's chromium with playwright-core and exits non-zero when a test fails.
// FABKIT_UPDATE_GOLDEN=1 rewrites tests/golden/flatpack_table.png; FABKIT_DOCS_SHOTS=1 writes the
// screenshots of docs/flatpack-editor.md into docs/flatpack-editor/.
import { execFileSync, spawnSync } from 'node:child_process';
import { mkdtempSync, mkdirSync, readFileSync, writeFileSync, existsSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { startServer, assert, median, makeTests, idle, click, setField } from './harness.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const fabkit = process.env.FABKIT || path.join(repo, 'build/bin/fabkit');
const examples = path.join(repo, 'examples/flatpack');
const golden = path.join(here, 'golden/flatpack_table.png');
const only = process.argv.slice(2);
const docsShots = process.env.FABKIT_DOCS_SHOTS === '1';
const shotDir = docsShots ? path.join(repo, 'docs/flatpack-editor') : mkdtempSync(path.join(tmpdir(), 'fabkit-fp-shots-'));
if (docsShots) mkdirSync(shotDir, { recursive: true });

const { test, finish } = makeTests(only);
const near = (a, b, tol = 0.01) => Math.abs(a - b) <= tol;
const asm = (page) => page.evaluate(() => window.__fabkit.assembly());
const yamlOf = (page) => page.evaluate(() => window.__fabkit.designYaml());

async function flatpackPage() {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log('  page error:', e.message));
  await page.goto(url);
  await idle(page);
  await page.getByTestId('workspace-switcher').selectOption('flatpack');
  await idle(page);
  assert((await page.evaluate(() => window.__fabkit.kit())) === 'flatpack', 'not in the flat-pack workspace');
  return page;
}

/** Adds a component from the library, names it and types its values (numbers or expressions). */
async function addComponent(page, type, name, values) {
  await page.getByTestId('new-component-name').fill(name);
  await click(page, `add-${type}`);
  for (const [k, v] of Object.entries(values)) await setField(page, `param-${name}-${k}`, v);
}
async function addParameter(page, name, value, meta = true) {
  await page.getByTestId('new-param-name').fill(name);
  await page.getByTestId('new-param-value').fill(String(value));
  if (meta) await page.getByTestId('new-param-meta').check();
  await click(page, 'add-param');
}
/** Clicks an edge ("A.t") where it shows on the canvas. */
async function clickEdge(page, key) {
  await page.evaluate(() => document.getElementById('view-all').click());
  const p = await page.evaluate((k) => window.__fabkit.edgePoint(k), key);
  assert(p, `edge ${key} is not visible on the canvas`);
  await page.mouse.click(p.x, p.y);
  await idle(page);
}
async function connectByClicking(page, a, b) {
  await clickEdge(page, a);
  const label = await page.getByTestId('pick-label').textContent();
  assert(label.includes(`${a} picked`), `pick label after clicking ${a}: ${label}`);
  await clickEdge(page, b);
}
async function shot(page, name) {
  await page.mouse.move(0, 0);
  await page.screenshot({ path: path.join(shotDir, `${name}.png`) });
}
async function canvasPng(page) {
  const u = await page.evaluate(() => document.querySelector('[data-testid=scene-canvas]').toDataURL('image/png'));
  return Buffer.from(u.split(',')[1], 'base64');
}
async function download(page, testid) {
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 60000 }), page.getByTestId(testid).click()]);
  await idle(page);
  const file = path.join(mkdtempSync(path.join(tmpdir(), 'fabkit-fp-dl-')), dl.suggestedFilename());
  await dl.saveAs(file);
  return file;
}
async function postAssemble(file) {
  const res = await fetch(`${url}api/flatpack/assemble`, { method: 'POST', headers: { 'Content-Type': 'application/x-yaml' }, body: readFileSync(file) });
  assert(res.ok, `assemble ${file}: ${res.status}`);
  return res.json();
}
const sizes = (a) => a.pieces.map((p) => `${p.name}:${p.size_mm.map((v) => v.toFixed(2)).join('x')}`).sort();
const kinds = (a) => a.joints.map((j) => j.kind).sort();
/** The bounding box (mm) of a piece's outline on the drawn sheet. */
const sheetBox = (page, piece) => page.evaluate((p) => {
  const e = document.querySelector(`[data-testid="sheet-piece-${p}"]`);
  if (!e) return null;
  const b = e.getBBox();
  return { w: b.width, h: b.height };
}, piece);

/** The simple table (paper Fig. 11(g), examples/flatpack/simple_table.yaml) built by clicking. */
async function buildSimpleTable(page) {
  await page.getByTestId('design-name').fill('simple table');
  await page.getByTestId('design-name').dispatchEvent('change');
  for (const [n, v] of [['length', 300], ['width', 180], ['height', 150], ['leg_width', 40]]) await addParameter(page, n, v);
  await addComponent(page, 'Rectangle', 'top', { l: 'length', w: 'width' });
  for (const leg of ['leg_fl', 'leg_bl', 'leg_fr', 'leg_br']) await addComponent(page, 'Rectangle', leg, { l: 'leg_width', w: 'height' });
  const legs = [['leg_fl', 'top.l', '(width - leg_width) / 2'], ['leg_bl', 'top.l', '-(width - leg_width) / 2'],
                ['leg_fr', 'top.r', '-(width - leg_width) / 2'], ['leg_br', 'top.r', '(width - leg_width) / 2']];
  for (let i = 0; i < legs.length; ++i) {
    const [leg, edge, x] = legs[i];
    await connectByClicking(page, `${leg}.t`, edge);
    await setField(page, `conn-${i}-offset-x`, x);
    await setField(page, `conn-${i}-offset-y`, 'leg_width / 2');
    await setField(page, `conn-${i}-rotation-x`, -90);
  }
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

let table = null; // the page with the simple table, shared by the tests after b
try {
  await test('a fig3-two-rectangles-by-clicking', async () => {
    const page = await flatpackPage();
    const lib = await page.locator('[data-testid^="lib-"]').count();
    assert(lib >= 10, `component library has ${lib} entries`);
    await addComponent(page, 'Rectangle', 'A', { l: 30, w: 60 });
    await addComponent(page, 'Rectangle', 'B', { l: 30, w: 60 });
    let a = await asm(page);
    assert(a.pieces.length === 2 && a.joints.length === 0, `two loose rectangles: ${a.pieces.length} pieces, ${a.joints.length} joints`);
    // Esc drops a picked edge
    await clickEdge(page, 'A.r');
    await page.keyboard.press('Escape');
    assert((await page.getByTestId('pick-label').textContent()) === '' && (await page.evaluate(() => window.__fabkit.pick())) === null, 'Esc did not cancel the pick');
    await clickEdge(page, 'A.t');
    assert((await page.getByTestId('pick-label').textContent()).includes('A.t picked'), 'A.t not picked');
    assert((await page.evaluate(() => window.__fabkit.styleOf('A.b'))).outlineWidth === 0, 'the picked component\'s other edges are not dimmed');
    await shot(page, 'picked-edge');
    await clickEdge(page, 'B.b');
    a = await asm(page);
    const ref = await postAssemble(path.join(examples, 'bookend.yaml'));
    assert(a.placed && a.joints.length === 1 && a.joints[0].kind === 'finger-finger' && !a.joints[0].automatic, `Fig. 3 joint: ${JSON.stringify(a.joints)}`);
    assert(JSON.stringify(kinds(a)) === JSON.stringify(kinds(ref)) && JSON.stringify(sizes(a)) === JSON.stringify(sizes(ref)), `differs from bookend.yaml: ${sizes(a)} vs ${sizes(ref)}`);
    assert(a.joints[0].fingers === ref.joints[0].fingers, `fingers ${a.joints[0].fingers} vs ${ref.joints[0].fingers}`);
    const y = await yamlOf(page);
    assert(/connect: \[ A\.t, B\.b \], alignment: front-front, offset: \[ 0, 0, 0 \], rotation: \[ 90, 0, 0 \]/.test(y), `the 5-tuple in the file:\n${y}`);
    assert((await page.getByTestId('connection-0-made').textContent()).includes('finger-finger'), 'connection list does not say which joint it made');
    for (const axis of ['x', 'y', 'z']) { assert(await page.getByTestId(`conn-0-offset-${axis}`).count() === 1, `offset ${axis} field`); assert(await page.getByTestId(`conn-0-rotation-${axis}`).count() === 1, `rotation ${axis} field`); }
    // both pieces on the sheet, labelled
    assert((await page.locator('[data-testid^="sheet-piece-"]').count()) === 2, 'sheet does not show both pieces');
    const labels = await page.getByTestId('sheet-label').allTextContents();
    assert(labels.includes('A') && labels.includes('B'), `sheet labels ${labels}`);
    // the edges of the selected component are buttons too: picking by keyboard, like clicking in the view
    await page.getByTestId('component-A').click();
    await page.getByTestId('edge-A-l').focus();
    await page.keyboard.press('Enter');
    await idle(page);
    assert((await page.evaluate(() => window.__fabkit.pick())) === 'A.l', 'edge button did not pick A.l');
    await page.keyboard.press('Escape');
    // the 5-tuple's rotation as a field: 0° lays A beside B in B's plane, so the two merge into one piece
    await setField(page, 'conn-0-rotation-x', 0);
    a = await asm(page);
    assert(a.pieces.length === 1 && a.merging_connections.includes(0), `rotation 0: ${a.pieces.length} pieces`);
    await click(page, 'undo');
    a = await asm(page);
    assert(a.pieces.length === 2 && a.joints.length === 1, 'undo did not bring the joint back');
    await shot(page, 'fig3');
    // the Delete key deletes the selected component and its connection, as one undoable step
    const before = await yamlOf(page);
    await page.getByTestId('component-B').click();
    await page.mouse.move(0, 0);
    await page.locator('body').press('Delete');
    await idle(page);
    a = await asm(page);
    assert(a.components.length === 1 && !(await yamlOf(page)).includes('connect:'), `after Delete: ${await yamlOf(page)}`);
    await click(page, 'undo');
    assert((await yamlOf(page)) === before, 'undo of Delete differs');
    await page.close();
  });

  await test('b simple-table-by-clicking', async () => {
    table = await flatpackPage();
    await buildSimpleTable(table);
    const a = await asm(table);
    const ref = await postAssemble(path.join(examples, 'simple_table.yaml'));
    assert(a.placed, `not placed: ${JSON.stringify(a.diagnostics)}`);
    assert(a.pieces.length === 5 && JSON.stringify(kinds(a)) === JSON.stringify(kinds(ref)), `joints ${kinds(a)} vs ${kinds(ref)}`);
    assert(JSON.stringify(sizes(a)) === JSON.stringify(sizes(ref)), `pieces ${sizes(a)} vs ${sizes(ref)}`);
    assert(a.diagnostics.filter((d) => d.severity !== 'note').length === ref.diagnostics.filter((d) => d.severity !== 'note').length, `diagnostics ${JSON.stringify(a.diagnostics)}`);
    const drives = await table.getByTestId('dparam-length-drives').textContent();
    assert(drives.includes('top.l'), `meta-parameter length drives: ${drives}`);
    // every joint is drawn in the view: one marker per joint
    const markers = await table.evaluate(() => window.__fabkit.assembly().joints.length);
    assert(markers === 4, `joint markers ${markers}`);
    // the saved file is a valid design for the command line
    const dir = mkdtempSync(path.join(tmpdir(), 'fabkit-fp-'));
    writeFileSync(path.join(dir, 'table.yaml'), await yamlOf(table));
    const r = spawnSync(fabkit, ['check', path.join(dir, 'table.yaml')], { encoding: 'utf8' });
    assert(r.status === 0, `fabkit check of the editor's file: ${r.status}\n${r.stdout}${r.stderr}`);
    await shot(table, 'simple-table');
  });

  await test('c meta-parameter-updates-sheets', async () => {
    assert(table, 'needs b');
    let box = await sheetBox(table, 'top');
    assert(box && near(box.w, 300, 0.05) && near(box.h, 180, 0.05) || box && near(box.w, 180, 0.05) && near(box.h, 300, 0.05), `top on the sheet ${JSON.stringify(box)}`);
    const before = await table.locator('[data-testid="sheet-1"]').innerHTML();
    await setField(table, 'dparam-length', 400);
    box = await sheetBox(table, 'top');
    assert(box && (near(box.w, 400, 0.05) && near(box.h, 180, 0.05) || near(box.w, 180, 0.05) && near(box.h, 400, 0.05)), `top after length = 400: ${JSON.stringify(box)}`);
    assert((await table.locator('[data-testid="sheet-1"]').innerHTML()) !== before, 'sheet not redrawn');
    const labels = await table.getByTestId('sheet-label').allTextContents();
    for (const n of ['top', 'leg_fl', 'leg_bl', 'leg_fr', 'leg_br']) assert(labels.includes(n), `label ${n} missing: ${labels}`);
    const top = (await asm(table)).pieces.find((p) => p.name === 'top');
    assert(near(Math.max(...top.size_mm), 400), `top ${top.size_mm}`);
    // the slider previews while dragged (no command) and commits once on release
    const undoTitle = await table.getByTestId('undo').getAttribute('title');
    const slider = table.getByTestId('dparam-height-slider');
    await slider.evaluate((e) => { e.value = '200'; e.dispatchEvent(new Event('input')); });
    await idle(table);
    const leg = (await asm(table)).pieces.find((p) => p.name === 'leg_fl');
    assert(near(Math.max(...leg.size_mm), 200 + 3 / 2, 2), `preview leg ${leg.size_mm}`);
    assert((await table.getByTestId('undo').getAttribute('title')) === undoTitle, 'a preview became a command');
    await slider.evaluate((e) => { e.value = '150'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
    await idle(table);
    // the round trip of one parameter edit: from the change to the redrawn model and sheets
    const n0 = (await table.evaluate(() => window.__fabkit.roundTrips())).length;
    const wall = [];
    for (let k = 0; k < 15; ++k) {
      const t0 = Date.now();
      await setField(table, 'dparam-length', 380 + (k % 2) * 20);
      wall.push(Date.now() - t0);
    }
    const rts = (await table.evaluate(() => window.__fabkit.roundTrips())).slice(n0);
    const st = (await table.evaluate(() => window.__fabkit.roundTripStages())).slice(n0);
    const med = (k) => [...st.map((x) => x[k])].sort((p, q) => p - q)[Math.floor(st.length / 2)].toFixed(1);
    console.log(`  stages (median ms): before ${med('before')}, request ${med('server')}, 3D view ${med('draw')}, panels ${med('panels')}`);
    const median = (xs) => [...xs].sort((p, q) => p - q)[Math.floor(xs.length / 2)];
    console.log(`  round trip of one parameter edit (simple table, in the page): median ${median(rts).toFixed(1)} ms, min ${Math.min(...rts).toFixed(1)}, max ${Math.max(...rts).toFixed(1)} over ${rts.length}; test-side fill+change+idle median ${median(wall)} ms`);
    assert(rts.length >= 15 && median(rts) < 2000, `round trips ${rts}`);
    await setField(table, 'dparam-length', 400);
  });

  await test('d downloads-dxf-svg-stl-glb-report', async () => {
    assert(table, 'needs b');
    const dxf = await download(table, 'download-dxf');
    assert(dxf.endsWith('simple_table-sheet-1.dxf'), `dxf name ${dxf}`);
    const py = `
import ezdxf, sys, json
doc = ezdxf.readfile(sys.argv[1])
boxes = []
for e in doc.modelspace().query('LWPOLYLINE'):
    pts = [p[:2] for p in e.get_points()]
    xs = [p[0] for p in pts]; ys = [p[1] for p in pts]
    boxes.append([max(xs) - min(xs), max(ys) - min(ys), e.closed, e.dxf.layer])
texts = [t.dxf.text for t in doc.modelspace().query('TEXT')]
print(json.dumps({"insunits": doc.header.get('$INSUNITS'), "boxes": boxes, "texts": texts}))
`;
    const out = JSON.parse(execFileSync('/usr/bin/python3', ['-c', py, dxf], { encoding: 'utf8' }));
    assert(out.insunits === 4, `$INSUNITS ${out.insunits} (4 = mm)`);
    assert(out.boxes.every((b) => b[2] && b[3] === 'CUT'), 'outlines not closed on layer CUT');
    const big = out.boxes.map((b) => [Math.max(b[0], b[1]), Math.min(b[0], b[1])]).sort((p, q) => q[0] - p[0])[0];
    assert(near(big[0], 400, 0.01) && near(big[1], 180, 0.01), `the top in the DXF is ${big[0]} × ${big[1]} mm, not 400 × 180`);
    assert(out.texts.includes('top'), `labels ${out.texts}`);
    const svg = readFileSync(await download(table, 'download-svg'), 'utf8');
    assert(/width="600mm" height="400mm" viewBox="0 0 600 400"/.test(svg), 'SVG not in mm');
    const stl = readFileSync(await download(table, 'download-stl'));
    const tris = stl.readUInt32LE(80);
    assert(stl.length === 84 + 50 * tris && tris > 50, `STL ${stl.length} bytes, ${tris} triangles`);
    const glb = readFileSync(await download(table, 'download-glb'));
    assert(glb.subarray(0, 4).toString() === 'glTF', 'not a glb');
    const report = JSON.parse(readFileSync(await download(table, 'download-report'), 'utf8'));
    assert(report.counts.pieces === 5 && report.counts.cut_joints_by_kind['finger-hole'] === 4, `report counts ${JSON.stringify(report.counts)}`);
  });

  await test('e warnings-beside-pieces-exploded-view', async () => {
    assert(table, 'needs b');
    // lift one leg's connection off the top: its pieces no longer meet, and the warning sits by the leg
    await setField(table, 'conn-0-offset-y', -100);
    const a = await asm(table);
    const w = a.diagnostics.find((d) => d.code === 'connection-makes-no-joint');
    assert(w && w.pieces.includes('leg_fl'), `warning: ${JSON.stringify(a.diagnostics)}`);
    await table.evaluate(() => document.getElementById('view-all').click());
    const note = await table.evaluate(() => { const e = document.querySelector('[data-testid="note-leg_fl"]'); return e && { display: e.style.display, left: e.style.left, top: e.style.top, text: e.textContent }; });
    assert(note && note.display !== 'none', `no warning beside leg_fl in the view: ${JSON.stringify(note)}`);
    await shot(table, 'warning');
    await click(table, 'undo');
    assert(await table.getByTestId('note-leg_fl').count() === 0, 'warning stays after undo');
    // exploded view moves the pieces apart, not the design
    const yaml = await yamlOf(table);
    const p0 = await table.evaluate(() => window.__fabkit.project('leg_fl'));
    await table.getByTestId('explode').fill('1');
    await idle(table);
    const p1 = await table.evaluate(() => window.__fabkit.project('leg_fl'));
    assert(Math.hypot(p1.x - p0.x, p1.y - p0.y) > 10, `exploded leg moved ${JSON.stringify([p0, p1])}`);
    assert((await yamlOf(table)) === yaml, 'exploding changed the design');
    await shot(table, 'exploded');
    await table.getByTestId('explode').fill('0');
    await idle(table);
  });

  await test('f material-per-design-and-per-piece', async () => {
    assert(table, 'needs b');
    await table.getByTestId('component-top').click();
    await click(table, 'component-top-own-material');
    const i = 0;
    await setField(table, `mat-${i}-thickness`, 6);
    let a = await asm(table);
    const top = a.pieces.find((p) => p.name === 'top');
    const leg = a.pieces.find((p) => p.name === 'leg_fl');
    assert(top.material.thickness === 6 && leg.material.thickness === 3, `thickness top ${top.material.thickness}, leg ${leg.material.thickness}`);
    await setField(table, 'mat-kerf', 0.15);
    a = await asm(table);
    assert(a.pieces.find((p) => p.name === 'leg_fl').material.kerf === 0.15, 'design kerf not applied');
    const y = await yamlOf(table);
    assert(/material: top_board1/.test(y) && /kerf: 0\.15/.test(y), `materials in the file:\n${y}`);
    for (let k = 0; k < 3; ++k) await click(table, 'undo');
    a = await asm(table);
    assert(a.pieces.every((p) => p.material.thickness === 3 && p.material.kerf === 0.1), 'undo did not restore the materials');
  });

  await test('g undo-redo-save-open', async () => {
    assert(table, 'needs b');
    const full = await yamlOf(table);
    await click(table, 'undo');
    assert((await yamlOf(table)) !== full, 'undo did nothing');
    await click(table, 'redo');
    assert((await yamlOf(table)) === full, 'redo differs');
    const [dl] = await Promise.all([table.waitForEvent('download'), table.getByTestId('save-yaml').click()]);
    const saved = readFileSync(await dl.path(), 'utf8');
    assert(saved === full, 'saved YAML differs from the design');
    const p2 = await flatpackPage();
    await p2.getByTestId('open-file').setInputFiles(await dl.path());
    await idle(p2);
    assert((await yamlOf(p2)) === full, 'opened YAML differs');
    assert(JSON.stringify(sizes(await asm(p2))) === JSON.stringify(sizes(await asm(table))), 'opened design assembles differently');
    // an example file opens and keeps its keys (joints, labels, sheet)
    await p2.getByTestId('open-file').setInputFiles(path.join(examples, 'reading_desk.yaml'));
    await idle(p2);
    const a = await asm(p2);
    const ref = await postAssemble(path.join(examples, 'reading_desk.yaml'));
    assert(a.placed && a.joints.length === ref.joints.length && a.pieces.length === ref.pieces.length, `reading desk: ${a.pieces.length} pieces, ${a.joints.length} joints vs ${ref.pieces.length}, ${ref.joints.length}`);
    assert(a.joints.some((j) => j.automatic) && await p2.locator('[data-testid^="auto-joint-"]').count() === a.joints.filter((j) => j.automatic).length, 'automatic joints not marked');
    await shot(p2, 'reading-desk');
    await p2.close();
  });

  await test('h residual-beside-piece', async () => {
    const p = await flatpackPage();
    const dir = mkdtempSync(path.join(tmpdir(), 'fabkit-fp-'));
    const file = path.join(dir, 'cycle.yaml');
    writeFileSync(file, 'fabkit: flatpack/1\nname: cycle\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 30}\n  - {name: B, type: Rectangle, l: 30, w: 30}\n  - {name: C, type: Rectangle, l: 30, w: 30}\nconnections:\n  - {connect: [B.l, A.r]}\n  - {connect: [C.l, B.r]}\n  - {connect: [C.b, A.t], offset: [0, 0, 5], name: closing}\n');
    await p.getByTestId('open-file').setInputFiles(file);
    await idle(p);
    const a = await asm(p);
    assert(!a.placed && a.residuals.length === 1 && !a.residuals[0].closes && near(a.residuals[0].position_mm, Math.sqrt(3600 + 900 + 25), 0.001), `residuals ${JSON.stringify(a.residuals)}`);
    assert(await p.getByTestId('residual-c2').isVisible(), 'residual not listed');
    assert((await p.getByTestId('connection-1-residual').textContent()).includes('67.27 mm'), 'residual not beside the connection');
    assert(await p.getByTestId('note-C').isVisible(), 'no note beside C in the view');
    // where c2 would put C: beside B, its corner at (60, 0, 0)
    const f = a.residuals[0].frame;
    assert(near(f[12], 60, 1e-6) && near(f[13], 0, 1e-6) && near(f[14], 0, 1e-6), `c2's placement of C ${f}`);
    assert((await p.getByTestId('residual-ghost-c2').textContent()).includes('c2 would put C here: 67.27 mm'), 'no ghost of the disagreeing placement');
    await shot(p, 'residual');
    await p.close();
  });

  await test('i screenshot-golden', async () => {
    assert(table, 'needs b');
    await table.mouse.move(0, 0);
    await table.getByTestId('component-top').click();
    await idle(table);
    await table.evaluate(() => { window.__fabkit.setCamera([700, -800, 500], [0, 0, 75]); document.getElementById('view-all').click(); });
    const png = await canvasPng(table);
    if (process.env.FABKIT_UPDATE_GOLDEN === '1') { writeFileSync(golden, png); console.log(`  wrote ${golden}`); return; }
    assert(existsSync(golden), `missing ${golden} (run with FABKIT_UPDATE_GOLDEN=1 to create it)`);
    const a = PNG.sync.read(png), b = PNG.sync.read(readFileSync(golden));
    assert(a.width === b.width && a.height === b.height, `size ${a.width}x${a.height} vs ${b.width}x${b.height}`);
    let bad = 0;
    for (let i = 0; i < a.data.length; i += 4) {
      const d = Math.max(Math.abs(a.data[i] - b.data[i]), Math.abs(a.data[i + 1] - b.data[i + 1]), Math.abs(a.data[i + 2] - b.data[i + 2]));
      if (d > 16) bad++;
    }
    const frac = bad / (a.width * a.height);
    const actual = path.join(tmpdir(), 'flatpack_table-actual.png');
    if (frac > 0.002) writeFileSync(actual, png);
    assert(frac <= 0.002, `${(frac * 100).toFixed(3)}% pixels differ (actual written to ${actual})`);
  });
} finally {
  await context.close();
  server.kill();
  rmSync(userDir, { recursive: true, force: true });
}
finish();
