// The web page in a real browser: Debian's Chromium, headless, driven by
// puppeteer-core, against a real wiredem-server on loopback running a real
// small job (tests/web/job.json: examples/tiny.json with a helix of wire).
// What the page shows is compared with what the API and summary.json hold:
// figures, the number of series and points of each plot (read from the data
// the page drew, not from pixels), the Mohr envelope against φ and c, the
// wire's autocorrelation lag against the summary's, and the 3D canvas against
// its background in a screenshot; the flagged Mohr-Coulomb fits wherever they
// are shown; the 3D view's wire seen (by ray casts in its scene graph and by
// its colours in screenshots), its framing and colour bar; the compare
// view's colours and dashes; a submit form no wider than the window; the
// form's grain-size, grain-shape, rolling and wire-break fields with the
// door's errors, and the clump job they make drawn sphere by sphere; a wire's
// breaks and pieces (tests/web/job-breaks.json) and a wire pulled out of
// its column (tests/web/job-pull.json: the pull force against the pulled
// length) on the job page and the offline report. Every page must load without a console
// error or a failed request; a job named like an HTML tag shows as text.
//
// Run through ctest (tests/web/run.sh). WIREDEM_WEB_SCREENSHOTS=DIR saves the
// main pages as PNG into DIR (docs/pictures/ for the README).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, rmSync, existsSync, openSync, closeSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';

function env(name) {
  const v = process.env[name];
  if (!v) throw new Error(`${name} is not set: run this test through ctest (tests/web/run.sh)`);
  return v;
}
const require = createRequire(path.join(env('WIREDEM_WEB_NODE_MODULES'), 'index.js'));
const puppeteer = require('puppeteer-core');
const serverBin = env('WIREDEM_SERVER_BIN');
const sourceDir = env('WIREDEM_SOURCE_DIR');
const screenshots = process.env.WIREDEM_WEB_SCREENSHOTS || '';
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const xssName = '<img src=x onerror=alert(1)>';

/// A wiredem-server child on 127.0.0.1:<free port> with its own data directory.
class Server {
  static async start(dir, extra = []) {
    const s = new Server();
    s.dir = dir;
    const portFile = path.join(dir, 'port');
    const log = openSync(path.join(dir, 'server.log'), 'a');
    s.proc = spawn(serverBin, ['--listen', '127.0.0.1:0', '--port-file', portFile, '--data-dir', path.join(dir, 'data'),
      '--jobs', '1', '--threads-per-job', '2', ...extra], { stdio: ['ignore', log, log] });
    closeSync(log);
    s.exited = new Promise((resolve) => s.proc.on('exit', (code) => resolve(code)));
    for (let i = 0; i < 200 && !existsSync(portFile); ++i) await sleep(50);
    s.port = Number(readFileSync(portFile, 'utf8'));
    s.url = `http://127.0.0.1:${s.port}`;
    return s;
  }
  async api(method, route, { body, token } = {}) {
    const headers = {};
    if (body !== undefined) headers['Content-Type'] = 'application/json';
    if (token) headers.Authorization = `Bearer ${token}`;
    const res = await fetch(this.url + route, { method, headers, body });
    const text = await res.text();
    let json = null;
    try { json = JSON.parse(text); } catch { /* not JSON */ }
    return { status: res.status, json };
  }
  async waitFor(id, states, limitMs = 420000, token) {
    const deadline = Date.now() + limitMs;
    for (;;) {
      const { json } = await this.api('GET', `/v1/jobs/${id}`, { token });
      if (states.includes(json.state)) return json;
      if (Date.now() > deadline) throw new Error(`job ${id} still ${json.state} after ${limitMs} ms: ${this.log()}`);
      await sleep(200);
    }
  }
  log() { return readFileSync(path.join(this.dir, 'server.log'), 'utf8').slice(-3000); }
  async stop() {
    this.proc.kill('SIGTERM');
    const code = await Promise.race([this.exited, sleep(10000).then(() => 'timeout')]);
    if (code === 'timeout') this.proc.kill('SIGKILL');
    return code;
  }
}

/// Everything that went wrong on a page: console errors, uncaught exceptions,
/// failed requests, HTTP errors not announced with expect(), dialogs (an
/// injected alert()).
function watch(page) {
  const w = { problems: [], expected: [], requests: [] };
  w.expect = (status, urlPart) => w.expected.push({ status, urlPart });
  const isExpected = (status, url) => w.expected.some((e) => e.status === status && url.includes(e.urlPart));
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    // Chromium also logs each error status it received; those are judged by their response below.
    const loc = m.location()?.url || '';
    if (/Failed to load resource: the server responded with a status of \d+/.test(m.text())) {
      const status = Number(m.text().match(/status of (\d+)/)[1]);
      if (isExpected(status, loc)) return;
    }
    w.problems.push(`console error: ${m.text()} (${loc})`);
  });
  page.on('pageerror', (e) => w.problems.push(`uncaught: ${e.message}`));
  page.on('requestfailed', (r) => w.problems.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on('request', (r) => w.requests.push({ url: r.url(), headers: r.headers() }));
  page.on('response', (r) => {
    if (r.status() >= 400 && !isExpected(r.status(), r.url())) w.problems.push(`HTTP ${r.status()}: ${r.url()}`);
  });
  page.on('dialog', async (d) => { w.problems.push(`dialog: ${d.message()}`); await d.dismiss(); });
  return w;
}

let browser, tmp, server, mainId, xssId, growId, breaksId, pullId, summary;

async function newPage() {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 1000 });
  return { page, w: watch(page) };
}

async function shot(page, name, options = {}) {
  if (screenshots) await page.screenshot({ path: path.join(screenshots, name), ...options });
}

/// A number as the page shows it (num(): 4 significant digits) matches `expected`.
function assertShown(text, expected, what) {
  const shown = Number(text);
  assert.ok(Number.isFinite(shown), `${what}: '${text}' is not a number`);
  assert.ok(Math.abs(shown - expected) <= 5e-4 * Math.abs(expected) + 1e-12, `${what}: page shows ${text}, expected ${expected}`);
}

before(async () => {
  tmp = mkdtempSync(path.join(tmpdir(), 'wiredem-web-'));
  // Checkpoints every 0.2 s: a running job's curves grow on its page.
  server = await Server.start(tmp, ['--checkpoint-seconds', '0.2']);
  const spec = readFileSync(path.join(sourceDir, 'tests/web/job.json'), 'utf8');
  const main = await server.api('POST', '/v1/jobs', { body: spec });
  assert.equal(main.status, 201, JSON.stringify(main.json));
  mainId = main.json.id;
  // Queued behind the main job (one worker): the list shows it, and the page cancels it.
  const xss = await server.api('POST', '/v1/jobs', { body: JSON.stringify({ ...JSON.parse(spec), name: xssName }) });
  assert.equal(xss.status, 201);
  xssId = xss.json.id;
  // Then a job whose tests load 20 times slower than the main job's (each
  // lasts tens of seconds, not the main job's one or two): its page is
  // watched until its curves have grown, whatever the machine's speed, and
  // the job is cancelled then.
  const slow = JSON.parse(spec);
  slow.name = 'web test: the slow job whose curves grow';
  slow.triaxial.plate_speed_m_per_s /= 20;
  const grow = await server.api('POST', '/v1/jobs', { body: JSON.stringify(slow) });
  assert.equal(grow.status, 201, JSON.stringify(grow.json));
  growId = grow.json.id;
  // A wire that breaks in its test and is cut (tests/web/job-breaks.json, about 14 s): its breaks and pieces.
  const breaks = await server.api('POST', '/v1/jobs', { body: readFileSync(path.join(sourceDir, 'tests/web/job-breaks.json'), 'utf8') });
  assert.equal(breaks.status, 201, JSON.stringify(breaks.json));
  breaksId = breaks.json.id;
  // The wire pulled out of the free column (tests/web/job-pull.json): the pull's plot.
  const pull = await server.api('POST', '/v1/jobs', { body: readFileSync(path.join(sourceDir, 'tests/web/job-pull.json'), 'utf8') });
  assert.equal(pull.status, 201, JSON.stringify(pull.json));
  pullId = pull.json.id;
  browser = await puppeteer.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    // --no-sandbox: CI runs as root; SwiftShader: WebGL without a GPU. The
    // job list and the running job's page are open at once: neither is
    // throttled or frozen for being in the background.
    args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--window-size=1400,1000',
      '--disable-background-timer-throttling', '--disable-backgrounding-occluded-windows', '--disable-renderer-backgrounding'],
  });
});

after(async () => {
  if (browser) await browser.close();
  if (server) assert.equal(await server.stop(), 0, 'the server stops cleanly');
  if (tmp) rmSync(tmp, { recursive: true, force: true });
});

