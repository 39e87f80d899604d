// The configuration of deploy/ checked by the tools that read it (docs/deploy.md):
//   - deploy/haproxy.cfg: `haproxy -c`;
//   - deploy/prometheus.yml: `promtool check config`;
//   - deploy/grafana/hlodr.json: every PromQL expression parses (`promtool check rules` on a rules
//     file made of them), and every metric it names is one a live server exports (a server is
//     started and renders a frame, so that the histograms have samples);
//   - deploy/k8s/*.yaml: each object validated against the Kubernetes API's JSON schema of its
//     kind (kubernetes-models bundles the schemas: offline). Those schemas check types, enums and
//     required fields but allow unknown fields; the probes and the HPA metric are checked here.
//
// Environment: HLODR_BINARY (default build/hlodr). Exits 77 (skipped) without haproxy, promtool
// or tests/deploy/node_modules (scripts/test.sh installs it), and fails instead when CI is set.
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { freePort } from './support.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const REPO = path.resolve(HERE, '../..');
const DEPLOY = path.join(REPO, 'deploy');
const HLODR = process.env.HLODR_BINARY || path.join(REPO, 'build/hlodr');

function skip(why) {
  console.log(`config.test: skipped: ${why}`);
  process.exit(process.env.CI ? 1 : 77);
}
for (const [tool, arg] of [['haproxy', '-v'], ['promtool', '--version']])
  if (spawnSync(tool, [arg], { stdio: 'ignore' }).status !== 0) skip(`${tool} is not installed`);
// Where the npm registry cannot be reached (scripts/test.sh sets HLODR_DEPLOY_K8S_SKIP), the
// manifests' schema check is left out, said loudly; the rest runs.
const k8sSkipped = !fs.existsSync(path.join(HERE, 'node_modules/kubernetes-models'));
if (k8sSkipped && !process.env.HLODR_DEPLOY_K8S_SKIP) skip('tests/deploy/node_modules is missing (npm ci)');
if (k8sSkipped) console.log('config.test: WARNING: no tests/deploy/node_modules: the Kubernetes manifests are NOT checked');

const failures = [];
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'hlodr-deploy-config-'));

function tool(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  return { ok: r.status === 0, out: `${r.stdout}${r.stderr}`.trim() };
}

// haproxy and Prometheus.
{
  const h = tool('haproxy', ['-c', '-f', path.join(DEPLOY, 'haproxy.cfg')]);
  check(h.ok, `haproxy -c deploy/haproxy.cfg${h.ok ? '' : `: ${h.out}`}`);
  const p = tool('promtool', ['check', 'config', path.join(DEPLOY, 'prometheus.yml')]);
  check(p.ok, `promtool check config deploy/prometheus.yml${p.ok ? '' : `: ${p.out}`}`);
}

// The dashboard's expressions, with Grafana's variables given values.
const dashboard = JSON.parse(fs.readFileSync(path.join(DEPLOY, 'grafana/hlodr.json'), 'utf8'));
const exprs = dashboard.panels.flatMap((p) => (p.targets || []).map((t) => t.expr)).filter(Boolean);
check(exprs.length >= 6, `the dashboard has ${exprs.length} queries`);
const concrete = (e) => e.replaceAll('$__rate_interval', '1m').replaceAll('$budget_ms', '33').replaceAll('$job', '.*');
{
  const rules = path.join(tmp, 'rules.yml');
  const body = exprs.map((e, i) => `      - record: dashboard:query${i}\n        expr: ${JSON.stringify(concrete(e))}`).join('\n');
  fs.writeFileSync(rules, `groups:\n  - name: dashboard\n    rules:\n${body}\n`);
  const r = tool('promtool', ['check', 'rules', rules]);
  check(r.ok, `promtool parses the dashboard's ${exprs.length} expressions${r.ok ? '' : `: ${r.out}`}`);
}

// Metric names of a PromQL expression: identifiers that are not functions, keywords, label
// names or values (strings, label matchers, grouping clauses and ranges are removed first).
const KEYWORDS = new Set(['by', 'without', 'on', 'ignoring', 'group_left', 'group_right', 'and', 'or', 'unless',
  'offset', 'bool', 'inf', 'nan']);
function metricNames(expr) {
  const stripped = concrete(expr)
    .replace(/"(?:[^"\\]|\\.)*"/g, '""')
    .replace(/\{[^}]*\}/g, ' ')
    .replace(/\b(by|without|on|ignoring)\s*\([^)]*\)/g, ' ')
    .replace(/\[[^\]]*\]/g, ' ');
  const names = new Set();
  for (const m of stripped.matchAll(/[A-Za-z_:][A-Za-z0-9_:]*(\s*\()?/g)) {
    if (m[1] || KEYWORDS.has(m[0].toLowerCase())) continue; // a function call, a keyword
    names.add(m[0]);
  }
  return names;
}
const wanted = new Set(exprs.flatMap((e) => [...metricNames(e)]));
check(wanted.has('hlodr_frame_seconds_bucket') && wanted.has('hlodr_queue_length') && wanted.has('hlodr_sessions') &&
  wanted.has('hlodr_resident_bytes'), `the dashboard shows frame time, queue, sessions, resident bytes (${[...wanted].join(', ')})`);

