// hlodr's page: wires the scene pickers (a store, and one of its scene files or the store's
// defaults), the settings, the interactive view, the path runner, the jobs list and the dashboard
// to each other. Each of those lives in its own module.

import { api } from './api.js';
import { Dashboard } from './charts.js';
import { ViewControls } from './controls.js';
import { formatCount } from './dom.js';
import { ErrorBar } from './errors.js';
import { ExportPanel } from './exports.js';
import { JobsList } from './jobs.js';
import { JobView } from './jobview.js';
import { StudiesPanel } from './studies.js';
import { Viewer } from './viewer.js';

const $ = (selector) => document.querySelector(selector);
const FIT_MAX = 960; // "fit the view": the frame's long side in pixels at most
const REFIT_MS = 400; // "fit the view": wait for the resize to settle before a new session

const errors = new ErrorBar($('#errors'));
const onError = (error, key) => errors.show(error, key);
const onRecovered = (key) => errors.clear(key);
window.addEventListener('unhandledrejection', (e) => errors.show(e.reason, 'page'));
window.addEventListener('error', (e) => errors.show(e.error || e.message, 'page'));

let scenes = [];
let scene = null; // the picked store: an entry of GET /api/scenes

const viewElement = $('#view');
const viewer = new Viewer({ canvas: $('#frame'), overlay: $('#overlay'), onError, onRecovered });
new ViewControls(viewElement, () => viewer.camera, () => viewer.cameraChanged());

const dashboard = new Dashboard({
  frameTime: $('#chart-frame-time'),
  levels: $('#chart-levels'),
  toggles: $('#chart-toggles'),
  memory: $('#chart-memory'),
  loads: $('#chart-loads'),
});
const jobView = new JobView(
  {
    title: $('#job-title'),
    state: $('#job-state'),
    summary: $('#job-summary'),
    image: $('#job-frame'),
    slider: $('#job-slider'),
    play: $('#job-play'),
    caption: $('#job-caption'),
  },
  dashboard,
  { onError, onRecovered, onStateChange: () => jobsList.refresh() },
);
const jobsList = new JobsList($('#jobs'), {
  onShow: (job) => jobView.follow(job, levelsOf(job.scene)),
  onError,
  onRecovered,
});

const exportPanel = new ExportPanel($('#export-tiles'), $('#export-status'), {
  scene: () => scene,
  onStarted: () => jobsList.refresh(),
  onError,
  onRecovered,
});

function levelsOf(sceneId) {
  const s = scenes.find((x) => x.id === sceneId);
  return s ? s.levels : 1;
}

// An optional number field: undefined when empty (the server's default), else its number; a
// value out of range goes to the server as it is, and its 400 message says what is allowed.
function numberField(selector) {
  const text = $(selector).value.trim();
  return text === '' ? undefined : Number(text);
}

// The frame size for "fit the view": the view's shape, the long side at most FIT_MAX, even sides
// (an MP4 needs them).
function fitSize() {
  const w = Math.max(viewElement.clientWidth, 16);
  const h = Math.max(viewElement.clientHeight, 16);
  const s = Math.min(1, FIT_MAX / Math.max(w, h));
  const even = (v) => Math.max(16, 2 * Math.round((v * s) / 2));
  return [even(w), even(h)];
}

function readSettings() {
  const size = $('#size').value;
  const [width, height] = size === 'fit' ? fitSize() : size.split('x').map(Number);
  const selector = $('#selector').value;
  return {
    width,
    height,
    budgetMs: numberField('#budget'),
    selector,
    ssePx: selector === 'sse' ? numberField('#sse-px') : undefined,
    memoryMb: numberField('#memory'),
    occlusion: $('#occlusion').value,
    showOcclusion: $('#show-occlusion').checked,
    mode: $('#mode').value,
  };
}

// The picked scene file's name, or null for the store's defaults.
function sceneFile() {
  return $('#look').value || null;
}

// What a session or a job gets as its `scene`: the scene file when one is picked (its effects
// and camera), else the store id. Studies take a store id only, and keep sending scene.id.
function sceneRef() {
  return sceneFile() || scene.id;
}

function applySettings() {
  $('#sse-row').hidden = $('#selector').value !== 'sse';
  if (scene) viewer.configure(scene, sceneFile(), readSettings());
}

// The scene files of the picked store, after "store defaults", each with the effects it
// declares (what it costs to draw); the pick goes back to the store's defaults.
function offerSceneFiles(files) {
  const picker = $('#look');
  const label = (f) => `${f.name} · ${f.effects.length ? f.effects.join(', ') : 'no effects'}`;
  picker.replaceChildren(new Option('store defaults', ''), ...files.map((f) => new Option(label(f), f.name)));
  picker.value = '';
  picker.disabled = files.length === 0;
}