test('job list: the job appears, its progress moves, a tag-like name is text, the state filter and cancel work; a running job\'s curves grow on its page', async () => {
  const { page, w } = await newPage();
  // The slow job's own page, open from while it is queued: it follows the
  // job into its tests, and its curves, from the tests' checkpoints, grow.
  const { page: livePage, w: liveWatch } = await newPage();
  await livePage.goto(`${server.url}/#/jobs/${growId}`);
  await page.bringToFront();
  await page.goto(`${server.url}/#/`);
  await page.waitForSelector(`tr[data-id="${xssId}"]`);
  const name = await page.$eval(`tr[data-id="${xssId}"] td.name`, (td) => td.textContent);
  assert.equal(name, xssName);
  assert.equal(await page.$$eval('#jobs img', (imgs) => imgs.length), 0, 'no element was made from the name');

  // Clicked in the page, in one step: the list redraws every second, and
  // page.click's find-scroll-click can hold a row that was just replaced.
  await page.$eval(`tr[data-id="${xssId}"] button.cancel`, (b) => b.click());
  await page.waitForSelector(`tr[data-id="${xssId}"][data-state="cancelled"]`);
  assert.equal((await server.api('GET', `/v1/jobs/${xssId}`)).json.state, 'cancelled');

  await page.select('#state-filter', 'cancelled');
  await page.waitForFunction(() => {
    const rows = [...document.querySelectorAll('#jobs tbody tr[data-id]')];
    return rows.length > 0 && rows.every((r) => r.dataset.state === 'cancelled');
  });
  assert.deepEqual(await page.$$eval('#jobs tbody tr[data-id]', (rows) => rows.map((r) => r.dataset.id)), [xssId]);
  await page.select('#state-filter', '');

  // The main job's progress bar, sampled as the list refreshes, until it has succeeded.
  const seen = new Set();
  const deadline = Date.now() + 420000;  // a few seconds alone; minutes on a loaded CI machine
  for (;;) {
    await sleep(300);
    const row = await page.$eval(`tr[data-id="${mainId}"]`, (r) => ({ state: r.dataset.state, progress: r.querySelector('progress').value })).catch(() => null);
    if (row && ['preparing', 'running'].includes(row.state)) seen.add(row.progress);
    if (row && row.state === 'succeeded') break;
    assert.ok(row === null || ['queued', 'preparing', 'running'].includes(row.state), `main job ${row && row.state}: ${server.log()}`);
    assert.ok(Date.now() < deadline, `job not finished: ${server.log()}`);
  }
  assert.ok(seen.size >= 2, `progress should move in the list, saw ${[...seen]}`);

  // The slow job's live q–ε plot (every test's loading rows so far), as its
  // page refreshes, until it has grown twice; then the job is cancelled.
  const livePoints = [];
  for (;;) {
    await sleep(300);
    const live = await livePage.evaluate(() => {
      const plot = document.querySelector('#live-curves #plot-q');
      const note = document.querySelector('#live-note');
      return plot && note ? { points: plot.wiredemPlot.series.reduce((n, s) => n + s.x.length, 0), partial: note.dataset.partial !== undefined } : null;
    });
    if (live && live.partial && live.points > 0 && live.points !== livePoints.at(-1)) livePoints.push(live.points);
    if (livePoints.length >= 3) break;
    const state = (await server.api('GET', `/v1/jobs/${growId}`)).json.state;
    assert.ok(['queued', 'preparing', 'running'].includes(state), `the slow job is ${state} before its curves grew (${livePoints} points): ${server.log()}`);
    assert.ok(Date.now() < deadline, `the slow job's curves did not grow (${livePoints} points): ${server.log()}`);
  }
  assert.deepEqual(livePoints, [...livePoints].sort((a, b) => a - b), `the running job's curves only grow: ${livePoints}`);
  assert.equal((await server.api('DELETE', `/v1/jobs/${growId}`)).status, 200);
  assert.equal((await server.waitFor(growId, ['cancelled'], 60000)).state, 'cancelled');
  // The page is in the background: poll on a timer, not on animation frames.
  await livePage.waitForFunction(() => document.querySelector('#job-state')?.textContent === 'cancelled', { polling: 200 });
  // Its partial curves stay, and say where the tests stopped, not that they run.
  const note = await livePage.waitForFunction(() => {
    const text = document.querySelector('#live-note')?.textContent ?? '';
    return text.includes('the job was cancelled') && text;
  }, { polling: 200 }).then((h) => h.jsonValue());
  assert.ok(note.includes('stopped') && !note.includes('running'), note);
  assert.ok(await livePage.evaluate(() => document.querySelector('#live-curves #plot-q').wiredemPlot.series.length > 0));
  assert.deepEqual(liveWatch.problems, []);
  await livePage.close();
  summary = (await server.api('GET', `/v1/jobs/${mainId}/summary`)).json;
  await page.waitForSelector(`tr[data-id="${mainId}"] input[type=checkbox]:not([disabled])`);
  await shot(page, 'web-jobs.png');
  assert.deepEqual(w.problems, []);
  await page.close();
});

test('job page: summary figures, every plot\'s series and points, the Mohr envelope, the wire, the 3D view', async () => {
  assert.ok(summary, 'the job list test ran first');
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/jobs/${mainId}`);
  await page.waitForFunction(() => document.querySelector('#view3d-canvas')?.wiredemView && document.querySelector('#plot-autocorrelation')?.wiredemPlot, { timeout: 60000 });

  // Figures and the per-test table against summary.json.
  const mc = summary.mohr_coulomb;
  const figure = (key) => page.$eval(`[data-figure="${key}"] .value`, (e) => e.textContent);
  assertShown(await figure('friction_angle_deg'), mc.friction_angle_deg, 'φ');
  assertShown(await figure('cohesion_pa'), mc.cohesion_pa / 1000, 'c [kPa]');
  assertShown(await figure('grain_volume_fraction'), summary.specimen.grain_volume_fraction, 'grain volume fraction');
  // Which triaxial cell ran (the job's membrane).
  assert.equal(summary.specimen.cell, 'membrane');
  assert.equal(await figure('cell'), 'membrane (flexible, pressurised)', 'the triaxial cell');
  assertShown(await figure('autocorrelation_lag_m'), summary.wire.autocorrelation_lag_m * 1000, 'lag [mm]');
  const prominentShown = await figure('autocorrelation_prominent_lag_m');
  if (summary.wire.autocorrelation_prominent_lag_m == null) assert.equal(prominentShown, '—', 'no prominent lag');
  else assertShown(prominentShown, summary.wire.autocorrelation_prominent_lag_m * 1000, 'prominent lag [mm]');
  for (const t of summary.tests) {
    for (const key of ['peak_deviatoric_stress_pa', 'sigma1_pa', 'sigma3_effective_pa']) {
      const text = await page.$eval(`tr[data-pressure="${t.confining_pressure_pa}"] td[data-key="${key}"]`, (e) => e.textContent);
      assertShown(text, t[key] / 1000, `${key} at ${t.confining_pressure_pa}`);
    }
  }
  assert.equal(await page.$$eval('#warnings li', (li) => li.length), summary.warnings.length, 'every warning is shown');
  await checkFlaggedFit(page, 'job page');

  // Each curve plot: one series per test, as many points as the test's loading rows in the series route.
  const { tests } = (await server.api('GET', `/v1/jobs/${mainId}/tests`)).json;
  const plots = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('.plot')].map((p) => [p.id, p.wiredemPlot])));
  for (const [id, column, scale] of [['plot-q', 'deviatoric_stress_pa', 1e-3], ['plot-ratio', 'stress_ratio', 1], ['plot-volumetric', 'volumetric_strain', 1]]) {
    assert.equal(plots[id].series.length, tests.length, `${id}: one series per test`);
    for (let i = 0; i < tests.length; ++i) {
      const s = (await server.api('GET', `${tests[i].series_url}?max_points=1000&columns=axial_strain,${column},phase`)).json;
      const loading = s.columns.phase.map((p, r) => r).filter((r) => s.columns.phase[r] === 2);
      assert.ok(loading.length > 10, `${id}: test ${i} has loading rows`);
      assert.equal(plots[id].series[i].x.length, loading.length, `${id}: points of test ${i}`);
      assert.equal(plots[id].series[i].y[loading.length - 1], s.columns[column][loading.at(-1)] * scale, `${id}: last point of test ${i}`);
    }
  }

  // Mohr: the envelope is τ = c + σ tan φ, and with two tests the fit is exact, so every yield circle touches it.
  const mohr = plots['plot-mohr'];
  const env = mohr.series.find((s) => s.label.startsWith('envelope'));
  const tanPhi = Math.tan((mc.friction_angle_deg * Math.PI) / 180);
  // Rounding is relative to the plotted stresses (c alone may be near zero, or negative).
  const envScale = Math.max(...env.y.map(Math.abs));
  assert.ok(Math.abs(env.y[0] - (mc.cohesion_pa / 1000 + env.x[0] * tanPhi)) < 1e-9 * envScale, `envelope at σ = ${env.x[0]}: ${env.y[0]}`);
  assert.ok(Math.abs((env.y[1] - env.y[0]) / (env.x[1] - env.x[0]) - tanPhi) < 1e-12);
  const yieldStates = summary.tests.filter((t) => t.yield);
  assert.equal(mohr.series.filter((s) => s.label.startsWith('yield')).length, yieldStates.length);
  const cosPhi = Math.cos(Math.atan(tanPhi));
  for (const t of yieldStates) {
    const p = (t.yield.sigma1_pa + t.yield.sigma3_effective_pa) / 2000, r = (t.yield.sigma1_pa - t.yield.sigma3_effective_pa) / 2000;
    const circle = mohr.series.find((s) => s.label === `yield at σ₃ = ${t.confining_pressure_pa / 1000} kPa`);
    assert.ok(circle, `circle of ${t.confining_pressure_pa}`);
    assert.ok(Math.abs(Math.max(...circle.y) - r) < 1e-9 * r, 'the circle\'s top is its radius');
    if (summary.tests.length === 2) assert.ok(Math.abs((mc.cohesion_pa / 1000 + p * tanPhi) * cosPhi - r) < 1e-6 * r, 'the envelope touches the circle');
  }
  assert.ok(mohr.series.some((s) => s.label.startsWith('slope of the tops')), 'the slope-of-the-tops line is drawn and labelled');
  checkMohrAxis(mohr, 'job page');
  // The volumetric strain says which sign is compaction.
  assert.match(await page.$eval('#plot-volumetric .note', (e) => e.textContent), /positive when the column compacts/);
  assert.match(plots['plot-volumetric'].yLabel, /> 0 compaction/);

  // The free-standing test: σ₁ against ε₁ with the strength marked and labelled, radius profiles, the wire's tension.
  await checkFreeStanding(page, plots, 'job page');

  // The wire: segments along its length, and the autocorrelation of the snapshot the summary's lag comes from.
  assert.equal(plots['plot-wire-strain'].series[0].x.length, summary.specimen.wire_nodes - 1);
  const ac = plots['plot-autocorrelation'];
  assert.equal(ac.first_maximum_lag_m, summary.wire.autocorrelation_lag_m);
  assert.equal(ac.prominent_maximum_lag_m, summary.wire.autocorrelation_prominent_lag_m);
  // Both maxima marked and labelled (one marker each; none when there is no such lag).
  assert.deepEqual(ac.markers.map((m) => m.replace(/ [0-9.]+ mm$/, '')),
    [['first maximum', ac.first_maximum_lag_m], ['first prominent maximum', ac.prominent_maximum_lag_m]].filter(([, v]) => v != null).map(([l]) => l));

  // 3D: what was built, and pixels that are not the background.
  const view = await page.$eval('#view3d-canvas', (c) => c.wiredemView);
  assert.equal(view.grains, summary.specimen.grains);
  assert.equal(view.wireSegments, summary.specimen.wire_nodes - 1);
  assert.ok(view.contacts > 0 && view.membraneTriangles > 0, JSON.stringify(view));
  const canvas = await page.$('#view3d-canvas');
  await canvas.scrollIntoView();
  const before = await canvas.screenshot({ encoding: 'base64' });
  const shown = await page.evaluate(pixelStats, before);
  assert.ok(shown.notBackground > 0.05, `the 3D view is blank: ${shown.notBackground} of its pixels differ from the background`);
  // The specimen fills the frame: what is not background spans most of the canvas's height.
  assert.ok(shown.height > 0.7, `the specimen spans ${shown.height} of the canvas's height`);
  // A colour bar with the strain scale of the wire's colours.
  assert.equal(await page.$eval('#view3d-colour-bar', (e) => e.hidden), false, 'the colour bar is shown');
  assert.equal(await page.$eval('#view3d-colour-max', (e) => e.textContent), `+${Number((view.maxAbsStrain * 1000).toPrecision(2))}·10⁻³`);

  // The wire is seen (the scene graph: the share of its segments whose
  // midpoint is the first thing a ray from the camera meets). By default the
  // grains are drawn small, so most of it shows; full-size grains hide most
  // of it, and cutting half of them away reveals it again.
  // (The force network, red like a stretched wire, is hidden meanwhile.)
  const wireSeen = () => page.$eval('#view3d-canvas', (c) => c.wiredemWireVisibility());
  assert.equal(await page.$eval('#view3d-grain-mode', (e) => e.value), 'small', 'a specimen with wire shows its grains small');
  await page.click('#view3d-forces');
  const seenSmall = await wireSeen();
  await page.select('#view3d-grain-mode', 'solid');
  await sleep(300);
  const solid = await canvas.screenshot({ encoding: 'base64' });
  const seenSolid = await wireSeen();
  await page.click('#view3d-cut');
  await sleep(300);
  const cut = await canvas.screenshot({ encoding: 'base64' });
  const seenCut = await wireSeen();
  const cutAway = await page.evaluate(pixelStats, solid, cut);
  const [wirePixelsSolid, wirePixelsCut] = [cutAway.strainColoured, cutAway.b.strainColoured];
  console.log(`3D view: wire seen ${seenSmall} (small grains), ${seenSolid} (full size), ${seenCut} (full size, cut); `
    + `wire-coloured pixels ${wirePixelsSolid} → ${wirePixelsCut} when cut; specimen spans ${shown.height} of the height`);
  assert.ok(seenSmall > 0.6, `small grains: ${seenSmall} of the wire is seen`);
  assert.ok(seenSolid < seenSmall, `full-size grains hide more of the wire (${seenSolid}) than small ones (${seenSmall})`);
  assert.ok(seenCut > 0.35 && seenCut > seenSolid + 0.2, `cutting half of the grains away reveals the wire: ${seenSolid} → ${seenCut}`);
  assert.ok(cutAway.changed > 0.01, 'cutting half away changes the picture');
  // ... and in pixels: the wire's strain colours (blue or red, g ≈ b or r ≈ g) cover more of the cut picture.
  assert.ok(wirePixelsCut > 1.5 * wirePixelsSolid, `wire-coloured pixels: ${wirePixelsSolid} → ${wirePixelsCut} when cut`);
  if (screenshots) await canvas.screenshot({ path: path.join(screenshots, 'web-3d-cut.png') });
  await page.click('#view3d-cut');
  await page.click('#view3d-forces');
  await page.select('#view3d-grain-mode', 'small');
  await sleep(300);
  await shot(page, 'web-job.png', { fullPage: true });
  if (screenshots) {
    await canvas.screenshot({ path: path.join(screenshots, 'web-3d.png') });
    const caveats = await page.$('#fit-caveats');
    if (caveats) {
      const mohrBox = await page.$('#plot-mohr');
      await mohrBox.scrollIntoView();
      await mohrBox.screenshot({ path: path.join(screenshots, 'web-mohr-flagged.png') });
      // The figures and the caveats under them, in the page's coordinates.
      const top = await page.$eval('#figures', (e) => e.getBoundingClientRect().top + window.scrollY);
      const bottom = await page.$eval('#fit-caveats', (e) => e.getBoundingClientRect().bottom + window.scrollY);
      await page.screenshot({ path: path.join(screenshots, 'web-fit-caveats.png'), captureBeyondViewport: true,
        clip: { x: 0, y: top - 8, width: 1400, height: bottom - top + 16 } });
    }
  }
  assert.deepEqual(w.problems, []);
  await page.close();
});

