// Browser test of hlodr's page (web/): Debian's headless Chromium, driven through playwright-core,
// against a real `hlodr serve` on a tiny city (or, with HLODR_WEB_URL, against a server that is
// already running). It orbits, zooms and walks and checks that the frame changes, that frames
// are asked one at a time (real-time while moving, one still frame at rest), shows an API error
// to the user, runs a 30-frame path job, checks that every chart got every frame, downloads the
// CSV, cancels a running job, picks a scene file (its effects and camera) for the view and a job,
// and fails on any console error or page error. Screenshots go to HLODR_WEB_SCREENSHOTS (default
// build/web-screenshots/).
//
// Exit 77 (ctest's skip) with a message when Chromium, node_modules or hlodr's serve command is
// missing.
//
// Environment: HLODR_BINARY (default build/hlodr), HLODR_CHROMIUM (default /usr/bin/chromium),
// HLODR_WEB_URL (use this server instead of starting one), HLODR_WEB_SCREENSHOTS,
// HLODR_SERVE_ARGS (extra arguments for hlodr serve, split at spaces).

import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import crypto from 'node:crypto';
import fs from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const REPO = path.resolve(HERE, '../..');
const CHROMIUM = process.env.HLODR_CHROMIUM || '/usr/bin/chromium';
const HLODR = process.env.HLODR_BINARY || path.join(REPO, 'build/hlodr');
const SHOTS = path.resolve(process.env.HLODR_WEB_SCREENSHOTS || path.join(REPO, 'build/web-screenshots'));
// The flags that work in this machine's containers (no sandbox, no GPU, no network of its own).
const CHROMIUM_FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];
const JOB_FRAMES = 30;

// In CI (CI=true) a missing piece is a failure: the set-up installs all of them.
function skip(reason) {
  console.log(`web.page: ${process.env.CI ? 'failed' : 'skipped'}: ${reason}`);
  process.exit(process.env.CI ? 1 : 77);
}

if (!fs.existsSync(CHROMIUM)) skip(`no Chromium at ${CHROMIUM} (scripts/setup.sh installs Debian's chromium)`);
if (!fs.existsSync(path.join(HERE, 'node_modules/playwright-core'))) {
  skip('tests/web/node_modules is missing: run `npm ci` in tests/web (scripts/test.sh does)');
}
if (!process.env.HLODR_WEB_URL) {
  if (!fs.existsSync(HLODR)) skip(`no hlodr binary at ${HLODR} (set HLODR_BINARY)`);
  if (spawnSync(HLODR, ['serve', '--help'], { stdio: 'ignore' }).status !== 0) skip(`${HLODR} has no serve command`);
}

const { chromium } = await import('playwright-core');

let tmp;
let dataDir; // the server's --data folder, when this test started the server
let profile; // Chromium's fresh --user-data-dir
let server;
let serverLog = '';
let baseUrl;
let context;
let page;
const problems = []; // console errors and page errors
let allowedStatus = 0; // while set, "Failed to load resource ... status of N" is expected
const frameRequests = []; // bodies of POST /api/sessions/{id}/frame
const createRequests = { sessions: [], jobs: [] }; // bodies of POST /api/sessions, /api/jobs
let framesInFlight = 0;
let maxFramesInFlight = 0;
const offOrigin = [];

function run(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')} failed (${r.status}):\n${r.stdout}\n${r.stderr}`);
}

