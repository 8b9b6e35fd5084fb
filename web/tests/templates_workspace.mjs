// Browser tests of the templates workspace (design and fabrication by example):
//   node web/tests/templates_workspace.mjs [test-name-prefix...]
// Starts `fabkit serve --port 0` (serving web/dist; run `npm run build` first), drives Debian's
// chromium with playwright-core and exits non-zero when a test fails. Prints the drag step's
// round trip (median over the steps of a sphere drag) for docs/benchmarks.md.
// FABKIT_UPDATE_GOLDEN=1 rewrites tests/golden/templates_table_shelf.png.
import { mkdtempSync, readFileSync, writeFileSync, existsSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { startServer, assert, median, makeTests, idle, click, setField } from './harness.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const fabkit = process.env.FABKIT || path.join(repo, 'build/bin/fabkit');
const example = path.join(repo, 'examples/templates/table_with_shelf.yaml');
const golden = path.join(here, 'golden/templates_table_shelf.png');
const only = process.argv.slice(2);
const docsShots = process.env.FABKIT_DOCS_SHOTS === '1';

const { test, finish } = makeTests(only);
const hook = (page, name, ...args) => page.evaluate(([n, a]) => window.__fabkit[n](...a), [name, args]);
async function shot(page, name) {
  if (!docsShots) return;
  await page.mouse.move(0, 0);
  await page.screenshot({ path: path.join(repo, 'docs/templates-editor', `${name}.png`) });
}
async function canvasPng(page) {
  const u = await page.evaluate(() => document.querySelector('[data-testid=scene-canvas]').toDataURL('image/png'));
  return Buffer.from(u.split(',')[1], 'base64');
}

/** Drags a library entry onto the 3D view, dropped at the world point `at` (mm). */
async function dropTemplate(page, spec, at) {
  const canvas = page.getByTestId('scene-canvas');
  const cb = await canvas.boundingBox();
  const p = at ? await hook(page, 'worldToScreen', at) : { x: cb.x + cb.width / 2, y: cb.y + cb.height / 2 };
  await page.getByTestId(`template-entry-${spec}`).dragTo(canvas, { targetPosition: { x: p.x - cb.x, y: p.y - cb.y } });
  await idle(page);
}
const composed = (page) => page.evaluate(() => window.__fabkit.composed());
const bomSizes = async (page, item) => (await page.getByTestId(`bom-sizes-${item}`).textContent()).trim();

/** The paper's table with a bottom shelf (Fig. 10), composed by dragging from the library. */
async function composeTableWithShelf(page) {
  await page.getByTestId('workspace-switcher').selectOption('templates');
  await idle(page);
  await page.getByTestId('template-search').fill('dining');
  await dropTemplate(page, 'dining_table', null);
  await page.getByTestId('template-search').fill('shelf');
  assert(await page.getByTestId('template-parts-bookshelf').evaluate((d) => d.open), "the search for 'shelf' does not open the bookshelf's parts");
  // a low view under the apron: the drop lands on the floor between the legs
  await hook(page, 'setCamera', [300, -2200, 500], [0, 0, 200]);
  await dropTemplate(page, 'bookshelf/shelves/bottom_shelf', [0, 0, 0]);
}

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
async function freshPage() {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log('  page error:', e.message));
  await page.goto(url);
  await idle(page);
  return page;
}
const dragMedians = {};
function reportDrag(key, what, t) {
  const m = {}; for (const k of ['roundTrip', 'request', 'draw', 'server', 'qp']) m[k] = median(t.map((x) => x[k]));
  dragMedians[key] = { steps: t.length, ...m };
  console.log(`  drag step (${what}): median round trip ${m.roundTrip.toFixed(1)} ms over ${t.length} steps ` +
    `(request ${m.request.toFixed(1)} ms of which server ${m.server.toFixed(1)} ms and QP ${m.qp.toFixed(2)} ms; redraw ${m.draw.toFixed(1)} ms; then the frame)`);
}