// Walk-fly and drive follow a z-up street grid (the API refuses them elsewhere); the catwalk
// walk and the fly-around are for CAD scenes (mesh and glTF stores, not z-up), which start on the
// catwalk walk. The orbit is offered everywhere.
const cityKinds = ['walk-fly', 'drive', 'orbit'];
const sceneKinds = ['catwalk', 'fly-around', 'orbit'];
function offerPathKinds(zUp) {
  const kinds = zUp ? cityKinds : sceneKinds;
  for (const select of [$('#path-kind'), document.querySelector('[name="study-path"]')]) {
    for (const option of select.options) option.disabled = !kinds.includes(option.value);
    if (select.selectedOptions[0] && select.selectedOptions[0].disabled) select.value = kinds[0];
  }
}

// Where a store came from (GET /api/scenes' `source`), in the scene picker: "mars (3D Tiles)".
const SOURCES = { '3d-tiles': '3D Tiles', city: 'city folder', cityjson: 'CityJSON', inputs: 'several inputs', mesh: 'mesh' };
const storeLabel = (s) => (SOURCES[s.source] ? `${s.id} (${SOURCES[s.source]})` : s.id);

function selectScene(id) {
  scene = scenes.find((s) => s.id === id) || null;
  if (!scene) return;
  exportPanel.show();
  offerPathKinds(!scene.up || scene.up[2] === 1);
  offerSceneFiles(scene.sceneFiles || []);
  const t = scene.triangles || {};
  $('#scene-info').textContent =
    `${formatCount(scene.nodes)} nodes · ${scene.levels} levels · ` +
    `${formatCount(t.input)} input triangles · ${formatCount(t.hlod0)} in hlod₀`;
  applySettings();
}

async function loadScenes() {
  try {
    scenes = await api.scenes();
  } catch (e) {
    onError(e, 'scenes');
    return;
  }
  const picker = $('#scene');
  picker.replaceChildren(...scenes.map((s) => new Option(storeLabel(s), s.id)));
  picker.disabled = scenes.length === 0;
  if (scenes.length === 0) {
    onError(new Error('the server has no scenes: its data folder holds no NAME.hlod/ store'), 'scenes');
    return;
  }
  selectScene(scenes[0].id);
}

async function startJob(event) {
  event.preventDefault();
  if (!scene) {
    onError(new Error('no scene to run a path on'), 'job');
    return;
  }
  const s = readSettings();
  const button = $('#start-job');
  button.disabled = true;
  try {
    const job = await api.createJob({
      scene: sceneRef(),
      path: { kind: $('#path-kind').value },
      fps: numberField('#fps'),
      frames: numberField('#frames'),
      video: $('#video').checked,
      width: s.width,
      height: s.height,
      budgetMs: s.budgetMs,
      selector: s.selector,
      ssePx: s.ssePx,
      mode: s.mode,
      memoryMb: s.memoryMb,
      occlusion: s.occlusion,
    });
    errors.clear('job');
    jobView.follow(job, scene.levels);
    jobsList.refresh();
  } catch (e) {
    onError(e, 'job');
  } finally {
    button.disabled = false;
  }
}

async function showHealth() {
  try {
    const h = await api.health();
    $('#health').textContent = `server ${h.status} · ${h.workers} render worker${h.workers === 1 ? '' : 's'}`;
  } catch (e) {
    onError(e, 'health');
  }
}

$('#scene').addEventListener('change', (e) => selectScene(e.target.value));
$('#look').addEventListener('change', applySettings); // a new session, from the file's camera
$('#settings').addEventListener('change', applySettings);
$('#settings').addEventListener('submit', (e) => {
  e.preventDefault(); // Enter in a field: the change event already applied it
});
$('#runner').addEventListener('submit', startJob);
window.addEventListener('pagehide', () => viewer.closeOnUnload());

// "fit the view" follows the view's size, once the resizing has stopped.
let refitTimer = 0;
new ResizeObserver(() => {
  if ($('#size').value !== 'fit' || !scene || !viewer.settings) return;
  const [w, h] = fitSize();
  if (w === viewer.settings.width && h === viewer.settings.height) return;
  clearTimeout(refitTimer);
  refitTimer = setTimeout(applySettings, REFIT_MS);
}).observe(viewElement);

// Read-only state for the browser test (tests/web/page.test.mjs) and for a curious console.
window.hlodrDebug = Object.freeze({
  chartPoints: () => dashboard.points(),
  viewer: () => ({
    framesShown: viewer.framesShown,
    stillFramesShown: viewer.stillFramesShown,
    inFlight: viewer.inFlight,
    session: viewer.session && viewer.session.id,
    sceneFile: viewer.sceneFile,
    camera: viewer.camera && viewer.camera.toApi(),
    settings: viewer.settings && { ...viewer.settings },
    stats: viewer.last && viewer.last.stats,
  }),
  job: () => ({
    id: jobView.job && jobView.job.id,
    state: jobView.state,
    framesReceived: jobView.framesDone,
    framesShown: jobView.framesShown,
  }),
  errors: () => errors.messages(),
});

const studies = new StudiesPanel($('#study'), $('#studies'), {
  scene: () => scene,
  onError,
  onRecovered,
});

showHealth();
loadScenes();
jobsList.refresh();
studies.refresh();