/// The free-standing test where a page shows it, against summary.json and the
/// API's /free_standing and its series: the compression's points (σ₁ of every
/// phase-3 row), the unconfined strength drawn at its value with its shape in
/// the label and a marker at its strain, the envelope's prediction drawn at
/// its value; radius against height for each profile the test has, point
/// for point; the wire's tension along its length, segment for segment.
async function checkFreeStanding(page, plots, where) {
  const fs = summary.free_standing;
  assert.ok(fs, `${where}: the test job has a free-standing test`);
  const c = fs.compression;
  const test = (await server.api('GET', `/v1/jobs/${mainId}/free_standing`)).json;
  const s = (await server.api('GET', `${test.series_url}?max_points=2000&columns=axial_strain,sigma1_pa,phase`)).json;
  const rows = s.columns.phase.map((_, r) => r).filter((r) => s.columns.phase[r] === 3);
  assert.ok(rows.length > 10, `${where}: the compression has rows (${rows.length})`);
  const stress = plots['plot-fs-stress'];
  assert.ok(stress, `${where}: the stress–strain plot is drawn`);
  const curve = stress.series[0];
  assert.equal(curve.x.length, rows.length, `${where}: a point per compression row`);
  // === (not Object.is): a −0 the API sends reaches the test from the page as 0.
  assert.ok(curve.y.at(-1) === s.columns.sigma1_pa[rows.at(-1)] / 1000, `${where}: last σ₁ ${curve.y.at(-1)}`);
  assert.ok(curve.x.at(-1) === s.columns.axial_strain[rows.at(-1)], `${where}: last ε₁ ${curve.x.at(-1)}`);
  assert.ok(['peak', 'plateau', 'rising'].includes(c.shape), JSON.stringify(c));
  const strength = stress.series.find((x) => x.label.startsWith('unconfined strength'));
  assert.ok(strength && strength.label.includes(`(${c.shape})`), `${where}: the strength is labelled with its shape: ${strength?.label}`);
  assert.ok(strength.y.every((v) => v === c.unconfined_strength_pa / 1000), `${where}: the strength line at ${c.unconfined_strength_pa} Pa`);
  assert.equal(stress.strength.shape, c.shape, where);
  for (const [k, v] of [['value_pa', c.unconfined_strength_pa], ['strain', c.strain_at_failure], ['predicted_pa', c.predicted_unconfined_strength_pa]])
    assert.ok(stress.strength[k] === v, `${where}: strength.${k} ${stress.strength[k]} against ${v}`);
  assertShown(await page.$eval('[data-figure="fs_unconfined_strength_pa"] .value', (e) => e.textContent), c.unconfined_strength_pa / 1000, `${where}: strength tile`);
  assert.match(await page.$eval('[data-figure="fs_unconfined_strength_pa"] .label', (e) => e.textContent), new RegExp(`\\(${c.shape}\\)`));
  if (c.predicted_unconfined_strength_pa != null) {
    const predicted = stress.series.find((x) => x.label.startsWith('envelope'));
    assert.ok(predicted && predicted.y.every((v) => v === c.predicted_unconfined_strength_pa / 1000), `${where}: the prediction is drawn at its value`);
  }
  assert.equal(await page.$eval('[data-figure="fs_stands"] .value', (e) => e.textContent), fs.settling.stands ? 'yes' : 'no');
  // How it failed: the summary's mode, with the spilled share it read.
  assert.ok(['wire_break', 'grains_spilling', 'bulging', 'unresolved'].includes(c.failure_mode), `${where}: failure_mode ${c.failure_mode}`);
  const how = await page.$eval('[data-figure="fs_failure_mode"] .value', (e) => e.textContent);
  assert.match(how, new RegExp(`^${{ wire_break: 'the wire broke', grains_spilling: 'grains spilling', bulging: 'bulging', unresolved: 'not resolved' }[c.failure_mode]}`), `${where}: ${how}`);
  assert.ok(how.includes('spilled ') && how.includes('widest slice +'), `${where}: ${how}`);
  // The verdict reads the grains' bulk and the grains lost (the job keeps the default bounds, 0.1 and 0.1).
  const st = fs.settling;
  assert.equal(st.stands, st.at_rest && st.bulk_height_loss <= 0.1 && st.lost_fraction <= 0.1, `${where}: ${JSON.stringify(st)}`);
  assert.equal(Number(await page.$eval('[data-figure="fs_bulk_height_loss"] .value', (e) => e.textContent)),
    Number(st.bulk_height_loss.toPrecision(3)), `${where}: the bulk height loss`);
  assert.match(await page.$eval('[data-figure="fs_escaped_grains"] .value', (e) => e.textContent),
    new RegExp(`^${st.escaped_grains} of ${st.grains} \\(`), `${where}: the grains lost`);
  const profile = plots['plot-fs-profile'];
  const present = ['profile_before', 'profile_settled', 'profile_at_peak', 'profile_at_end'].filter((k) => test.profiles[k]);
  assert.deepEqual(profile.profiles, present, `${where}: one curve per profile`);
  assert.ok(present.includes('profile_settled') && present.includes('profile_at_peak'), `${where}: settled and at failure`);
  present.forEach((k, i) => {
    assertSameNumbers(profile.series[i].x, test.profiles[k].height_m.map((h) => h * 1000), `${where}: ${k} heights`);
    assertSameNumbers(profile.series[i].y, test.profiles[k].radius_m.map((r) => r * 1000), `${where}: ${k} radii`);
  });
  const wire = plots['plot-fs-wire'];
  assert.equal(wire.segments, test.wire_at_peak.tension_n.length, `${where}: every segment's tension`);
  assert.equal(wire.segments, summary.specimen.wire_nodes - 1, `${where}: the whole wire`);
  assertSameNumbers(wire.series[0].y, test.wire_at_peak.tension_n.map((t) => t * 1000), `${where}: the tensions as stored, in mN`);
}

