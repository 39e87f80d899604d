// Four sessions on one server (issue: beyond one machine): N clients orbit the city at once, each
// asking for its next frame when the last one arrives (as the page does while the camera moves),
// first under `serve --admission share`, then `--admission queue`, each beside one client alone.
// Prints, per client: frames per second, the median interval between its frames, the median
// relative deviation |d| of the frame's time from the target it was selected for (its share of
// the budget, or the budget), and from the session's own budget, and the median triangles.
//
//   node tests/deploy/sessions.bench.mjs [--store STORE.hlod] [--clients 4] [--budget-ms 33]
//        [--size 640x360] [--seconds 20] [--workers 2]
// Without --store it builds the default city (`hlodr city` then `hlodr build`) in a temporary
// folder. Environment: HLODR_BINARY (default build/hlodr); DUMP=PREFIX writes every frame's stats
// to PREFIX-ADMISSION-CLIENTS.json.
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { freePort, orbit } from './support.mjs';

const REPO = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const HLODR = process.env.HLODR_BINARY || path.join(REPO, 'build/hlodr');

function option(name, fallback) {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
const CLIENTS = Number(option('clients', 4));
const BUDGET = Number(option('budget-ms', 33));
const [WIDTH, HEIGHT] = option('size', '640x360').split('x').map(Number);
const SECONDS = Number(option('seconds', 20));
const WORKERS = option('workers', '2');
const WARM_MS = 3000;
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function run(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')} failed (${r.status}):\n${r.stdout}\n${r.stderr}`);
}

const median = (v) => {
  if (!v.length) return NaN;
  const s = [...v].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
};

async function post(url, body) {
  const r = await fetch(url, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  if (r.status >= 400) throw new Error(`${url}: ${r.status} ${await r.text()}`);
  return r;
}

class Client {
  constructor(base, scene, phase) {
    this.base = base;
    this.scene = scene;
    this.phase = phase; // angle offset: the clients look at different sides of the city
    this.frames = []; // {at, gpuMs, targetMs, budgetMs, sharedBy, triangles}
    this.stopped = false;
  }

  async loop() {
    const s = await (await post(`${this.base}/api/sessions`, { scene: this.scene.id, width: WIDTH, height: HEIGHT, budgetMs: BUDGET })).json();
    let angle = this.phase;
    while (!this.stopped) {
      angle += 0.02;
      const camera = orbit(s.defaultCamera, this.scene.up, angle);
      const r = await post(`${this.base}/api/sessions/${s.id}/frame`, { camera, still: false, format: 'jpeg', quality: 60 });
      await r.arrayBuffer();
      const st = JSON.parse(r.headers.get('X-Hlodr-Stats'));
      this.frames.push({ at: performance.now(), ...st });
    }
    await fetch(`${this.base}/api/sessions/${s.id}`, { method: 'DELETE' });
  }

  figures(from, to) {
    const f = this.frames.filter((x) => x.at >= from && x.at < to);
    const intervals = f.slice(1).map((x, i) => x.at - f[i].at);
    return {
      fps: f.length / ((to - from) / 1000),
      interval: median(intervals),
      dTarget: median(f.map((x) => Math.abs(x.gpuMs - x.targetMs) / x.targetMs)),
      dBudget: median(f.map((x) => Math.abs(x.gpuMs - x.budgetMs) / x.budgetMs)),
      gpuMs: median(f.map((x) => x.gpuMs)),
      targetMs: median(f.map((x) => x.targetMs)),
      sharedBy: median(f.map((x) => x.sharedBy)),
      triangles: median(f.map((x) => x.triangles)),
    };
  }
}

async function phase(base, scene, n, admission) {
  const clients = Array.from({ length: n }, (_, i) => new Client(base, scene, (2 * Math.PI * i) / n));
  const loops = clients.map((c) => c.loop());
  await sleep(WARM_MS);
  const from = performance.now();
  await sleep(SECONDS * 1000);
  const to = performance.now();
  clients.forEach((c) => (c.stopped = true));
  await Promise.all(loops);
  if (process.env.DUMP) fs.writeFileSync(`${process.env.DUMP}-${admission}-${n}.json`, JSON.stringify(clients.map((c) => c.frames)));
  return clients.map((c) => c.figures(from, to));
}

const row = (name, f) =>
  `  ${name.padEnd(10)} ${f.fps.toFixed(1).padStart(5)} ${f.interval.toFixed(0).padStart(6)} ${f.gpuMs.toFixed(1).padStart(6)} ` +
  `${f.targetMs.toFixed(1).padStart(6)} ${String(f.sharedBy).padStart(3)} ${(100 * f.dTarget).toFixed(1).padStart(6)}% ` +
  `${(100 * f.dBudget).toFixed(1).padStart(6)}% ${String(Math.round(f.triangles)).padStart(8)}`;

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'hlodr-sessions-'));
let server = null;
try {
  const data = path.join(tmp, 'data');
  fs.mkdirSync(data);
  const store = option('store', '');
  if (store) {
    fs.symlinkSync(path.resolve(store), path.join(data, 'city.hlod'));
  } else {
    console.log('building the default city...');
    run(HLODR, ['city', '--quiet', '-o', path.join(tmp, 'city')]);
    run(HLODR, ['build', path.join(tmp, 'city'), '-o', path.join(data, 'city.hlod'), '--quiet']);
  }
  console.log(`${os.cpus().length} cores, ${WORKERS} workers, ${WIDTH}x${HEIGHT} JPEG, budget ${BUDGET} ms, ${SECONDS} s per phase`);
  console.log(`  ${'client'.padEnd(10)} ${'fps'.padStart(5)} ${'int ms'.padStart(6)} ${'ms'.padStart(6)} ${'tgt'.padStart(6)} ${'k'.padStart(3)} ` +
    `${'|d|tgt'.padStart(7)} ${'|d|bud'.padStart(7)} ${'tris'.padStart(8)}   (medians)`);
  for (const admission of ['share', 'queue']) {
    const port = await freePort();
    server = spawn(HLODR, ['serve', '--data', data, '--jobs-dir', path.join(tmp, `jobs-${admission}`), '--port', String(port),
      '--workers', WORKERS, '--admission', admission, '--quiet'], { stdio: 'ignore' });
    const base = `http://127.0.0.1:${port}`;
    for (let i = 0; ; i++) {
      if ((await fetch(`${base}/healthz`).catch(() => null))?.status === 200) break;
      if (i > 600) throw new Error('the server did not start');
      await sleep(100);
    }
    const scene = (await (await fetch(`${base}/api/scenes`)).json()).scenes.find((s) => s.id === 'city');
    console.log(`--admission ${admission}`);
    const [alone] = await phase(base, scene, 1, admission);
    console.log(row('alone', alone));
    const many = await phase(base, scene, CLIENTS, admission);
    many.forEach((f, i) => console.log(row(`${CLIENTS} #${i}`, f)));
    server.kill('SIGTERM');
    await new Promise((r) => server.once('exit', r));
    server = null;
  }
} finally {
  if (server) server.kill('SIGKILL');
  fs.rmSync(tmp, { recursive: true, force: true });
}
