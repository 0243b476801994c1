// The HTML report of `jnd report` in a real browser: Debian's chromium, headless,
// driven by playwright-core (pinned in tests/browser/playwright.sh). From file://,
// with every request that is not a file refused and counted:
//   - no console error, no page error, no request outside file://
//   - every image of every page loads (complete, natural size > 0)
//   - the index's totals and every number of its table equal summary.json
//     (data-value exactly; the shown text within its rounding)
//   - clicking a column sorts by it, the status filter hides the other rows
//   - each asset's page opens from the index
// usage: node report.js PLAYWRIGHT_CORE_DIR OUT SCREENSHOT.png
'use strict';
const path = require('path');
const fs = require('fs');
const [pwDir, out, shot] = process.argv.slice(2);
const { chromium } = require(pwDir);
const summary = JSON.parse(fs.readFileSync(path.join(out, 'summary.json'), 'utf8'));
const failures = [];
const fail = (m) => { failures.push(m); console.log('FAIL ' + m); };
const ok = (m) => console.log('ok   ' + m);

// the index's text for a number, as report.c writes it
function shown(v, kind) {
  if (v === null || v === undefined) return '—';
  if (kind === 'p') return v.toFixed(3);
  if (kind === 'percent') return (100 * v).toFixed(1) + '%';
  if (kind === 'number') return v.toFixed(1);
  if (kind === 'bytes') {
    const x = v / 1048576;
    return (Math.abs(x) >= 0.01 || x === 0 ? x.toFixed(2) : x.toFixed(4)) + ' MiB';
  }
  return String(v);
}

// Whether a cell's text is v rounded as shown() rounds it.  The report is
// written by C, whose printf breaks an exact tie to even (3.25 -> '3.2'),
// while toFixed breaks it upwards ('3.3'); both are v to that many places,
// anything further off is not.
function showsValue(text, v, kind) {
  if (text === shown(v, kind)) return true;
  if (v === null || v === undefined) return false;
  const want = shown(v, kind);
  const m = /^(-?\d+\.(\d+))(.*)$/.exec(text);
  const w = /^(-?\d+\.(\d+))(.*)$/.exec(want);
  if (!m || !w || m[3] !== w[3] || m[2].length !== w[2].length) return false;
  const scale = kind === 'percent' ? 100 : kind === 'bytes' ? 1 / 1048576 : 1;
  const half = 0.5 * Math.pow(10, -m[2].length);
  return Math.abs(parseFloat(m[1]) - v * scale) <= half * (1 + 1e-9);
}