/// Two lists of numbers equal element by element (=== : 0 and −0 alike).
function assertSameNumbers(a, b, what) {
  assert.equal(a.length, b.length, `${what}: length`);
  a.forEach((v, i) => assert.ok(v === b[i], `${what}: [${i}] ${v} against ${b[i]}`));
}

/// The flagged fit where a page shows it: every caveat of summary.json's
/// fits in #fit-caveats, φ, c and R² marked, the constrained fits shown, and
/// the caveats among the warnings. (The test job has two pressures, so its
/// fits always have the caveat two_pressures, and no R².)
async function checkFlaggedFit(page, where) {
  const mc = summary.mohr_coulomb;
  assert.ok(mc.caveats.some((c) => c.code === 'two_pressures'), `${where}: two pressures are flagged: ${JSON.stringify(mc.caveats)}`);
  assert.equal(mc.r_squared, null, 'no R² through two circles');
  const shown = await page.$$eval('#fit-caveats li', (li) => li.map((e) => ({ code: e.dataset.code, text: e.textContent })));
  const expected = [...mc.caveats, ...summary.mohr_coulomb_max_q.caveats];
  assert.equal(shown.length, expected.length, `${where}: every caveat is shown`);
  for (const [i, c] of expected.entries()) {
    assert.equal(shown[i].code, c.code);
    assert.ok(shown[i].text.endsWith(c.message), `${where}: ${shown[i].text}`);
    assert.ok(summary.warnings.some((w) => w.endsWith(c.message)), `the warnings hold ${c.message}`);
  }
  for (const key of ['friction_angle_deg', 'cohesion_pa', 'r_squared']) {
    const tile = await page.$eval(`[data-figure="${key}"]`, (e) => ({ flagged: e.classList.contains('flagged'), label: e.querySelector('.label').textContent, caveats: e.dataset.caveats }));
    assert.ok(tile.flagged && tile.label.endsWith('⚠'), `${where}: ${key} is marked: ${JSON.stringify(tile)}`);
    assert.equal(tile.caveats, mc.caveats.map((c) => c.code).join(' '));
  }
  assert.equal(await page.$eval('[data-figure="r_squared"] .value', (e) => e.textContent), '—');
  const nn = await page.$eval('[data-figure="nonnegative"] .value', (e) => e.textContent);
  const [phi, c] = nn.split(', ');
  assertShown(phi.replace('°', ''), mc.nonnegative.friction_angle_deg, `${where}: φ with c ≥ 0`);
  assertShown(c.replace(' kPa', ''), mc.nonnegative.cohesion_pa / 1000 || 0, `${where}: c with c ≥ 0`);
  assert.ok(mc.nonnegative.cohesion_pa >= 0 && mc.nonnegative.friction_angle_deg >= 0, JSON.stringify(mc.nonnegative));
  assertShown(await page.$eval('[data-figure="cohesionless_friction_angle_deg"] .value', (e) => e.textContent), mc.cohesionless.friction_angle_deg, `${where}: φ with c = 0`);
}

/// The Mohr plot's τ axis shows a negative intercept, and the constrained fits are drawn when they differ.
function checkMohrAxis(mohr, where) {
  const mc = summary.mohr_coulomb;
  assert.equal(mohr.envelope.flagged, mc.caveats.length > 0);
  if (mc.cohesion_pa < 0) assert.ok(mohr.yMin < mc.cohesion_pa / 1000, `${where}: the τ axis starts at ${mohr.yMin}, below c = ${mc.cohesion_pa / 1000} kPa`);
  else assert.ok(mohr.yMin <= 0, where);
  const differs = mc.nonnegative.cohesion_pa !== mc.cohesion_pa || mc.nonnegative.friction_angle_deg !== mc.friction_angle_deg;
  assert.equal(mohr.constrained.includes('nonnegative'), differs, `${where}: the c ≥ 0 fit is drawn when it differs`);
  const nnLine = mohr.series.find((s) => s.label.startsWith('fit with c ≥ 0'));
  if (nnLine) assert.ok(Math.abs(nnLine.y[0] - mc.nonnegative.cohesion_pa / 1000) < 1e-9 * Math.max(...nnLine.y.map(Math.abs)));
}

/// In the page: what the PNG screenshots `a` (and `b`, of the same size)
/// show, from their pixels. A pixel is background when it is within 24 (sum
/// of |Δ| over r, g, b) of the corner pixel. For each image: `notBackground`,
/// the fraction of other pixels; `height` and `width`, the share of the
/// image that they span; `strainColoured`, the pixels in the wire's strain
/// colours (view3d.js's strainColour: red (1, 1 − t, 1 − t) or blue
/// (1 + t, 1 + t, 1), so g = b below r, or r = g below b), which neither the
/// grains' sand (r > g > b), the slate force chains nor the grey background
/// has. With `b`: `changed`, the fraction of pixels that differ between them.
async function pixelStats(a, b) {
  const decode = async (png) => {
    const img = new Image();
    img.src = `data:image/png;base64,${png}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    return { w: c.width, h: c.height, d: ctx.getImageData(0, 0, c.width, c.height).data };
  };
  const differ = (d, i, e, j) => Math.abs(d[i] - e[j]) + Math.abs(d[i + 1] - e[j + 1]) + Math.abs(d[i + 2] - e[j + 2]) > 24;
  const stats = ({ w, h, d }) => {
    let n = 0, wire = 0, top = h, bottom = -1, left = w, right = -1;
    for (let y = 0; y < h; ++y)
      for (let x = 0; x < w; ++x) {
        const i = 4 * (y * w + x);
        const [r, g, bl] = [d[i], d[i + 1], d[i + 2]];
        if ((Math.abs(g - bl) <= 6 && r - g >= 40) || (Math.abs(r - g) <= 6 && bl - r >= 40)) ++wire;
        if (!differ(d, i, d, 0)) continue;
        ++n;
        top = Math.min(top, y); bottom = Math.max(bottom, y); left = Math.min(left, x); right = Math.max(right, x);
      }
    return { notBackground: n / (w * h), strainColoured: wire,
      height: bottom < 0 ? 0 : (bottom - top + 1) / h, width: right < 0 ? 0 : (right - left + 1) / w };
  };
  const p = await decode(a);
  const out = stats(p);
  if (b) {
    const q = await decode(b);
    let n = 0;
    for (let i = 0; i < p.d.length; i += 4) if (differ(p.d, i, q.d, i)) ++n;
    out.changed = n / (p.w * p.h);
    out.b = stats(q);
  }
  return out;
}

test('submit: a form from the job spec\'s schema; an invalid spec shows each error next to its field; a valid one creates a job, which the job page cancels', async () => {
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/submit`);
  await page.waitForSelector('tr[data-field="specimen.wire.pattern"] select');
  // The form has a row for every field of the job spec's schema, and edits the JSON.
  const schema = (await server.api('GET', '/v1/job-spec/schema')).json;
  // An object-or-null field with fields of its own (a grain-size curve, a grain shape) is a row and its fields' rows.
  const countLeaves = (s) => Object.values(s.properties).reduce((n, f) => n + (f.type === 'object' ? countLeaves(f)
    : Array.isArray(f.type) && f.type.includes('object') ? 1 + countLeaves(f) : 1), 0);
  assert.equal(await page.$$eval('#spec-fields tbody tr', (rows) => rows.length), countLeaves(schema));
  // Each row shows the field's unit and meaning, as the schema gives them.
  const radius = schema.properties.specimen.properties.membrane_radius_m;
  assert.equal(await page.$eval('tr[data-field="specimen.membrane_radius_m"] td.unit', (e) => e.textContent), radius['x-unit']);
  assert.equal(await page.$eval('tr[data-field="specimen.membrane_radius_m"] td.meaning', (e) => e.textContent), radius.description);
  assert.ok(radius['x-unit'] === 'm' && radius.description.length > 10, JSON.stringify(radius));
  await page.select('tr[data-field="specimen.wire.pattern"] select', 'radial_helix');
  const edited = JSON.parse(await page.$eval('#spec-editor', (e) => e.value));
  assert.equal(edited.specimen.wire.pattern, 'radial_helix');
  assert.equal(edited.specimen.grain_count, 150, 'the rest of the JSON is kept');
  const bad = { name: 'bad', seed: -1, specimen: { grain_count: 0 } };
  const setSpec = (text) => page.$eval('#spec-editor', (e, t) => { e.value = t; e.dispatchEvent(new Event('change')); }, text);
  await setSpec(JSON.stringify(bad, null, 2));
  w.expect(400, '/v1/jobs');
  await page.click('#submit-button');
  await page.waitForSelector('tr[data-field="seed"] .field-error div');
  const api = (await server.api('POST', '/v1/jobs', { body: JSON.stringify(bad) })).json.error;
  assert.ok(api.details.length >= 2, JSON.stringify(api));
  for (const d of api.details) {
    const shown = await page.$eval(`tr[data-field="${d.field}"] .field-error`, (e) => e.textContent);
    assert.ok(shown.includes(d.message), `${d.field}: shows '${shown}', the API says '${d.message}'`);
  }
  await shot(page, 'web-submit.png', { fullPage: true });
  // The field table is no wider than the window, at the test's width and a narrower one.
  for (const width of [1400, 1000]) {
    await page.setViewport({ width, height: 1000 });
    await sleep(200);
    const fits = await page.evaluate(() => ({ page: document.documentElement.scrollWidth, window: window.innerWidth,
      table: document.querySelector('#spec-fields').getBoundingClientRect().right }));
    assert.ok(fits.page <= fits.window && fits.table <= fits.window, `at ${width} px: ${JSON.stringify(fits)}`);
  }
  await page.setViewport({ width: 1400, height: 1000 });

  const good = { ...JSON.parse(readFileSync(path.join(sourceDir, 'tests/web/job.json'), 'utf8')), name: 'submitted from the page' };
  await setSpec(JSON.stringify(good));
  await page.click('#submit-button');
  await page.waitForFunction(() => /^#\/jobs\/[0-9a-f]{24}$/.test(location.hash));
  const id = (await page.evaluate(() => location.hash)).split('/')[2];
  const created = await server.api('GET', `/v1/jobs/${id}`);
  assert.equal(created.status, 200);
  assert.equal(created.json.name, 'submitted from the page');
  await page.waitForSelector('#cancel-job');
  await page.click('#cancel-job');
  await page.waitForFunction(() => document.querySelector('#job-state')?.textContent === 'cancelled');
  assert.equal((await server.waitFor(id, ['cancelled'], 10000)).state, 'cancelled');
  assert.deepEqual(w.problems, []);
  await page.close();
});