async function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.on('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

async function waitForHealth(url, ms) {
  const end = Date.now() + ms;
  for (;;) {
    if (server && server.exitCode !== null) throw new Error(`hlodr serve exited (${server.exitCode}):\n${serverLog}`);
    try {
      const r = await fetch(`${url}/healthz`);
      if (r.ok) return;
    } catch {
      // not up yet
    }
    if (Date.now() > end) throw new Error(`hlodr serve did not answer /healthz within ${ms} ms:\n${serverLog}`);
    await new Promise((r) => setTimeout(r, 200));
  }
}

async function startServer() {
  tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'hlodr-web-'));
  const data = path.join(tmp, 'data');
  fs.mkdirSync(data);
  dataDir = data;
  run(HLODR, ['city', '--blocks', '4', '--texture', '128', '--quiet', '-o', path.join(tmp, 'city')]);
  run(HLODR, ['build', path.join(tmp, 'city'), '-o', path.join(data, 'city.hlod')]);
  // A y-up store (an OBJ box stands on y): the page offers it the CAD scenes' paths and the orbit.
  const box = [0, 1, 2, 3, 4, 5, 6, 7].map((i) => `v ${i & 1} ${4 * ((i >> 1) & 1)} ${(i >> 2) & 1}`);
  fs.writeFileSync(path.join(tmp, 'tall.obj'),
    [...box, 'f 1 3 4 2', 'f 5 6 8 7', 'f 1 2 6 5', 'f 3 7 8 4', 'f 1 5 7 3', 'f 2 4 8 6', ''].join('\n'));
  run(HLODR, ['build', path.join(tmp, 'tall.obj'), '-o', path.join(data, 'tall.hlod'), '--quiet']);
  const port = await freePort();
  const extra = (process.env.HLODR_SERVE_ARGS || '').split(' ').filter(Boolean);
  server = spawn(HLODR, ['serve', '--data', data, '--bind', '127.0.0.1', '--port', String(port), ...extra], {
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  const keep = (d) => (serverLog = (serverLog + d).slice(-20000));
  server.stdout.on('data', keep);
  server.stderr.on('data', keep);
  const url = `http://127.0.0.1:${port}`;
  await waitForHealth(url, 60000);
  return url;
}

// A hash of the frame the page shows (the canvas' pixels as PNG).
async function frameHash() {
  const png = await page.evaluate(() => document.querySelector('#frame').toDataURL('image/png'));
  return crypto.createHash('sha256').update(png).digest('hex');
}

const viewerState = () => page.evaluate(() => window.hlodrDebug.viewer());

// page.waitForFunction, and on a timeout what the page and the server were doing.
async function waitOnPage(fn, arg, timeout, what) {
  try {
    await page.waitForFunction(fn, arg, { timeout });
  } catch (e) {
    const state = await page.evaluate(() => ({
      viewer: window.hlodrDebug.viewer(),
      job: window.hlodrDebug.job(),
      charts: window.hlodrDebug.chartPoints(),
      errors: window.hlodrDebug.errors(),
    })).catch((err) => `(page state unreadable: ${err.message})`);
    throw new Error(`${what}: ${e.message}\npage: ${JSON.stringify(state)}\nconsole: ${problems.join(' | ')}` +
      `\nserver log (tail):\n${serverLog.slice(-4000)}`);
  }
}

// Waits until a still frame newer than `before` is shown and nothing is in flight.
async function waitForRest(before, what) {
  await waitOnPage(
    (n) => {
      const v = window.hlodrDebug.viewer();
      return v.stillFramesShown > n && !v.inFlight;
    },
    before.stillFramesShown,
    30000,
    `no still frame after ${what}`,
  );
}

async function shot(name) {
  fs.mkdirSync(SHOTS, { recursive: true });
  await page.screenshot({ path: path.join(SHOTS, `${name}.png`), fullPage: true });
}

before(async () => {
  baseUrl = process.env.HLODR_WEB_URL ? process.env.HLODR_WEB_URL.replace(/\/$/, '') : await startServer();
  profile = fs.mkdtempSync(path.join(os.tmpdir(), 'hlodr-chromium-'));
  context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    args: CHROMIUM_FLAGS,
    viewport: { width: 1440, height: 900 },
    acceptDownloads: true,
  });
  page = context.pages()[0] || (await context.newPage());
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    if (allowedStatus && m.text().includes(`status of ${allowedStatus}`)) return;
    problems.push(`console: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('request', (r) => {
    if (!r.url().startsWith(baseUrl) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) offOrigin.push(r.url());
    const create = r.method() === 'POST' && /\/api\/(sessions|jobs)$/.exec(new URL(r.url()).pathname);
    if (create) createRequests[create[1]].push(JSON.parse(r.postData()));
    if (/\/api\/sessions\/[^/]+\/frame$/.test(r.url())) {
      frameRequests.push(JSON.parse(r.postData()));
      maxFramesInFlight = Math.max(maxFramesInFlight, ++framesInFlight);
    }
  });
  const done = (r) => /\/api\/sessions\/[^/]+\/frame$/.test(r.url()) && framesInFlight--;
  page.on('requestfinished', done);
  page.on('requestfailed', done);
});

after(async () => {
  if (context) await context.close().catch(() => {});
  if (server) {
    server.kill('SIGTERM');
    await new Promise((r) => (server.exitCode !== null ? r() : server.once('exit', r)));
  }
  for (const dir of [tmp, profile]) if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

test('the page loads, picks the scene and shows a still frame', async () => {
  const response = await page.goto(`${baseUrl}/`);
  assert.equal(response.status(), 200);
  assert.match(await response.text(), /<title>hlodr<\/title>/);
  await waitForRest({ stillFramesShown: 0 }, 'loading the page');
  const scene = await page.locator('#scene').inputValue();
  assert.equal(scene, 'city');
  const v = await viewerState();
  assert.ok(v.stats && v.stats.targetMs > 0, 'the frame came with its X-Hlodr-Stats');
  assert.match(await page.locator('#overlay').innerText(), /ms budget/);
  await shot('1-view');
});

test('dragging orbits the camera: real-time frames while moving, one still frame at rest', async () => {
  const before = await viewerState();
  const hash = await frameHash();
  const requestsBefore = frameRequests.length;
  const box = await page.locator('#view').boundingBox();
  const x = box.x + box.width / 2;
  const y = box.y + box.height / 2;
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let i = 1; i <= 12; i++) {
    await page.mouse.move(x + i * 18, y + i * 5);
    await page.waitForTimeout(25);
  }
  await page.mouse.up();
  await waitForRest(before, 'the drag');
  const now = await viewerState();
  assert.ok(now.framesShown >= before.framesShown + 2, 'a real-time frame during the drag and a still one after');
  assert.notEqual(await frameHash(), hash, 'the frame changed');
  const sent = frameRequests.slice(requestsBefore);
  const moving = sent.filter((b) => b.still === false);
  const still = sent.filter((b) => b.still === true);
  assert.ok(moving.length >= 1, 'real-time frames while dragging');
  assert.equal(still.length, 1, 'one still frame once the camera rests');
  assert.ok(moving[0].quality < still[0].quality, 'real-time frames at a lower JPEG quality');
  assert.equal(sent[sent.length - 1].still, true, 'the still frame comes last');
  assert.equal(maxFramesInFlight, 1, 'one frame request in flight at a time');
  await shot('2-orbited');
});

test('the wheel zooms and WASD walks, each changing the frame', async () => {
  let before = await viewerState();
  let hash = await frameHash();
  const box = await page.locator('#view').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel(0, -500);
  await waitForRest(before, 'zooming');
  assert.notEqual(await frameHash(), hash, 'zooming changed the frame');

  before = await viewerState();
  hash = await frameHash();
  await page.focus('#view');
  await page.keyboard.down('w');
  await page.waitForTimeout(500);
  await page.keyboard.up('w');
  await waitForRest(before, 'walking');
  assert.notEqual(await frameHash(), hash, 'walking changed the frame');
  assert.equal(maxFramesInFlight, 1, 'one frame request in flight at a time');
});

test("an out-of-range setting shows the API's error message, and a good one clears it", async () => {
  const before = await viewerState();
  allowedStatus = 400; // the browser logs the 400 it is about to get
  await page.fill('#budget', '0');
  await page.locator('#budget').dispatchEvent('change');
  const error = page.locator('#errors .error');
  await error.waitFor({ timeout: 15000 });
  assert.match(await error.innerText(), /budgetMs/, 'the message names the field');
  await shot('3-error');
  await page.fill('#budget', '33');
  await page.locator('#budget').dispatchEvent('change');
  await waitForRest(before, 'the budget was set back');
  allowedStatus = 0;
  assert.equal(await page.locator('#errors .error').count(), 0, 'the error went once frames came again');
});

test('a new size makes a new session whose frames have that size', async () => {
  const before = await viewerState();
  // 640 x 360 also keeps the path job below quick on a loaded machine.
  await page.selectOption('#size', '640x360');
  await waitForRest(before, 'the size changed');
  const now = await viewerState();
  assert.notEqual(now.session, before.session, 'a new session');
  assert.deepEqual(await page.evaluate(() => [document.querySelector('#frame').width, document.querySelector('#frame').height]),
    [640, 360]);
});

test('a path job plays its frames, fills every chart, and offers its CSV and MP4', async () => {
  await page.fill('#frames', String(JOB_FRAMES));
  await page.selectOption('#path-kind', 'walk-fly');
  await page.check('#video');
  await page.click('#start-job');
  await waitOnPage(() => window.hlodrDebug.job().framesReceived >= 5, null, 120000, 'the job sent no frames');
  await shot('4-job-running');
  await waitOnPage(() => ['done', 'failed', 'cancelled'].includes(window.hlodrDebug.job().state), null, 180000,
    'the job did not end');
  const job = await page.evaluate(() => window.hlodrDebug.job());
  assert.equal(job.state, 'done', `the job ended ${job.state}: ${problems.join(' | ')}`);
  assert.equal(job.framesReceived, JOB_FRAMES);
  assert.ok(job.framesShown >= 1, 'the player showed frames');
  // The player may be swapping in the last frame as the job ends; wait for the image, not for a moment.
  await waitOnPage(() => document.querySelector('#job-frame').complete &&
    document.querySelector('#job-frame').naturalWidth > 0, null, 15000, 'the frame image loaded');
  const points = await page.evaluate(() => window.hlodrDebug.chartPoints());
  for (const [chart, n] of Object.entries(points)) assert.equal(n, JOB_FRAMES, `chart ${chart} has every frame`);

  const row = page.locator(`tr[data-job="${job.id}"][data-state="done"]`);
  await row.waitFor({ timeout: 15000 });
  await page.waitForTimeout(300); // let the charts draw their last points before the screenshot
  await shot('5-job-done');

  const [download] = await Promise.all([page.waitForEvent('download'), row.locator('a.csv').click()]);
  const csv = fs.readFileSync(await download.path(), 'utf8');
  const lines = csv.trim().split('\n');
  const columns = lines[0].split(',');
  assert.equal(columns[0], 'index', `the CSV header: ${lines[0]}`);
  for (const name of ['time', 'targetMs', 'gpuMs', 'triangles', 'upToggles', 'residentBytes', 'loadsFinished', 'level0']) {
    assert.ok(columns.includes(name), `the CSV header has ${name}: ${lines[0]}`);
  }
  assert.equal(lines.length - 1, JOB_FRAMES, 'one CSV row per frame');

  const video = await row.locator('a[href$=".mp4"]').getAttribute('href');
  const mp4 = await page.evaluate(async (href) => {
    const r = await fetch(href);
    const bytes = new Uint8Array(await r.arrayBuffer());
    return { status: r.status, type: r.headers.get('Content-Type'), box: String.fromCharCode(...bytes.slice(4, 8)) };
  }, video);
  assert.equal(mp4.status, 200);
  assert.match(mp4.type, /^video\/mp4/);
  assert.equal(mp4.box, 'ftyp', 'an MP4 starts with its ftyp box');
});

test('a running job can be cancelled from the jobs list', async () => {
  await page.fill('#frames', '1000');
  await page.uncheck('#video');
  const previous = await page.evaluate(() => window.hlodrDebug.job().id);
  await page.click('#start-job');
  await waitOnPage((id) => {
    const job = window.hlodrDebug.job();
    return job.id !== id && job.framesReceived >= 2;
  }, previous, 120000, 'the long job sent no frames');
  const id = await page.evaluate(() => window.hlodrDebug.job().id);
  const cancel = page.locator(`tr[data-job="${id}"] button.cancel`);
  await cancel.waitFor({ timeout: 15000 });
  await cancel.click();
  await waitOnPage(() => window.hlodrDebug.job().state === 'cancelled', null, 30000, 'the job was not cancelled');
  await page.locator(`tr[data-job="${id}"][data-state="cancelled"]`).waitFor({ timeout: 15000 });
  const job = await page.evaluate(() => window.hlodrDebug.job());
  assert.ok(job.framesReceived < 1000, 'it stopped before its last frame');
  await shot('6-job-cancelled');
});

test('an accuracy study runs from the page and its report opens', async () => {
  const form = page.locator('#study');
  await form.locator('[name="study-frames"]').fill('2');
  await form.locator('[name="study-budgets"]').fill('16, 33');
  await form.locator('[name="study-sse-px"]').fill('8');
  await form.locator('[name="use-fs"]').uncheck();
  await form.locator('[name="start-study"]').click();
  const done = page.locator('#studies tr[data-state="done"]');
  await done.waitFor({ timeout: 180000 });
  const href = await done.locator('a').first().getAttribute('href');
  assert.match(href, /^\/api\/studies\/[a-z0-9]+\/report\/index\.html$/);
  const report = await page.evaluate(async (url) => {
    const r = await fetch(url);
    const json = await (await fetch(url.replace('index.html', 'study.json'))).json();
    return { status: r.status, html: await r.text(), runs: json.runs.length };
  }, href);
  assert.equal(report.status, 200);
  assert.match(report.html, /What accuracy costs in time/);
  assert.equal(report.runs, 3, 'lakhia at 16 and 33 ms, sse at 8 px');
  await shot('7-study-done');
  const reportPage = await context.newPage();
  await reportPage.goto(new URL(href, page.url()).href);
  await reportPage.waitForLoadState('load');
  await reportPage.screenshot({ path: path.join(SHOTS, '8-study-report.png'), fullPage: true });
  await reportPage.close();
});

test('a y-up store is offered the CAD paths and the orbit, and the city its three kinds', async () => {
  const kinds = () => page.evaluate(() => ['#path-kind', '[name="study-path"]'].map((q) => {
    const select = document.querySelector(q);
    const enabled = [...select.options].filter((o) => !o.disabled).map((o) => o.value).sort();
    return { value: select.value, enabled };
  }));
  let before = await viewerState();
  await page.selectOption('#scene', 'tall');
  await waitForRest(before, 'picking the y-up scene');
  for (const k of await kinds())
    assert.deepEqual(k, { value: 'catwalk', enabled: ['catwalk', 'fly-around', 'orbit'] });
  await shot('9-y-up-scene');
  before = await viewerState();
  await page.selectOption('#scene', 'city');
  await waitForRest(before, 'picking the city again');
  for (const k of await kinds()) assert.deepEqual(k.enabled, ['drive', 'orbit', 'walk-fly']);
});

// A scene file next to the stores: lambert, the sun and a sky, and a low camera at the city's
// corner rather than the store's overview. The page offers it with its effects; picking it opens
// a session on the file, which starts from the file's camera, and a job on it runs.
test('a scene file is offered with its effects, and picking it draws it from its camera', {
  skip: process.env.HLODR_WEB_URL ? 'writes into the data folder of a server this test starts' : false,
}, async () => {
  const city = (await (await fetch(`${baseUrl}/api/scenes`)).json()).scenes.find((s) => s.id === 'city');
  const { min, max } = city.bounds;
  const size = max.map((v, i) => v - min[i]);
  const camera = {
    position: [min[0] - 0.1 * size[0], min[1] - 0.1 * size[1], min[2] + 0.3 * size[2]],
    target: [min[0] + 0.6 * size[0], min[1] + 0.6 * size[1], min[2] + 0.1 * size[2]],
    up: [0, 0, 1],
    fov: 65,
  };
  fs.writeFileSync(path.join(dataDir, 'corner.json'), JSON.stringify({
    store: 'city.hlod',
    camera,
    background: { sky: {} },
    effects: { shading: 'lambert', sun: true },
  }, null, 2));

  // The list of scene files comes with GET /api/scenes, which the page reads as it loads.
  await page.reload();
  await waitForRest({ stillFramesShown: 0 }, 'reloading the page');
  const look = page.locator('#look');
  const options = () => look.evaluate((s) => [...s.options].map((o) => ({ value: o.value, text: o.textContent })));
  assert.equal(await page.locator('#scene').inputValue(), 'city');
  assert.equal(await look.inputValue(), '', 'the store defaults first');
  assert.equal(await look.isDisabled(), false);
  assert.deepEqual(await options(), [
    { value: '', text: 'store defaults' },
    { value: 'corner.json', text: 'corner.json · lambert, sun, sky' },
  ]);
  assert.equal(createRequests.sessions.at(-1).scene, 'city', 'store defaults: the store id');

  let before = await viewerState();
  const storeFrame = await frameHash();
  const requestsBefore = frameRequests.length;
  await page.selectOption('#look', 'corner.json');
  await waitForRest(before, 'picking the scene file');
  const now = await viewerState();
  assert.notEqual(now.session, before.session, 'a new session');
  assert.equal(now.sceneFile, 'corner.json');
  assert.equal(createRequests.sessions.at(-1).scene, 'corner.json', 'the session was opened on the file');
  assert.notEqual(await frameHash(), storeFrame, 'the frame differs from the store-defaults frame');
  // Every frame since the pick is from the file's camera (nothing moved it).
  const sent = frameRequests.slice(requestsBefore);
  assert.ok(sent.length >= 1);
  for (const body of sent) {
    assert.equal(body.camera.fov, camera.fov);
    for (const key of ['position', 'target']) {
      const off = Math.hypot(...body.camera[key].map((v, i) => v - camera[key][i]));
      assert.ok(off < 1e-6 * Math.hypot(...size), `the frame's camera ${key} is the file's: ${body.camera[key]}`);
    }
  }
  await shot('10-scene-file');

  // A job on the picked file: sent as its name; the job object names the store, which the jobs
  // list uses to size the dashboard's levels chart when the job is shown from the list.
  await page.fill('#frames', '3');
  await page.selectOption('#path-kind', 'orbit');
  await page.uncheck('#video');
  const previous = await page.evaluate(() => window.hlodrDebug.job().id);
  await page.click('#start-job');
  await waitOnPage((id) => {
    const job = window.hlodrDebug.job();
    return job.id !== id && ['done', 'failed', 'cancelled'].includes(job.state);
  }, previous, 120000, 'the job on the scene file did not end');
  assert.equal(createRequests.jobs.at(-1).scene, 'corner.json', 'the job was started on the file');
  const job = await page.evaluate(() => window.hlodrDebug.job());
  assert.equal(job.state, 'done');
  const row = page.locator(`tr[data-job="${job.id}"][data-state="done"]`);
  await row.waitFor({ timeout: 15000 });
  assert.match(await row.locator('.sub').first().innerText(), /^city \(corner\.json\) · orbit$/);
  await row.locator('button.link').click();
  await waitOnPage(() => Object.values(window.hlodrDebug.chartPoints()).every((n) => n === 3), null, 30000,
    'the job shown from the list did not fill its charts');

  // A store without scene files: only the store defaults, disabled; back on the city, the pick
  // has gone back to its defaults.
  before = await viewerState();
  await page.selectOption('#scene', 'tall');
  await waitForRest(before, 'picking the y-up scene');
  assert.equal(await look.isDisabled(), true);
  assert.deepEqual(await options(), [{ value: '', text: 'store defaults' }]);
  assert.equal(createRequests.sessions.at(-1).scene, 'tall');
  before = await viewerState();
  await page.selectOption('#scene', 'city');
  await waitForRest(before, 'picking the city again');
  assert.equal(await look.inputValue(), '');
  assert.equal(createRequests.sessions.at(-1).scene, 'city');
});

test('the scene picker says where a store came from, and the scene exports as 3D Tiles', async () => {
  const labels = await page.locator('#scene').evaluate((s) => [...s.options].map((o) => o.textContent));
  if (!process.env.HLODR_WEB_URL) assert.deepEqual(labels, ['city (city folder)', 'tall (mesh)']);
  await page.selectOption('#scene', 'city');
  await page.click('#export-tiles');
  const url = page.locator('#export-url');
  await url.waitFor({ timeout: 60000 });
  const href = await url.inputValue();
  assert.match(href, /^http:\/\/[^/]+\/api\/jobs\/e[0-9a-f]+\/tiles\/tileset\.json$/);
  const zip = await page.locator('#export-zip').getAttribute('href');
  const got = await page.evaluate(async ([tileset, archive]) => {
    const t = await fetch(tileset);
    const z = await fetch(archive);
    const bytes = new Uint8Array(await z.arrayBuffer());
    return { status: t.status, version: (await t.json()).asset.version, zipStatus: z.status, magic: String.fromCharCode(...bytes.slice(0, 2)) };
  }, [href, zip]);
  assert.deepEqual(got, { status: 200, version: '1.1', zipStatus: 200, magic: 'PK' });
  const id = href.split('/')[5];
  await page.locator(`#jobs tr[data-job="${id}"][data-state="done"] a[href$="tileset.json"]`).waitFor({ timeout: 15000 });
  await shot('11-export');
});

test('the page uses nothing but its own server, and the vendored uPlot is unchanged', () => {
  assert.deepEqual(offOrigin, []);
  // web/vendor/uplot/SHA256SUMS holds the hashes of the npm package's files (uplot@1.6.32).
  const sums = fs.readFileSync(path.join(REPO, 'web/vendor/uplot/SHA256SUMS'), 'utf8').trim().split('\n');
  assert.equal(sums.length, 3);
  for (const line of sums) {
    const [hash, name] = line.split(/\s+/);
    const actual = crypto.createHash('sha256').update(fs.readFileSync(path.join(REPO, 'web/vendor/uplot', name))).digest('hex');
    assert.equal(actual, hash, `web/vendor/uplot/${name} matches SHA256SUMS`);
  }
});

test('no console errors and no page errors', () => {
  assert.deepEqual(problems, []);
});