// A live server's metrics, after a frame.
let server = null;
try {
  const data = path.join(tmp, 'data');
  fs.mkdirSync(data);
  for (const args of [['city', '--blocks', '1', '--texture', '64', '--quiet', '-o', path.join(tmp, 'city')],
    ['build', path.join(tmp, 'city'), '-o', path.join(data, 'city.hlod'), '--quiet']]) {
    const r = tool(HLODR, args);
    if (!r.ok) throw new Error(`hlodr ${args[0]}: ${r.out}`);
  }
  const port = await freePort();
  server = spawn(HLODR, ['serve', '--data', data, '--bind', '127.0.0.1', '--port', String(port), '--quiet'], { stdio: 'ignore' });
  const url = `http://127.0.0.1:${port}`;
  for (let i = 0; ; i++) {
    const ok = await fetch(`${url}/healthz`).then((r) => r.ok).catch(() => false);
    if (ok) break;
    if (i > 300) throw new Error('hlodr serve did not start');
    await sleep(100);
  }
  const post = (p, body) => fetch(`${url}${p}`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const session = await (await post('/api/sessions', { scene: 'city', width: 64, height: 48 })).json();
  const frame = await post(`/api/sessions/${session.id}/frame`, {});
  await frame.arrayBuffer();
  check(frame.status === 200, `a frame rendered (${frame.status})`);
  const text = await (await fetch(`${url}/metrics`)).text();
  // Every sample's name (histograms export NAME_bucket, NAME_sum and NAME_count).
  const exported = new Set(text.split('\n').filter((l) => l && !l.startsWith('#')).map((l) => l.match(/^[A-Za-z_:][A-Za-z0-9_:]*/)[0]));
  for (const name of wanted) check(exported.has(name), `the server exports ${name}`);
  check(exported.has('hlodr_queue_length'), 'the server exports hlodr_queue_length (the HPA metric)');
} catch (e) {
  check(false, String(e && e.stack ? e.stack : e));
} finally {
  if (server) server.kill('SIGTERM');
}

// Kubernetes manifests against the API's schemas.
if (!k8sSkipped) {
  const YAML = (await import('yaml')).default;
  const kinds = {
    'apps/v1/Deployment': 'kubernetes-models/apps/v1/Deployment',
    'v1/Service': 'kubernetes-models/v1/Service',
    'autoscaling/v2/HorizontalPodAutoscaler': 'kubernetes-models/autoscaling/v2/HorizontalPodAutoscaler',
    'batch/v1/Job': 'kubernetes-models/batch/v1/Job',
  };
  const objects = {};
  for (const file of fs.readdirSync(path.join(DEPLOY, 'k8s')).filter((f) => f.endsWith('.yaml'))) {
    for (const doc of YAML.parseAllDocuments(fs.readFileSync(path.join(DEPLOY, 'k8s', file), 'utf8'))) {
      const obj = doc.toJS();
      const key = `${obj.apiVersion}/${obj.kind}`;
      if (!kinds[key]) {
        check(false, `${file}: ${key} has no schema here`);
        continue;
      }
      const mod = await import(kinds[key]);
      const Model = mod[obj.kind];
      try {
        new Model(obj).validate();
        check(true, `${file}: ${key} ${obj.metadata.name} is valid against the Kubernetes schema`);
      } catch (e) {
        check(false, `${file}: ${key}: ${e.message}`);
      }
      objects[obj.kind] = obj;
    }
  }
  const d = objects.Deployment;
  const c = d?.spec?.template?.spec?.containers?.[0];
  for (const probe of ['readinessProbe', 'livenessProbe'])
    check(c?.[probe]?.httpGet?.path === '/healthz', `the Deployment's ${probe} asks /healthz`);
  check(c?.args?.includes('--drain-s'), 'the Deployment drains on SIGTERM (--drain-s)');
  const m = objects.HorizontalPodAutoscaler?.spec?.metrics?.[0];
  check(['Pods', 'External'].includes(m?.type) && (m?.pods || m?.external)?.metric?.name === 'hlodr_queue_length',
    'the HPA scales on hlodr_queue_length');
  check(objects.Service?.spec?.selector?.['app.kubernetes.io/name'] === d?.spec?.selector?.matchLabels?.['app.kubernetes.io/name'],
    'the Service selects the Deployment\'s pods');
}

fs.rmSync(tmp, { recursive: true, force: true });
process.exit(failures.length ? 1 : 0);