test('compare: the φ/c table and the overlaid envelopes and curves', async () => {
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/compare/${mainId}`);
  await page.waitForSelector('#compare-q');
  const phi = await page.$eval(`#compare-table tr[data-id="${mainId}"] td[data-key="friction_angle_deg"]`, (e) => ({ text: e.textContent, title: e.title }));
  // A flagged fit is marked, its caveats in the cell's title.
  assertShown(phi.text.replace(' ⚠', ''), summary.mohr_coulomb.friction_angle_deg, 'φ');
  assert.ok(phi.text.endsWith(' ⚠') && phi.title.includes(summary.mohr_coulomb.caveats[0].message), JSON.stringify(phi));
  const plots = await page.evaluate(() => ({ env: document.querySelector('#compare-envelopes').wiredemPlot, q: document.querySelector('#compare-q').wiredemPlot }));
  assert.equal(plots.env.series.length, 1);
  assert.equal(plots.q.series.length, summary.tests.length);
  await checkCompareLegend(page, [mainId]);
  assert.deepEqual(w.problems, []);
  await page.close();
});

/// The compare page's q curves: one colour per job, one dash per confining
/// pressure (the same in every job), both in the legend's swatches; the
/// chooser names each job with its id and time, so two jobs of one name differ.
async function checkCompareLegend(page, ids) {
  const q = await page.$eval('#compare-q', (e) => e.wiredemPlot);
  const swatches = await page.$$eval('#compare-q .swatches li', (li) => li.map((e) => ({ dash: e.dataset.dash, text: e.textContent,
    stroke: e.querySelector('line').getAttribute('stroke'), dasharray: e.querySelector('line').getAttribute('stroke-dasharray') })));
  assert.equal(swatches.length, q.series.length, 'a swatch per curve');
  const pressureOf = (label) => label.match(/σ₃ = ([0-9.]+) kPa/)[1];
  for (const [i, s] of swatches.entries()) {
    assert.equal(s.stroke, q.legend[i].color);
    assert.equal(s.dasharray ?? '', q.legend[i].dash.join(' '));
    for (const [j, o] of swatches.entries()) {
      const samePressure = pressureOf(q.legend[i].label) === pressureOf(q.legend[j].label);
      const sameJob = q.legend[i].label.split(', σ₃')[0] === q.legend[j].label.split(', σ₃')[0];
      assert.equal(s.dash === o.dash, samePressure, `dash: ${s.text} / ${o.text}`);
      assert.equal(s.stroke === o.stroke, sameJob, `colour: ${s.text} / ${o.text}`);
    }
  }
  const picks = await page.$$eval('label.pick', (l) => l.map((e) => ({ id: e.querySelector('input').value, text: e.textContent })));
  for (const p of picks) assert.ok(p.text.includes(p.id.slice(0, 8)) && /\d\d:\d\d/.test(p.text), `the chooser names ${p.id}: ${p.text}`);
  assert.equal(new Set(picks.map((p) => p.text)).size, picks.length, 'no two jobs look alike in the chooser');
  for (const id of ids) assert.ok(swatches.some((s) => s.text.includes(id.slice(0, 8))), `the legend names ${id}`);
}

test('studies: the list, a study\'s points with their jobs and the summary over the seeds, links to each job, the compare view pre-filled, cancel', async () => {
  // Two seeds of the test job made cheap (no wire, a faster pour, loaded to 3 %; seconds each):
  // a group whose φ and c have a mean and an sd.
  const base = JSON.parse(readFileSync(path.join(sourceDir, 'tests/web/job.json'), 'utf8'));
  base.specimen = { ...base.specimen, wire: { pattern: 'none' }, pouring: { ...base.specimen.pouring, fill_rate_m_per_s: 0.25 } };
  base.triaxial = { ...base.triaxial, target_axial_strain: 0.03, snapshot_strains: [0.03] };
  const study = await server.api('POST', '/v1/studies', { body: JSON.stringify({ name: 'web study', base, points: [{ seed: 1 }, { seed: 2 }] }) });
  assert.equal(study.status, 201, JSON.stringify(study.json));
  const doomed = await server.api('POST', '/v1/studies', { body: JSON.stringify({ name: 'web study to cancel', base, points: [{ seed: 3 }] }) });
  assert.equal(doomed.status, 201, JSON.stringify(doomed.json));
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/studies`);
  await page.waitForSelector(`#studies tr[data-id="${study.json.id}"]`);
  await page.waitForSelector(`#studies tr[data-id="${doomed.json.id}"]`);

  // Cancel: the study queued behind the first one.
  await page.click(`#studies tr[data-id="${doomed.json.id}"] a`);
  await page.waitForSelector('#cancel-study');
  await page.click('#cancel-study');
  await page.waitForSelector('#study-points tr[data-index="0"][data-state="cancelled"]');
  assert.equal((await server.api('GET', `/v1/studies/${doomed.json.id}`)).json.jobs_by_state.cancelled, 1);

  // The study's page follows its jobs until both have succeeded.
  await page.goto(`${server.url}/#/studies/${study.json.id}`);
  // The page must be this study's (the cancelled one's table may still be shown right after the
  // navigation, or none yet: every() of no rows is true) with both rows succeeded.
  await page.waitForFunction((name) => {
    const rows = [...document.querySelectorAll('#study-points tbody tr')];
    return document.querySelector('#study-name')?.textContent === name && rows.length === 2
      && rows.every((r) => r.dataset.state === 'succeeded');
  }, { timeout: 420000, polling: 500 }, 'web study');
  const summary = (await server.api('GET', `/v1/studies/${study.json.id}/summary`)).json;
  assert.equal(summary.points.length, 2);
  for (const p of summary.points) {
    const row = `#study-points tr[data-index="${p.index}"]`;
    // Two pressures: every point's fit is flagged.
    assert.ok(p.fit_caveats.includes('two_pressures'), JSON.stringify(p.fit_caveats));
    for (const [key, value] of [['friction_angle_deg', p.friction_angle_deg], ['cohesion_pa', p.cohesion_pa / 1000]]) {
      const cell = await page.$eval(`${row} td[data-key="${key}"]`, (e) => ({ text: e.textContent, caveats: e.dataset.caveats }));
      assert.ok(cell.text.endsWith(' ⚠'), `${key} of point ${p.index} is marked: ${cell.text}`);
      assert.equal(cell.caveats, p.fit_caveats.join(' '));
      assertShown(cell.text.replace(' ⚠', ''), value, `${key} of point ${p.index}`);
    }
    assert.equal(await page.$eval(`${row} td.name a`, (a) => a.getAttribute('href')), `#/jobs/${p.job_id}`);
  }
  // The group over the seeds: mean ± sd (n), as the summary computed them.
  const g = summary.groups[0].friction_angle_deg;
  assert.equal(g.n, 2);
  const [mean, rest] = (await page.$eval('#study-groups tr[data-group="0"] td[data-key="friction_angle_deg"]', (e) => e.textContent)).split(' ± ');
  assertShown(mean, g.mean, 'mean φ');
  const [sd, n] = rest.split(' ');
  assert.ok(Math.abs(Number(sd) - g.sd) <= 5e-3 * g.sd + 1e-12, `sd φ: page ${sd}, summary ${g.sd}`);
  assert.equal(n, '(2)');
  await shot(page, 'web-study.png', { fullPage: true });

  // Compare, pre-filled with the study's succeeded jobs.
  await page.click('#study-compare');
  await page.waitForSelector('#compare-q');
  const compared = await page.$$eval('#compare-table tbody tr', (rows) => rows.map((r) => r.dataset.id));
  assert.deepEqual(compared.sort(), summary.points.map((p) => p.job_id).sort());
  await checkCompareLegend(page, compared);
  await shot(page, 'web-compare.png', { fullPage: true });
  assert.deepEqual(w.problems, []);
  await page.close();
});

