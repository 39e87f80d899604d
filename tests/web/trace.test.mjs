// hlodr's Chrome traces (`--trace FILE`, docs/cli.md) read by a trace viewer people use:
// speedscope (vendor/speedscope-1.25.0.tgz, its built web app) in Debian's headless Chromium.
// Perfetto UI is a web site, and this Chromium refuses chrome://tracing; speedscope's importer of
// the Trace Event Format is strict about nesting: a slice that ends after its parent, even by
// 1e-11 us, is logged ("Tried to end ... when ... was on the top of the stack").
//
// A 4-block city, a realtime path of 60 frames and a settled one (its frames wait for loading)
// with `hlodr render --trace`, and a two-run `hlodr study --trace`; each trace is opened in
// speedscope as a user does (its file input). Checked: speedscope names the profile after the
// file and shows the run's frames track, and it logs nothing about the events.
//
// Exit 77 (ctest's skip) with a message when Chromium, tests/web/node_modules or tar is missing;
// a failure instead when CI is set. Environment: HLODR_BINARY (default build/hlodr),
// HLODR_CHROMIUM (default /usr/bin/chromium).
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const REPO = path.resolve(HERE, '../..');
const CHROMIUM = process.env.HLODR_CHROMIUM || '/usr/bin/chromium';
const HLODR = process.env.HLODR_BINARY || path.join(REPO, 'build/hlodr');
const SPEEDSCOPE = path.join(HERE, 'vendor/speedscope-1.25.0.tgz');
const CHROMIUM_FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

function skip(reason) {
  console.log(`web.trace: ${process.env.CI ? 'failed' : 'skipped'}: ${reason}`);
  process.exit(process.env.CI ? 1 : 77);
}
if (!fs.existsSync(CHROMIUM)) skip(`no Chromium at ${CHROMIUM} (scripts/setup.sh installs Debian's chromium)`);
if (!fs.existsSync(path.join(HERE, 'node_modules/playwright-core'))) skip('tests/web/node_modules is missing: run `npm ci` in tests/web');
if (!fs.existsSync(HLODR)) skip(`no hlodr binary at ${HLODR} (set HLODR_BINARY)`);
if (spawnSync('tar', ['--version'], { stdio: 'ignore' }).status !== 0) skip('tar is not installed');
const { chromium } = await import('playwright-core');

function run(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')} failed (${r.status}):\n${r.stdout}\n${r.stderr}`);
}

const failures = [];
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'hlodr-trace-'));
let browser;
try {
  // The viewer: the package's built app, opened from the disk.
  run('tar', ['xzf', SPEEDSCOPE, '-C', tmp]);
  const app = `file://${path.join(tmp, 'package/dist/release/index.html')}`;

  const store = path.join(tmp, 'city.hlod');
  run(HLODR, ['city', '--blocks', '4', '--texture', '128', '--quiet', '-o', path.join(tmp, 'city')]);
  run(HLODR, ['build', path.join(tmp, 'city'), '-o', store, '--quiet']);
  run(HLODR, ['path', store, '--kind', 'orbit', '-o', path.join(tmp, 'orbit.json')]);
  const traces = [];
  for (const mode of ['realtime', 'settled']) {
    const file = path.join(tmp, `render-${mode}.json`);
    run(HLODR, ['render', store, '--path', path.join(tmp, 'orbit.json'), '--frames', '60', '--size', '320x180',
      '--mode', mode, '-o', path.join(tmp, `frames-${mode}`), '--quiet', '--trace', file]);
    traces.push({ file, track: 'hlodr render' });
  }
  const studyTrace = path.join(tmp, 'study.json');
  run(HLODR, ['study', store, '--kind', 'orbit', '--frames', '12', '--size', '160x90', '--selectors', 'lakhia,sse',
    '--budgets', '16', '--sse-px', '4', '--quiet', '-o', path.join(tmp, 'study'), '--trace', studyTrace]);
  traces.push({ file: studyTrace, track: '' });

  browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_FLAGS });
  for (const { file, track } of traces) {
    const name = path.basename(file);
    const page = await browser.newPage();
    const logged = []; // warnings and errors
    let importer = '';
    page.on('console', (m) => {
      if (/^Importing as /.test(m.text())) importer = m.text();
      // Chromium's own notes on its software WebGL are not the trace's.
      if ((m.type() === 'warning' || m.type() === 'error') && !/GL Driver Message|WebGL/.test(m.text()))
        logged.push(m.text());
    });
    page.on('pageerror', (e) => logged.push(String(e)));
    await page.goto(app);
    await page.locator('input[type=file]').first().setInputFiles(file);
    await page.waitForFunction((n) => document.title.startsWith(n), name, { timeout: 30000 }).catch(() => {});
    const title = await page.title();
    const body = await page.evaluate(() => document.body.innerText);
    check(title === `${name} - speedscope`, `${name}: speedscope opened it (title "${title}")`);
    check(body.includes('frames (tid 1)') && (!track || body.includes(track)),
      `${name}: the frames track is shown${track ? ` for ${track}` : ''}`);
    check(importer === 'Importing as Trace Event Format profile', `${name}: read as the Trace Event Format (${importer || 'no importer named'})`);
    check(logged.length === 0, `${name}: speedscope warned of nothing${logged.length ? `:\n  ${logged.slice(0, 5).join('\n  ')}` : ''}`);
    await page.close();
  }
} catch (e) {
  failures.push(String(e && e.stack ? e.stack : e));
  console.log(`FAIL ${e && e.stack ? e.stack : e}`);
} finally {
  if (browser) await browser.close();
  fs.rmSync(tmp, { recursive: true, force: true });
}
console.log(failures.length ? `web.trace: ${failures.length} failed` : 'web.trace: passed');
process.exit(failures.length ? 1 : 0);