(async () => {
  const browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
           '--disable-component-update', '--disable-sync'],
  });
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  let offline = 0;
  await context.route('**/*', (route) => {
    if (route.request().url().startsWith('file:')) return route.continue();
    offline++;
    fail('a request outside file://: ' + route.request().url());
    return route.abort();
  });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push('failed to load ' + r.url()));

  async function imagesLoad(name) {
    const imgs = await page.$$eval('img', (xs) => xs.map((i) => ({ src: i.getAttribute('src'), ok: i.complete && i.naturalWidth > 0 })));
    const bad = imgs.filter((i) => !i.ok);
    if (bad.length) fail(`${name}: ${bad.length} of ${imgs.length} images did not load: ${bad.map((b) => b.src).join(', ')}`);
    return imgs.length;
  }

  const index = 'file://' + path.resolve(out, 'report', 'index.html');
  await page.goto(index, { waitUntil: 'load' });
  await imagesLoad('index');

  // the totals
  const tot = summary.result.totals;
  for (const k of ['assets', 'ok', 'above', 'failed', 'pending', 'memory_before_bytes', 'memory_after_bytes', 'reduction', 'seconds']) {
    if (!(k in tot)) continue;
    const v = await page.$eval('#total-' + k, (e) => e.getAttribute('data-value')).catch(() => null);
    if (v === null ? tot[k] !== null : parseFloat(v) !== tot[k]) fail(`total ${k}: page ${v}, summary.json ${tot[k]}`);
  }
  ok('the totals equal summary.json');

  // every row and number of the table
  const rows = await page.$$eval('#assets tbody tr', (trs) => trs.map((tr) => {
    const heads = Array.from(document.querySelectorAll('#assets thead th')).map((h) => h.getAttribute('data-key'));
    const o = { id: tr.getAttribute('data-id'), status: tr.getAttribute('data-status'), cells: {} };
    Array.from(tr.cells).forEach((td, i) => { o.cells[heads[i]] = { value: td.getAttribute('data-value'), text: td.textContent.trim() }; });
    return o;
  }));
  const assets = summary.result.assets;
  if (rows.length !== assets.length) fail(`the table has ${rows.length} rows, summary.json ${assets.length} assets`);
  const kinds = { p_detect: 'p', memory_before_bytes: 'bytes', memory_after_bytes: 'bytes', reduction: 'percent', seconds: 'number' };
  let numbers = 0;
  assets.forEach((a, i) => {
    const r = rows[i];
    if (!r || r.id !== a.id || r.status !== a.status) { fail(`row ${i}: ${JSON.stringify(r && [r.id, r.status])} is not ${a.id} ${a.status}`); return; }
    if (r.cells.command.text !== a.command) fail(`${a.id}: command ${r.cells.command.text}`);
    if (r.cells.decision.text !== a.decision) fail(`${a.id}: decision '${r.cells.decision.text}'`);
    if (r.cells.error.text !== (a.error || '')) fail(`${a.id}: error '${r.cells.error.text}'`);
    for (const [k, kind] of Object.entries(kinds)) {
      if (!(k in a)) continue;
      const c = r.cells[k];
      if (!c) { fail(`${a.id}: no column ${k}`); continue; }
      const v = a[k];
      const exact = v === null ? c.value === '' : parseFloat(c.value) === v;
      if (!exact) fail(`${a.id} ${k}: data-value ${c.value}, summary.json ${v}`);
      if (!showsValue(c.text, v, kind)) fail(`${a.id} ${k}: shows '${c.text}', summary.json ${v} reads '${shown(v, kind)}'`);
      numbers++;
    }
  });
  ok(`the table's ${rows.length} rows and ${numbers} numbers equal summary.json`);

  // sorting: by memory before, ascending then descending, assets without it last
  const col = (key) => page.$$eval('#assets tbody tr', (trs, key) => {
    const i = Array.from(document.querySelectorAll('#assets thead th')).findIndex((h) => h.getAttribute('data-key') === key);
    return trs.map((tr) => tr.cells[i].getAttribute('data-value'));
  }, key);
  await page.click('#assets th[data-key=memory_before_bytes]');
  let vals = await col('memory_before_bytes');
  const nums = vals.filter((v) => v !== '').map(parseFloat);
  const sortedAsc = nums.every((v, i) => i === 0 || nums[i - 1] <= v) && vals.slice(nums.length).every((v) => v === '');
  if (!sortedAsc || nums.length < 2) fail('sorting by memory before (ascending): ' + vals.join(' '));
  await page.click('#assets th[data-key=memory_before_bytes]');
  vals = await col('memory_before_bytes');
  const desc = vals.filter((v) => v !== '').map(parseFloat);
  if (!desc.every((v, i) => i === 0 || desc[i - 1] >= v)) fail('sorting by memory before (descending): ' + vals.join(' '));
  await page.click('#assets th[data-key=id]');
  const ids = (await col('id')).length;
  if (ids !== assets.length) fail('sorting lost rows');
  ok('clicking a column sorts the table by it');

  // filtering by status
  await page.selectOption('#status-filter', 'failed');
  const visible = await page.$$eval('#assets tbody tr', (trs) => trs.filter((t) => !t.hidden).map((t) => t.getAttribute('data-status')));
  const failed = assets.filter((a) => a.status === 'failed').length;
  if (visible.length !== failed || visible.some((s) => s !== 'failed')) fail(`filter 'failed' shows ${visible.join(',')}`);
  const count = await page.textContent('#shown');
  if (count !== `${failed} shown`) fail(`the filter's count says '${count}'`);
  await page.selectOption('#status-filter', '');
  ok(`the status filter shows the ${failed} failed assets only`);

  // the screenshot of the index (docs/batch.md shows one)
  await page.goto(index, { waitUntil: 'load' }); // in manifest order for the picture
  await page.screenshot({ path: shot, fullPage: true });

  // each asset's page, from the index's link
  let pictures = 0;
  for (const a of assets) {
    await page.goto(index, { waitUntil: 'load' });
    await Promise.all([page.waitForNavigation({ waitUntil: 'load' }), page.click(`#assets tr[data-id="${a.id}"] a`)]);
    const h1 = await page.textContent('h1');
    if (!h1.startsWith(a.id)) fail(`${a.id}: the page's title is '${h1}'`);
    pictures += await imagesLoad(a.id);
  }
  ok(`every asset's page opens and its ${pictures} pictures load`);
  if (errors.length) fail('console or page errors: ' + errors.join(' | '));
  else ok('no console errors');
  if (!offline) ok('no request left file://');
  await browser.close();
  console.log(`${failures.length ? 'FAILED' : 'passed'}: ${failures.length} failures`);
  process.exit(failures.length ? 1 : 0);
})().catch((e) => { console.error('FAIL ' + (e && e.stack || e)); process.exit(1); });