test('offline report: wiredem report OUT/ writes one page with the same figures and plots, which opens without a server', async () => {
  const out = mkdtempSync(path.join(tmp, 'report-'));
  for (const [route, file] of [['summary', 'summary.json'], ['result.h5', 'result.h5']]) {
    const res = await fetch(`${server.url}/v1/jobs/${mainId}/${route}`);
    assert.equal(res.status, 200);
    writeFileSync(path.join(out, file), Buffer.from(await res.arrayBuffer()));
  }
  const client = path.join(path.dirname(serverBin), 'wiredem');
  const run = spawn(client, ['report', out], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  run.stderr.on('data', (d) => { stderr += d; });
  assert.equal(await new Promise((resolve) => run.on('exit', resolve)), 0, stderr);
  const { page, w } = await newPage();
  await page.goto(`file://${path.join(out, 'report.html')}`);
  await page.waitForSelector('#main[data-rendered="true"]');
  assert.equal(await page.$eval('#job-name', (e) => e.textContent), summary.name ?? (await server.api('GET', `/v1/jobs/${mainId}`)).json.name);
  assertShown(await page.$eval('[data-figure="friction_angle_deg"] .value', (e) => e.textContent), summary.mohr_coulomb.friction_angle_deg, 'φ');
  assert.equal(await page.$eval('[data-figure="cell"] .value', (e) => e.textContent), 'membrane (flexible, pressurised)', 'offline report: the triaxial cell');
  await checkFlaggedFit(page, 'offline report');
  const plots = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('.plot')].map((p) => [p.id, p.wiredemPlot])));
  checkMohrAxis(plots['plot-mohr'], 'offline report');
  for (const id of ['plot-q', 'plot-ratio', 'plot-volumetric']) assert.equal(plots[id].series.length, summary.tests.length, id);
  const env = plots['plot-mohr'].series.find((s) => s.label.startsWith('envelope'));
  const tanPhi = Math.tan((summary.mohr_coulomb.friction_angle_deg * Math.PI) / 180);
  const expected = summary.mohr_coulomb.cohesion_pa / 1000 + env.x[0] * tanPhi;
  assert.ok(Math.abs(env.y[0] - expected) < 1e-9 * Math.max(...env.y.map(Math.abs)), `envelope at σ = ${env.x[0]}: ${env.y[0]}, expected ${expected}`);
  assert.equal(plots['plot-autocorrelation'].first_maximum_lag_m, summary.wire.autocorrelation_lag_m);
  assert.equal(plots['plot-autocorrelation'].prominent_maximum_lag_m, summary.wire.autocorrelation_prominent_lag_m);
  await checkFreeStanding(page, plots, 'offline report');
  assert.equal(w.requests.filter((r) => !r.url.startsWith('file:')).length, 0, 'the report fetches nothing');
  // The server offers the same report (the job page's download button).
  const served = await fetch(`${server.url}/v1/jobs/${mainId}/report.html`);
  assert.equal(served.status, 200);
  assert.equal(served.headers.get('content-disposition'), 'attachment; filename="report.html"');
  const servedText = await served.text();
  const fileText = readFileSync(path.join(out, 'report.html'), 'utf8');
  const dataOf = (html) => JSON.parse(html.match(/id="report-data">(.*?)<\/script>/s)[1]);
  const [a, b] = [dataOf(servedText), dataOf(fileText)];
  delete a.source; delete b.source;
  assert.deepEqual(a, b, 'the served report holds the same data as wiredem report');
  await shot(page, 'web-report.png', { fullPage: true });
  assert.deepEqual(w.problems, []);
  await page.close();

  // A fit with a negative c: the main job's tests and fits, as the engine
  // wrote them at a step of 15.38 µs (tests/web/summary-negative-cohesion.json,
  // docs/figures/main-summary.json until the springs' packing step made
  // that job's fit c = 0.3 kPa), in this job's summary (the Mohr plot reads
  // the summary alone). The τ axis goes below c, the c ≥ 0 fit is drawn,
  // the caveat is said.
  const negative = mkdtempSync(path.join(tmp, 'report-negative-'));
  const mainSummary = JSON.parse(readFileSync(path.join(sourceDir, 'tests/web/summary-negative-cohesion.json'), 'utf8'));
  const mainFit = mainSummary.mohr_coulomb;
  assert.ok(mainFit.cohesion_pa < 0 && mainFit.caveats.some((c) => c.code === 'negative_cohesion'), JSON.stringify(mainFit));
  writeFileSync(path.join(negative, 'summary.json'), JSON.stringify({ ...summary, tests: mainSummary.tests, mohr_coulomb: mainFit,
    mohr_coulomb_max_q: mainSummary.mohr_coulomb_max_q, warnings: mainSummary.warnings }));
  writeFileSync(path.join(negative, 'result.h5'), readFileSync(path.join(out, 'result.h5')));
  const again = spawn(client, ['report', negative], { stdio: ['ignore', 'pipe', 'pipe'] });
  assert.equal(await new Promise((resolve) => again.on('exit', resolve)), 0);
  const { page: neg, w: negWatch } = await newPage();
  await neg.goto(`file://${path.join(negative, 'report.html')}`);
  await neg.waitForSelector('#main[data-rendered="true"]');
  const mohr = await neg.$eval('#plot-mohr', (e) => e.wiredemPlot);
  assert.ok(mohr.yMin < mainFit.cohesion_pa / 1000, `the τ axis starts at ${mohr.yMin} kPa, below c = ${mainFit.cohesion_pa / 1000} kPa`);
  assert.ok(await neg.$eval('#plot-mohr', (e) => e.uplot.scales.y.min) < mainFit.cohesion_pa / 1000, 'and uPlot drew it so');
  assert.ok(mohr.constrained.includes('nonnegative'), JSON.stringify(mohr.constrained));
  const nnLine = mohr.series.find((x) => x.label.startsWith('fit with c ≥ 0'));
  assert.equal(nnLine.y[0], 0, 'the c ≥ 0 fit of a negative free c is on the bound c = 0');
  assert.ok(mohr.series.find((x) => x.label.startsWith('envelope')).label.endsWith('(unconstrained ⚠)'));
  assert.ok((await neg.$eval('#fit-caveats li[data-code="negative_cohesion"]', (e) => e.textContent)).includes('negative cohesion'));
  assert.ok(await neg.$eval('[data-figure="cohesion_pa"]', (e) => e.classList.contains('flagged')));
  if (screenshots) {
    const box = await neg.$('#plot-mohr');
    await box.scrollIntoView();
    await box.screenshot({ path: path.join(screenshots, 'web-mohr-negative.png') });
  }
  assert.deepEqual(negWatch.problems, []);
  await neg.close();
});

/// The clump job the form builds (examples/tiny-clumps.json, smaller: 60
/// grains at one pressure, a few seconds), without the fields the form sets.
function clumpJobBase() {
  const job = JSON.parse(readFileSync(path.join(sourceDir, 'examples/tiny-clumps.json'), 'utf8'));
  delete job.comment;
  delete job.specimen.grain_shape;
  job.name = 'web test: clumps from the form';
  Object.assign(job.specimen, { grain_count: 60, membrane_height_m: 0.025 });
  Object.assign(job.triaxial, { confining_pressures_pa: [20000], target_axial_strain: 0.04, snapshot_strains: [0, 0.04] });
  return job;
}