try {
  let page;

  await test('a library', async () => {
    page = await freshPage();
    await page.getByTestId('workspace-switcher').selectOption('templates');
    await idle(page);
    assert(await hook(page, 'kit') === 'templates', 'not in the templates workspace');
    const cards = page.locator('[data-testid^="template-"][class="tmpl-card"]');
    assert(await cards.count() === 12, `${await cards.count()} designs in the library, expected the 12 bundled ones`);
    // thumbnails of the designs in view are drawn
    await page.waitForFunction(() => document.querySelector('[data-testid="template-thumb-bed_frame"]')?.dataset.state === 'done', null, { timeout: 20000 });
    // search: names, descriptions and the designs' parts ("drawer" finds the chest's drawers)
    await page.getByTestId('template-search').fill('drawer');
    const shown = await page.locator('.tmpl-card').evaluateAll((es) => es.map((e) => e.dataset.testid));
    assert(shown.includes('template-chest_of_drawers') && !shown.includes('template-bed_frame'), `search 'drawer': ${shown}`);
    assert(await page.getByTestId('template-entry-chest_of_drawers/drawers/drawer_1').isVisible(), 'the drawer sub-template is not listed');
    await page.getByTestId('template-search').fill('');
    await page.getByTestId('template-category').selectOption('table');
    const tables = await page.locator('.tmpl-card').evaluateAll((es) => es.map((e) => e.dataset.testid).sort());
    assert(JSON.stringify(tables) === JSON.stringify(['template-coffee_table', 'template-desk', 'template-dining_table', 'template-side_table']), `tables: ${tables}`);
    await page.getByTestId('template-search').fill('zzz');
    assert(await page.getByTestId('template-none').isVisible(), 'no "no match" message');
    await page.getByTestId('template-search').fill('');
    await page.getByTestId('template-category').selectOption('');
    await shot(page, 'library');
    await page.close();
  });

  await test('b compose-table-with-shelf-by-dragging', async () => {
    page = await freshPage();
    await composeTableWithShelf(page);
    let c = await composed(page);
    assert(c && c.steps.length === 2, `steps: ${JSON.stringify(c?.steps)}`);
    // dropped at its own size, the shelf touches nothing: the panel says so and how to fix it
    const first = c.steps[1];
    if (!first.links?.length) {
      assert(await page.getByTestId('not-touching-bottom_shelf').isVisible(), 'no explanation for a shelf that joins nothing');
      await setField(page, 'step-bottom_shelf-size_y', 789);
      c = await composed(page);
    }
    const s = c.steps[1];
    assert(s.links.length === 4 && s.links.every((l) => l.connected), `shelf links: ${JSON.stringify(s.links)}`);
    assert(/LBR-40/.test(s.outcome), `outcome ${s.outcome}`);
    assert(c.stability.stable && c.max_violation < 1e-6, `stable ${c.stability.stable}, violation ${c.max_violation}`);
    // connectors drawn: the brackets and their screws are parts of the view
    const styles = await hook(page, 'partStyles');
    const brackets = c.parts.filter((p) => p.item === 'LBR-40');
    assert(brackets.length >= 4 && brackets.every((p) => styles[p.name]), `brackets drawn: ${brackets.length}`);
    const yaml = await hook(page, 'modelYaml');
    assert(/use: bookshelf\/shelves\/bottom_shelf/.test(yaml) && /size_y: 789/.test(yaml), yaml);
    // the BOM has the shelf's plywood and the brackets, with prices
    assert(await page.getByTestId('bom-row-LBR-40').isVisible(), 'no bracket line in the BOM');
    const total = await page.getByTestId('bom-total').textContent();
    assert(total === `$${c.bom.total.toFixed(2)}`, `total ${total} vs ${c.bom.total}`);
    // undo removes the size, redo brings it back
    await click(page, 'undo');
    assert(!/size_y: 789/.test(await hook(page, 'modelYaml')), 'undo kept the size');
    await click(page, 'redo');
    assert((await composed(page)).steps[1].links.length === 4, 'redo did not restore the joined shelf');
    await shot(page, 'composed');
  });

  await test('c select-leaf-walk-up', async () => {
    await hook(page, 'setCamera', [1800, -2400, 1500], [0, 0, 300]);
    const leg = await hook(page, 'projectPart', 'leg_fr');
    assert(leg, 'leg_fr not on the screen');
    await page.mouse.click(leg.x, leg.y); await idle(page);
    assert(await hook(page, 'selectedNode') === 'dining_table/base/legs/leg_fr', `selected ${await hook(page, 'selectedNode')}`);
    let styles = await hook(page, 'partStyles');
    assert(styles.top.dim && !styles.leg_fr.dim, 'unselected parts are not see-through');
    const label = await page.getByTestId('selection-label').textContent();
    assert(label.includes('leg_fr'), label);
    await page.mouse.click(leg.x, leg.y); await idle(page);
    assert(await hook(page, 'selectedNode') === 'dining_table/base/legs', `walk up: ${await hook(page, 'selectedNode')}`);
    styles = await hook(page, 'partStyles');
    assert(!styles.leg_fl.dim && styles.top.dim, 'the legs group is not the selection');
    await click(page, 'select-parent');
    assert(await hook(page, 'selectedNode') === 'dining_table/base', `Up: ${await hook(page, 'selectedNode')}`);
    // constrained directions have no handle: a plywood top cannot get thicker
    await click(page, 'node-dining_table/top');
    const handles = await hook(page, 'handleControls');
    assert(!handles.includes('size_z') && handles.includes('size_x'), `top's handles: ${handles}`);
    assert(await page.getByTestId('control-fixed-size_z').isVisible(), 'the fixed thickness is not shown as fixed');
    await shot(page, 'walk-up');
  });

  await test('d reshape-with-sphere', async () => {
    await click(page, 'node-dining_table');
    const before = await bomSizes(page, 'LUM-PINE-4x4');
    assert(before === '4 x 732 mm', `legs before: ${before}`);
    await hook(page, 'setCamera', [2400, -2400, 900], [0, 0, 400]);
    await click(page, 'node-dining_table'); // handles redrawn for this view
    const p = await hook(page, 'handlePoint', 'size_z');
    assert(p, 'no size_z sphere on the table');
    const n0 = (await hook(page, 'dragTimings')).length;
    await page.mouse.move(p.x, p.y);
    await page.mouse.down();
    for (let i = 1; i <= 12; ++i) { await page.mouse.move(p.x, p.y - i * 6); await page.waitForTimeout(60); }
    await page.mouse.up();
    await idle(page);
    const timings = (await hook(page, 'dragTimings')).slice(n0);
    assert(timings.length >= 3, `only ${timings.length} drag steps were solved`);
    reportDrag('noLoads', 'table with shelf, no loads', timings);
    const yaml = await hook(page, 'modelYaml');
    const m = yaml.match(/node: dining_table, control: size_z, to: ([\d.]+)/);
    assert(m && Number(m[1]) > 770, `no taller table in the file:\n${yaml}`);
    const after = await bomSizes(page, 'LUM-PINE-4x4');
    assert(after !== before && Number(after.match(/4 x (\d+)/)[1]) > 732, `legs after: ${after}`);
    const c = await composed(page);
    assert(c.max_violation < 1e-6, `constraints violated by ${c.max_violation} mm`);
    assert((await page.getByTestId('constraints').textContent()).startsWith('Every constraint holds'), 'constraints text');
    // the shelf stayed joined to the legs (its connections hold)
    assert(c.steps[1].links.every((l) => l.connected), 'the shelf came loose');
    await shot(page, 'reshaped');
  });

  await test('e removed-leg-turns-red', async () => {
    // someone leaning on the corner above leg_fl (300 N)
    await click(page, 'node-dining_table/top');
    await setField(page, 'load-part', 'top');
    await page.getByTestId('load-at-x').fill('-780'); await page.getByTestId('load-at-y').fill('-430');
    const top = (await composed(page)).nodes.find((n) => n.path === 'dining_table/top').box.max[2];
    await page.getByTestId('load-at-z').fill(String(top));
    await click(page, 'load-add');
    let c = await composed(page);
    assert(c.stability.stable, 'the table with four legs is not stable under the load');
    assert((await page.getByTestId('stability-verdict').textContent()).startsWith('Stable'), 'verdict text');
    await click(page, 'node-dining_table/base/legs/leg_fl');
    await click(page, 'remove-selected');
    c = await composed(page);
    assert(!c.parts.some((p) => p.name === 'leg_fl'), 'leg_fl still there');
    assert(!c.stability.stable, 'three legs under the corner load should tip');
    const styles = await hook(page, 'partStyles');
    const principal = c.parts.filter((p) => p.role === 'principal');
    assert(principal.every((p) => styles[p.name].red), `not every part red: ${principal.filter((p) => !styles[p.name].red).map((p) => p.name)}`);
    assert((await page.getByTestId('stability-verdict').textContent()).includes('tips'), 'verdict does not say it tips');
    await click(page, 'color-stability');
    assert((await hook(page, 'partStyles')).top.color === 0xff0000, 'stability colouring');
    await shot(page, 'unstable');
    await click(page, 'color-materials');
    await click(page, 'undo');
    c = await composed(page);
    assert(c.stability.stable && c.parts.some((p) => p.name === 'leg_fl'), 'undo did not bring the leg back');
    assert(!(await hook(page, 'partStyles')).top.red, 'still red after undo');
  });

  await test('f downloads', async () => {
    await click(page, 'build');
    for (const f of ['bom.csv', 'report.html', 'cuts_LUM-PINE-4x4.svg', 'scene.glb', 'model.stl']) {
      assert(await page.getByTestId(`download-${f}`).isVisible(), `no download ${f}`);
    }
    const sheets = await page.locator('[data-testid^="download-sheet_"]').count();
    assert(sheets >= 1, 'no sheet cut diagram');
    const total = (await page.getByTestId('bom-total').textContent()).slice(1);
    let [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('download-bom-csv').click()]);
    const csv = readFileSync(await dl.path(), 'utf8');
    assert(csv.startsWith('category,item,name,parts,units') && csv.includes('LUM-PINE-4x4') && csv.includes(total), `bom.csv:\n${csv.slice(0, 400)}`);
    [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('download-glb').click()]);
    const glb = readFileSync(await dl.path());
    assert(glb.subarray(0, 4).toString() === 'glTF', 'scene.glb is not binary glTF');
    [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('download-cuts_LUM-PINE-4x4.svg').click()]);
    const svg = readFileSync(await dl.path(), 'utf8');
    assert(/<svg[^>]*width="[\d.]+mm"/.test(svg), 'the cut diagram is not at true size (mm)');
    [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('download-report').click()]);
    assert(readFileSync(await dl.path(), 'utf8').includes('<html'), 'report is not HTML');
  });

  await test('g save-open-yaml', async () => {
    const [dl] = await Promise.all([page.waitForEvent('download'), page.getByTestId('save-yaml').click()]);
    const saved = readFileSync(await dl.path(), 'utf8');
    assert(saved.startsWith('fabkit: templates/1') && /loads:/.test(saved) && /adjust:/.test(saved), saved);
    const before = await composed(page);
    // a fresh tab opens the saved file and composes the same model
    const p2 = await freshPage();
    await p2.getByTestId('workspace-switcher').selectOption('templates'); await idle(p2);
    const file = path.join(tmpdir(), 'fabkit-templates-saved.yaml');
    writeFileSync(file, saved);
    await p2.getByTestId('open-file').setInputFiles(file); await idle(p2);
    const after = await composed(p2);
    assert(after && after.bom.total === before.bom.total && after.parts.length === before.parts.length, `reopened: ${after?.bom.total} vs ${before.bom.total}`);
    // the example file from the repository
    await p2.getByTestId('open-file').setInputFiles(example); await idle(p2);
    const ex = await composed(p2);
    assert(ex.name === 'Dining table with a bottom shelf' && ex.steps[1].links.every((l) => l.connected), `example: ${ex.name}`);
    await p2.close();
  });

  await test('h no-connection-explained', async () => {
    const p2 = await freshPage();
    await p2.getByTestId('workspace-switcher').selectOption('templates'); await idle(p2);
    // a caster dropped onto the table top: the database only has casters screwed under shelves
    await p2.getByTestId('template-search').fill('dining');
    await dropTemplate(p2, 'dining_table', null);
    await p2.getByTestId('template-search').fill('caster');
    await hook(p2, 'setCamera', [1200, -1800, 2200], [0, 0, 600]);
    await dropTemplate(p2, 'rolling_cart/wheels/caster_fl', [0, 0, 750]);
    // without snapping it stands on the top as dropped
    await p2.getByTestId('step-caster_fl-snap').uncheck(); await idle(p2);
    const c = await composed(p2);
    const failed = (c.steps[1].links ?? []).filter((l) => !l.connected);
    assert(failed.length > 0, `expected a pair that cannot be joined: ${JSON.stringify(c.steps[1])}`);
    const l = failed[0];
    const box = p2.getByTestId(`no-connection-${l.added}-${l.existing}`);
    assert(await box.isVisible(), 'the failure is not shown');
    const text = await box.textContent();
    assert(/no connection found/.test(text) && /tried/.test(text), `explanation: ${text}`);
    await shot(p2, 'no-connection');
    await p2.close();
  });

  await test('i drag-with-loads', async () => {
    const p2 = await freshPage();
    await p2.getByTestId('workspace-switcher').selectOption('templates'); await idle(p2);
    await p2.getByTestId('open-file').setInputFiles(example); await idle(p2);
    await click(p2, 'node-table');
    await hook(p2, 'setCamera', [2400, -2400, 900], [0, 0, 400]);
    await click(p2, 'node-table');
    const p = await hook(p2, 'handlePoint', 'size_x');
    assert(p, 'no size_x sphere');
    await p2.mouse.move(p.x, p.y); await p2.mouse.down();
    for (let i = 1; i <= 10; ++i) { await p2.mouse.move(p.x + i * 6, p.y - i * 3); await p2.waitForTimeout(60); }
    await p2.mouse.up(); await idle(p2);
    const t = await hook(p2, 'dragTimings');
    reportDrag('withLoad', 'table with shelf and a 300 N load', t);
    assert(t.length >= 2, 'too few drag steps');
    const width = () => hook(p2, 'modelYaml').then((y) => Number((y.match(/node: table, control: size_x, to: ([\d.]+)/) ?? [])[1]));
    const w1 = await width();
    assert(w1 > 1600, `the x sphere did not widen the table: ${w1}`);
    // the sphere on the opposite face, pulled outward (to -x), widens it too
    const q = await hook(p2, 'handlePoint', 'size_x', -1);
    assert(q, 'no size_x sphere on the min face');
    await p2.mouse.move(q.x, q.y); await p2.mouse.down();
    for (let i = 1; i <= 6; ++i) { await p2.mouse.move(q.x - i * 6, q.y + i * 3); await p2.waitForTimeout(60); }
    await p2.mouse.up(); await idle(p2);
    const w2 = await width();
    assert(w2 > w1, `pulling the min-face sphere outward: ${w1} → ${w2}`);
    assert((await composed(p2)).max_violation < 1e-6, 'constraints after the second drag');
    await p2.close();
  });

  await test('j screenshot-golden', async () => {
    const p2 = await freshPage();
    await p2.getByTestId('workspace-switcher').selectOption('templates'); await idle(p2);
    await p2.getByTestId('open-file').setInputFiles(example); await idle(p2);
    await p2.mouse.move(0, 0);
    await hook(p2, 'setCamera', [2000, -2600, 1500], [0, 0, 350]);
    await click(p2, 'node-shelf');
    await hook(p2, 'setCamera', [2000, -2600, 1500], [0, 0, 350]);
    const png = await canvasPng(p2);
    if (docsShots) await p2.screenshot({ path: path.join(repo, 'docs/templates-editor', 'editor.png') });
    if (process.env.FABKIT_UPDATE_GOLDEN === '1') { writeFileSync(golden, png); console.log(`  wrote ${golden}`); await p2.close(); return; }
    assert(existsSync(golden), `missing ${golden} (run with FABKIT_UPDATE_GOLDEN=1 to create it)`);
    const a = PNG.sync.read(png), b = PNG.sync.read(readFileSync(golden));
    assert(a.width === b.width && a.height === b.height, `size ${a.width}x${a.height} vs ${b.width}x${b.height}`);
    let bad = 0;
    for (let i = 0; i < a.data.length; i += 4) {
      const d = Math.max(Math.abs(a.data[i] - b.data[i]), Math.abs(a.data[i + 1] - b.data[i + 1]), Math.abs(a.data[i + 2] - b.data[i + 2]));
      if (d > 16) bad++;
    }
    const frac = bad / (a.width * a.height);
    const actual = path.join(tmpdir(), 'templates-actual.png');
    if (frac > 0.002) writeFileSync(actual, png);
    assert(frac <= 0.002, `${(frac * 100).toFixed(3)}% pixels differ (actual written to ${actual})`);
    await p2.close();
  });
} finally {
  await context.close();
  server.kill();
  rmSync(userDir, { recursive: true, force: true });
}
finish();