test('submit: the grain-size curve, grain shape, rolling resistance and wire-break fields edit the spec, show the door\'s errors next to them, and submit a clump job, whose 3D view draws every sphere coloured by its clump', async () => {
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/submit`);
  await page.waitForSelector('tr[data-field="specimen.grain_shape.template"] select');
  const schema = (await server.api('GET', '/v1/job-spec/schema')).json;
  const field = (p) => p.split('.').reduce((f, k) => f.properties[k], schema);
  // The groups and their fields, each with the schema's meaning and, for numbers, unit.
  for (const group of ['specimen.grain_sizes', 'specimen.grain_shape'])
    assert.equal(await page.$eval(`tr.group[data-field="${group}"] td.meaning`, (e) => e.textContent), field(group).description);
  for (const p of ['specimen.grain_sizes.basis', 'specimen.grain_sizes.diameters_m', 'specimen.grain_sizes.fraction_passing',
    'specimen.grain_shape.template', 'specimen.grain_shape.spheres', 'contact.rolling_friction_coeff', 'contact.rolling_stiffness_factor',
    'contact.rolling_damping_ratio', 'specimen.wire.breaking_strain', 'specimen.wire.cuts_at_m', 'specimen.wire.cut_every_loops']) {
    const row = await page.$eval(`tr[data-field="${p}"]`, (r) => ({ meaning: r.querySelector('td.meaning').textContent,
      unit: r.querySelector('td.unit').textContent, allowed: r.querySelector('td.muted').textContent }));
    assert.equal(row.meaning, field(p).description, p);
    assert.equal(row.unit, field(p)['x-unit'] ?? '', p);
    assert.ok(row.allowed.length > 0, `${p} says what it allows`);
  }
  assert.equal(await page.$eval('tr[data-field="specimen.grain_sizes.diameters_m"] td.muted', (e) => e.textContent), '2–64 numbers in [0.00002, 0.2], increasing');
  assert.equal(await page.$eval('tr[data-field="specimen.grain_sizes.fraction_passing"] td.muted', (e) => e.textContent), '2–64 numbers in [0, 1], nondecreasing');
  assert.equal(await page.$eval('tr[data-field="specimen.grain_shape.spheres"] td.muted', (e) => e.textContent), '2–32 entries of 4 numbers');
  assert.equal(await page.$eval('tr[data-field="specimen.grain_shape"] td.muted', (e) => e.textContent), 'one of template, spheres, or null');

  const setSpec = (text) => page.$eval('#spec-editor', (e, t) => { e.value = t; e.dispatchEvent(new Event('change')); }, text);
  const spec = () => page.$eval('#spec-editor', (e) => JSON.parse(e.value));
  const type = (p, text) => page.$eval(`[data-path="${p}"]`, (e, t) => { e.value = t; e.dispatchEvent(new Event('change')); }, text);
  const valueOf = (p) => page.$eval(`[data-path="${p}"]`, (e) => e.value);
  const base = clumpJobBase();
  await setSpec(JSON.stringify(base, null, 2));
  assert.equal(await page.$eval('.group-state[data-group="specimen.grain_shape"]', (e) => e.textContent), 'null (the default)');

  // A shape is a template or spheres: giving one drops the other.
  const spheres = [[0, 0, 0, 1], [1.2, 0, 0, 0.8]];
  await page.select('[data-path="specimen.grain_shape.template"]', 'crushed');
  assert.deepEqual((await spec()).specimen.grain_shape, { template: 'crushed' });
  assert.equal(await page.$eval('.group-state[data-group="specimen.grain_shape"]', (e) => e.textContent), 'given');
  await type('specimen.grain_shape.spheres', JSON.stringify(spheres));
  assert.deepEqual((await spec()).specimen.grain_shape, { spheres });
  assert.equal(await valueOf('specimen.grain_shape.template'), '', 'the template was dropped');
  // "leave out" makes it null (absent) again.
  await page.click('.group-clear[data-group="specimen.grain_shape"]');
  assert.equal((await spec()).specimen.grain_shape, undefined);
  assert.equal(await valueOf('specimen.grain_shape.spheres'), '');

  // Bad values through the form: each of the door's messages next to its field (a sphere's radius: the spheres' row).
  await type('specimen.grain_shape.spheres', JSON.stringify([[0, 0, 0, 1], [1.2, 0, 0, -0.8]]));
  await type('specimen.grain_sizes.diameters_m', '[0.0015, 0.002, 0.0025]');
  await type('specimen.grain_sizes.fraction_passing', '[0, 0.7, 0.5]');
  await page.select('[data-path="specimen.grain_sizes.basis"]', 'number');
  await type('contact.rolling_friction_coeff', '2');
  await type('contact.rolling_damping_ratio', '0.05');
  await type('specimen.wire.breaking_strain', '0');
  await type('specimen.wire.cuts_at_m', '[0.02, 0.01]');
  const bad = await spec();
  assert.deepEqual(bad.specimen.grain_sizes, { diameters_m: [0.0015, 0.002, 0.0025], fraction_passing: [0, 0.7, 0.5], basis: 'number' });
  assert.equal(bad.contact.rolling_friction_coeff, 2);
  assert.equal(bad.specimen.wire.breaking_strain, 0);
  w.expect(400, '/v1/jobs');
  await page.click('#submit-button');
  await page.waitForSelector('tr[data-field="contact.rolling_friction_coeff"] .field-error div');
  const api = (await server.api('POST', '/v1/jobs', { body: JSON.stringify(bad) })).json.error;
  const fields = api.details.map((d) => d.field);
  for (const f of ['contact.rolling_friction_coeff', 'specimen.grain_sizes.fraction_passing[2]', 'specimen.grain_shape.spheres[1][3]',
    'specimen.wire.breaking_strain', 'specimen.wire.cuts_at_m[1]'])
    assert.ok(fields.includes(f), `the door names ${f}: ${JSON.stringify(api.details)}`);
  for (const d of api.details) {
    const row = d.field.replace(/(\[\d+\])+$/, '');
    const shown = await page.$eval(`tr[data-field="${row}"] .field-error`, (e) => e.textContent);
    assert.ok(shown.includes(d.message), `${d.field}: shows '${shown}', the door says '${d.message}'`);
  }
  assert.equal(await page.$$eval('#submit-error li', (li) => li.length), 0, 'every problem is next to its field');
  if (screenshots) {  // the rows of the two groups, with their errors
    const clip = await page.evaluate(() => {
      const top = document.querySelector('tr[data-field="specimen.grain_sizes"]').getBoundingClientRect();
      const bottom = document.querySelector('tr[data-field="specimen.grain_shape.spheres"]').getBoundingClientRect();
      return { x: top.left + window.scrollX, y: top.top + window.scrollY, width: top.width, height: bottom.bottom - top.top };
    });
    await page.screenshot({ path: path.join(screenshots, 'web-submit-grains.png'), clip, captureBeyondViewport: true });
  }

  // Fixed in the form, the spec is the clump job with what the form set, and the door takes it.
  await type('specimen.grain_sizes.fraction_passing', '[0, 0.5, 1]');
  await page.select('[data-path="specimen.grain_shape.template"]', 'crushed');
  await type('contact.rolling_friction_coeff', '0.1');
  await type('specimen.wire.breaking_strain', '');
  await type('specimen.wire.cuts_at_m', '');
  const good = await spec();
  assert.deepEqual(good, { ...base, specimen: { ...base.specimen, wire: { pattern: 'none' }, grain_shape: { template: 'crushed' },
    grain_sizes: { diameters_m: [0.0015, 0.002, 0.0025], fraction_passing: [0, 0.5, 1], basis: 'number' } },
    contact: { rolling_friction_coeff: 0.1, rolling_damping_ratio: 0.05 } });
  await page.click('#submit-button');
  await page.waitForFunction(() => /^#\/jobs\/[0-9a-f]{24}$/.test(location.hash));
  const id = (await page.evaluate(() => location.hash)).split('/')[2];
  const job = await server.waitFor(id, ['succeeded', 'failed', 'cancelled']);
  assert.equal(job.state, 'succeeded', server.log());
  const stored = (await server.api('GET', `/v1/jobs/${id}`)).json.spec;
  assert.deepEqual(stored.specimen.grain_shape, { template: 'crushed' });
  assert.deepEqual(stored.specimen.grain_sizes, { basis: 'number', diameters_m: [0.0015, 0.002, 0.0025], fraction_passing: [0, 0.5, 1] });
  assert.equal(stored.contact.rolling_friction_coeff, 0.1);

  // The 3D view: every sphere of every clump, coloured by its clump, as the specimen's grain_clump says.
  await page.waitForFunction(() => document.querySelector('#view3d-canvas')?.wiredemView, { timeout: 60000 });
  // And the sizes drawn against the curve's (summary.specimen.grain_sizes).
  const sizes = (await server.api('GET', `/v1/jobs/${id}/summary`)).json.specimen.grain_sizes;
  for (const key of ['d10_m', 'd50_m', 'd60_m', 'uniformity_coefficient'])
    for (const which of ['requested', 'drawn'])
      assertShown(await page.$eval(`#grain-sizes-table tr[data-key="${key}"] td[data-which="${which}"]`, (e) => e.textContent),
        sizes[which][key] * (key.endsWith('_m') ? 1000 : 1), `${which} ${key}`);
  assert.match(await page.$eval('#grain-sizes-ks', (e) => e.textContent), new RegExp(`distance of the drawn sizes from the curve: ${Number(sizes.ks_distance.toPrecision(3))} `));
  const res = await fetch(`${server.url}/v1/jobs/${id}/specimen/grain_clump`);
  assert.equal(res.status, 200);
  const clumpOf = new Int32Array(await res.arrayBuffer());
  const jobSummary = (await server.api('GET', `/v1/jobs/${id}/summary`)).json;
  const clumps = new Set(clumpOf.filter((k) => k >= 0)).size;
  assert.equal(clumps, jobSummary.specimen.grains, 'a clump per grain');
  assert.equal(clumpOf.length, 5 * clumps, 'the crushed clump has five spheres');
  const checkView = async (what) => {
    const view = await page.$eval('#view3d-canvas', (c) => c.wiredemView);
    assert.equal(view.grains, clumpOf.length, `${what}: every sphere drawn`);
    assert.equal(view.clumps, clumps, what);
    assert.equal(view.clumpSpheres, clumpOf.length, what);
    const colours = await page.$eval('#view3d-canvas', (c, n) => Array.from({ length: n }, (_, i) => c.wiredemClumpColour(i)), clumpOf.length);
    const byClump = new Map();
    clumpOf.forEach((k, i) => byClump.set(k, [...(byClump.get(k) || []), colours[i]]));
    for (const [k, cs] of byClump) assert.equal(new Set(cs).size, 1, `${what}: the spheres of clump ${k} share a colour`);
    const distinct = new Set([...byClump.values()].map((cs) => cs[0])).size;
    assert.ok(distinct >= 0.9 * clumps, `${what}: ${distinct} colours for ${clumps} clumps`);
    assert.match(await page.$eval('#view3d-info', (e) => e.textContent), new RegExp(`^${clumps} clumps of ${clumpOf.length} spheres`));
  };
  await checkView('the prepared specimen');
  // A snapshot of the test: its positions, the specimen's clumps.
  const snap = (await server.api('GET', `/v1/jobs/${id}/tests`)).json.tests[0].snapshots.at(-1);
  const snapGroup = (await server.api('GET', snap.url)).json;
  assert.deepEqual(snapGroup.arrays.find((a) => a.name === 'grain_position_m').shape, [clumpOf.length, 3], 'a snapshot has every sphere');
  await page.$eval('#view3d-canvas', (c) => { c.wiredemView.stale = true; });
  await page.select('#view3d-source', '0');
  await page.waitForFunction(() => !document.querySelector('#view3d-canvas').wiredemView.stale);
  await checkView('the end of the test');
  await page.select('#view3d-grain-mode', 'solid');
  if (screenshots) {
    const canvas = await page.$('#view3d-canvas');
    await canvas.scrollIntoView();
    await canvas.screenshot({ path: path.join(screenshots, 'web-3d-clumps.png') });
  }
  assert.deepEqual(w.problems, []);
  await page.close();
});

/// The breaks of a breakable wire and the pieces of a cut one, as `page`
/// shows them, against summary.json: what failed at each test's peak, each
/// break listed and marked on its curve, the prepared wire's pieces.
async function checkWireParts(page, s, where) {
  const rows = s.tests.map((t) => [String(t.confining_pressure_pa), t]);
  if (s.free_standing) rows.push(['free_standing', s.free_standing.compression]);
  for (const [key, t] of rows) {
    const shown = await page.$eval(`#wire-failure-table tr[data-test="${key}"]`, (r) => ({
      failure: r.querySelector('[data-key="peak_failure"]').dataset.value, breaks: Number(r.querySelector('[data-key="breaks"]').textContent) }));
    assert.equal(shown.failure, t.peak_failure ?? '', `${where}: peak_failure of ${key}`);
    assert.equal(shown.breaks, (t.wire_breaks || []).length, `${where}: breaks of ${key}`);
  }
  const all = rows.flatMap(([key, t]) => (t.wire_breaks || []).map((b) => [key, b]));
  const listed = await page.$$eval('#wire-breaks-table tbody tr', (trs) => trs.map((r) => ({ test: r.dataset.test,
    ...Object.fromEntries([...r.querySelectorAll('[data-key]')].map((c) => [c.dataset.key, c.textContent])) })));
  assert.equal(listed.length, all.length, `${where}: every break listed`);
  all.forEach(([key, b], i) => {
    assert.equal(listed[i].test, key, where);
    assertShown(listed[i].time_s, b.time_s, `${where}: time of break ${i}`);
    assertShown(listed[i].axial_strain, b.axial_strain, `${where}: axial strain of break ${i}`);
    assertShown(listed[i].position_m, b.position_m * 1000, `${where}: position of break ${i} [mm]`);
    assert.equal(Number(listed[i].segment), b.segment, where);
  });
  const plots = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('.plot')].map((p) => [p.id, p.wiredemPlot])));
  assert.deepEqual(plots['plot-q'].breaks, s.tests.flatMap((t) => (t.wire_breaks || []).map((b) => b.axial_strain)), `${where}: breaks marked on q`);
  if (s.free_standing)
    assert.deepEqual(plots['plot-fs-stress'].breaks, (s.free_standing.compression.wire_breaks || []).map((b) => b.axial_strain), where);
  const pieces = s.specimen.wire_pieces;
  const shownPieces = await page.$$eval('#wire-pieces-table tbody tr', (trs) => trs.map((r) => ({
    rest: r.querySelector('[data-key="rest_length_m"]').textContent, length: r.querySelector('[data-key="length_m"]').textContent })));
  assert.equal(shownPieces.length, pieces.length, `${where}: every piece listed`);
  pieces.forEach((p, i) => {
    assertShown(shownPieces[i].rest, p.rest_length_m * 1000, `${where}: rest length of piece ${i}`);
    assertShown(shownPieces[i].length, p.length_m * 1000, `${where}: length of piece ${i}`);
  });
  assert.equal(await page.$eval('[data-figure="wire_cuts"] .value', (e) => e.textContent), String(s.specimen.wire_cuts), where);
}

test('a breakable wire cut every two loops: its breaks marked on the curves and listed, what failed at the peak, the pieces, on the job page and in the offline report', async () => {
  const job = await server.waitFor(breaksId, ['succeeded', 'failed', 'cancelled']);
  assert.equal(job.state, 'succeeded', server.log());
  const s = (await server.api('GET', `/v1/jobs/${breaksId}/summary`)).json;
  // The job is made to break its wire in the test and to be cut (job-breaks.json): else this test checks nothing.
  assert.ok(s.tests.some((t) => t.wire_breaks.length > 0), JSON.stringify(s.tests.map((t) => t.wire_breaks)));
  assert.ok(s.specimen.wire_cuts > 0 && s.specimen.wire_pieces.length > 1, JSON.stringify(s.specimen.wire_pieces));
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/jobs/${breaksId}`);
  await page.waitForSelector('#wire-parts');
  await page.waitForFunction(() => document.querySelector('#plot-fs-stress')?.wiredemPlot);
  await checkWireParts(page, s, 'job page');
  // The 3D view draws the wire as it was: the prepared pieces' segments, less
  // those the test broke by the snapshot shown (the end of the test: all of them).
  await page.waitForFunction(() => document.querySelector('#view3d-canvas')?.wiredemView, { timeout: 60000 });
  const inPieces = s.specimen.wire_pieces.reduce((n, p) => n + p.nodes - 1, 0);
  const brokeInTest = s.tests.at(-1).wire_breaks.length;
  assert.ok(inPieces < s.specimen.wire_nodes - 1, 'the cuts removed segments');
  assert.equal((await page.$eval('#view3d-canvas', (c) => c.wiredemView)).wireSegments, inPieces - brokeInTest, 'the end of the test');
  await page.$eval('#view3d-canvas', (c) => { c.wiredemView.stale = true; });
  await page.select('#view3d-source', 'specimen');
  await page.waitForFunction(() => !document.querySelector('#view3d-canvas').wiredemView.stale);
  assert.equal((await page.$eval('#view3d-canvas', (c) => c.wiredemView)).wireSegments, inPieces, 'the prepared specimen');
  if (screenshots) {
    const section = await page.$('#plot-q');
    await section.scrollIntoView();
    await section.screenshot({ path: path.join(screenshots, 'web-wire-breaks-q.png') });
    const parts = await page.$('#wire-parts');
    await parts.scrollIntoView();
    await parts.screenshot({ path: path.join(screenshots, 'web-wire-breaks.png') });
  }
  assert.deepEqual(w.problems, []);
  await page.close();

  const out = mkdtempSync(path.join(tmp, 'report-breaks-'));
  for (const [route, file] of [['summary', 'summary.json'], ['result.h5', 'result.h5']]) {
    const res = await fetch(`${server.url}/v1/jobs/${breaksId}/${route}`);
    assert.equal(res.status, 200);
    writeFileSync(path.join(out, file), Buffer.from(await res.arrayBuffer()));
  }
  const run = spawn(path.join(path.dirname(serverBin), 'wiredem'), ['report', out], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  run.stderr.on('data', (d) => { stderr += d; });
  assert.equal(await new Promise((resolve) => run.on('exit', resolve)), 0, stderr);
  const { page: report, w: reportWatch } = await newPage();
  await report.goto(`file://${path.join(out, 'report.html')}`);
  await report.waitForSelector('#main[data-rendered="true"]');
  await checkWireParts(report, s, 'offline report');
  assert.deepEqual(reportWatch.problems, []);
  await report.close();
});

/// The pull-out as `page` shows it, against summary.json's `po` and the
/// API's rows (GET …/free_standing's pull_out): a point per row, the pull
/// force and the end tension as stored, the pulled length in mm; the peak
/// drawn at its value (the largest row mean) and marked at its length; its tile.
async function checkPullOut(page, po, rows, where) {
  const plot = await page.$eval('#plot-fs-pull', (p) => p.wiredemPlot);
  const n = rows.pulled_length_m.values.length;
  assert.ok(n > 5, `${where}: the pull has rows (${n})`);
  assert.equal(plot.rows, n, where);
  assertSameNumbers(plot.series[0].x, rows.pulled_length_m.values.map((v) => v * 1000), `${where}: pulled lengths [mm]`);
  assertSameNumbers(plot.series[0].y, rows.pull_force_n.values, `${where}: pull forces`);
  assertSameNumbers(plot.series[1].y, rows.end_tension_n.values, `${where}: end tensions`);
  assert.equal(Math.max(0, ...rows.pull_force_n.values), po.peak_pull_force_n, `${where}: the peak is the largest row mean`);
  const peak = plot.series.find((x) => x.label.startsWith('peak'));
  assert.ok(peak && peak.y.every((v) => v === po.peak_pull_force_n), `${where}: the peak drawn at its value`);
  assert.deepEqual(plot.peak, { force_n: po.peak_pull_force_n, length_m: po.pulled_length_at_peak_m }, where);
  assert.equal(Number(await page.$eval('[data-figure="fs_peak_pull_force_n"] .value', (e) => e.textContent)),
    Number(po.peak_pull_force_n.toPrecision(4)), `${where}: the peak's tile`);
}

test('pull-out: the pull force against the pulled length, its peak marked, on the job page and in the offline report', async () => {
  const job = await server.waitFor(pullId, ['succeeded', 'failed', 'cancelled']);
  assert.equal(job.state, 'succeeded', server.log());
  const s = (await server.api('GET', `/v1/jobs/${pullId}/summary`)).json;
  const po = s.free_standing.pull_out;
  assert.ok(po && po.pulled_length_m > 0 && po.peak_pull_force_n > 0, JSON.stringify(s.free_standing));
  const rows = (await server.api('GET', `/v1/jobs/${pullId}/free_standing`)).json.pull_out;
  const { page, w } = await newPage();
  await page.goto(`${server.url}/#/jobs/${pullId}`);
  await page.waitForFunction(() => document.querySelector('#plot-fs-pull')?.wiredemPlot);
  await checkPullOut(page, po, rows, 'job page');
  if (screenshots) {
    const plot = await page.$('#plot-fs-pull');
    await plot.scrollIntoView();
    await plot.screenshot({ path: path.join(screenshots, 'web-pull-out.png') });
  }
  assert.deepEqual(w.problems, []);
  await page.close();

  const out = mkdtempSync(path.join(tmp, 'report-pull-'));
  for (const [route, file] of [['summary', 'summary.json'], ['result.h5', 'result.h5']]) {
    const res = await fetch(`${server.url}/v1/jobs/${pullId}/${route}`);
    assert.equal(res.status, 200);
    writeFileSync(path.join(out, file), Buffer.from(await res.arrayBuffer()));
  }
  const run = spawn(path.join(path.dirname(serverBin), 'wiredem'), ['report', out], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  run.stderr.on('data', (d) => { stderr += d; });
  assert.equal(await new Promise((resolve) => run.on('exit', resolve)), 0, stderr);
  const { page: report, w: reportWatch } = await newPage();
  await report.goto(`file://${path.join(out, 'report.html')}`);
  await report.waitForSelector('#main[data-rendered="true"]');
  await checkPullOut(report, po, rows, 'offline report');
  assert.deepEqual(reportWatch.problems, []);
  await report.close();
});

test('token: the page asks for it, sends it as a bearer header only, and the API refuses requests without it', async () => {
  const dir = mkdtempSync(path.join(tmp, 'token-'));
  const token = 'web-test-token-7f3a';
  writeFileSync(path.join(dir, 'token'), `${token}\n`);
  const guarded = await Server.start(dir, ['--token-file', path.join(dir, 'token')]);
  try {
    assert.equal((await guarded.api('GET', '/v1/jobs')).status, 401);
    const { page, w } = await newPage();
    w.expect(401, '/v1/jobs');
    await page.goto(`${guarded.url}/#/`);
    await page.waitForSelector('#token-dialog[open]');
    await page.type('#token-input', 'wrong');
    await page.click('#token-form button');
    await page.waitForFunction(() => document.querySelector('#token-error')?.textContent.includes('refused'));
    await page.type('#token-input', token);
    await page.click('#token-form button');
    await page.waitForFunction(() => document.querySelector('#jobs tbody td')?.textContent === 'No jobs.');
    assert.equal(await page.$('#token-dialog[open]'), null);
    const api = w.requests.filter((r) => r.url.includes('/v1/'));
    assert.ok(api.some((r) => r.headers.authorization === `Bearer ${token}`), 'the token goes in the Authorization header');
    assert.ok(w.requests.every((r) => !r.url.includes(token) && !r.url.includes('wrong')), 'never in a URL');
    assert.deepEqual(w.problems, []);
    await page.close();
  } finally {
    assert.equal(await guarded.stop(), 0);
  }
});
