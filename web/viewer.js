// The interactive frame view: one hlodr session per (scene, scene file, settings), frames drawn on
// a canvas, and the overlay of the last frame's statistics.
//
// Frame requests follow what a remote viewer does: at most one request in flight, and when it
// returns, the next one is for the camera as it is then (moves made meanwhile collapse into
// one frame, so no queue of stale frames builds up). While the camera moves the frames are
// real-time (`still: false`: what is resident now, under the budget, JPEG at a lower quality);
// once it has rested for REST_MS, one still frame (`still: true`: the front the budget buys,
// loaded first, at a higher quality). In `settled` mode every frame is a still one.

import { api } from './api.js';
import { OrbitCamera } from './camera.js';
import { el, formatCount, formatMs } from './dom.js';
import { frameOrReopen, newSessionId } from './recovery.js';

const REST_MS = 300;
const JPEG_QUALITY = { moving: 60, still: 90 };

export class Viewer {
  // canvas: where frames are drawn; overlay: the element the statistics go in;
  // onError(error, key) / onRecovered(key): for the page's error bar.
  constructor({ canvas, overlay, onError, onRecovered }) {
    this.canvas = canvas;
    this.context = canvas.getContext('2d');
    this.overlay = overlay;
    this.onError = onError;
    this.onRecovered = onRecovered;
    this.scene = null;
    this.sceneFile = null; // the name of the scene file drawn, null for the store's defaults
    this.settings = null;
    this.camera = null;
    this.cameraFromSession = false; // the next session's defaultCamera replaces the camera
    this.session = null;
    this.toClose = []; // sessions of older settings, closed when no request is in flight
    this.generation = 0; // bumped by configure(): answers of an older one are dropped
    this.inFlight = false;
    this.dirty = false; // the camera moved since the last request was sent
    this.wantStill = false; // the camera rests and its still frame is not sent yet
    this.restTimer = 0;
    this.framesShown = 0;
    this.stillFramesShown = 0;
    this.last = null; // {stats, timing, roundTripMs, still}
  }

  // Starts over with a scene (an entry of GET /api/scenes), one of its scene files (a name, or
  // null for the store's defaults) and settings {width, height, budgetMs, selector, ssePx,
  // memoryMb, occlusion, showOcclusion, mode}: the old session is closed and the next frame opens a new one. The camera is
  // kept when only the settings change; a new scene or scene file starts from the new session's
  // defaultCamera, which is the scene file's camera when it declares one.
  configure(scene, sceneFile, settings) {
    if (!this.scene || this.scene.id !== scene.id || this.sceneFile !== sceneFile) {
      // The store's camera until the session answers: the controls need a camera meanwhile.
      this.camera = new OrbitCamera(scene);
      this.cameraFromSession = true;
    }
    this.scene = scene;
    this.sceneFile = sceneFile;
    this.settings = settings;
    this.generation++;
    this.closeSession();
    this.cameraChanged();
  }

  // Closes the current session; one with a request in flight is closed once that returns (closing
  // it under the request would make the request fail with a 404).
  closeSession() {
    if (this.session) this.toClose.push(this.session);
    this.session = null;
    if (!this.inFlight) this.flushClosed();
  }

  // The page goes away: close the session now rather than let it hold a server slot until it
  // expires (keepalive lets the request outlive the page).
  closeOnUnload() {
    for (const old of [...this.toClose.splice(0), this.session].filter(Boolean)) api.deleteSessionOnUnload(old.id);
    this.session = null;
  }

  flushClosed() {
    for (const old of this.toClose.splice(0)) {
      // An expired session answers 404, which is what closing wants anyway.
      api.deleteSession(old.id).catch((e) => e.status !== 404 && this.onError(e, 'session'));
    }
  }

  // The camera moved: ask for a frame, and for a still one once it rests.
  cameraChanged() {
    this.dirty = true;
    this.wantStill = false;
    clearTimeout(this.restTimer);
    if (this.settings && this.settings.mode !== 'settled') {
      this.restTimer = setTimeout(() => {
        this.wantStill = true;
        this.pump();
      }, REST_MS);
    }
    this.pump();
  }

  // Sends the next request if none is in flight and there is something to ask for.
  async pump() {
    if (this.inFlight || !this.scene) return;
    let still;
    if (this.dirty) still = this.settings.mode === 'settled';
    else if (this.wantStill) still = true;
    else return;
    this.dirty = false;
    if (still) this.wantStill = false;
    this.inFlight = true;
    try {
      await this.requestFrame(still);
    } finally {
      this.inFlight = false;
    }
    this.flushClosed();
    this.pump();
  }

  async openSession(generation) {
    const s = this.settings;
    const session = await api.createSession({
      id: newSessionId(), // a load balancer routes by it (docs/deploy.md)
      scene: this.sceneFile || this.scene.id,
      width: s.width,
      height: s.height,
      budgetMs: s.budgetMs,
      selector: s.selector,
      ssePx: s.ssePx,
      memoryMb: s.memoryMb,
      occlusion: s.occlusion,
      showOcclusion: s.showOcclusion,
    });
    if (generation !== this.generation) {
      this.toClose.push(session); // the settings changed while it opened
      return false;
    }
    this.session = session;
    if (this.cameraFromSession) {
      // Only the first session of a scene (file) moves the camera: a session reopened after it
      // expired, or one for new settings, keeps the view where the user left it.
      this.cameraFromSession = false;
      this.camera = new OrbitCamera(this.scene, session.defaultCamera || this.scene.defaultCamera);
    }
    return true;
  }

  async requestFrame(still) {
    const generation = this.generation;
    try {
      // A session that expired (404) or was lost with its server (404, 502, the balancer's 503)
      // is opened again with the same settings, and the frame asked for the same camera.
      const answer = await frameOrReopen(
        this.session,
        async () => {
          this.session = null;
          return (await this.openSession(generation)) ? this.session : null;
        },
        (session) =>
          // The camera is read once the session is open: a new one may have just set it.
          api.sessionFrame(session.id, {
            camera: this.camera.toApi(),
            still,
            format: 'jpeg',
            quality: still ? JPEG_QUALITY.still : JPEG_QUALITY.moving,
          }),
      );
      if (!answer || generation !== this.generation) return;
      await this.show(answer.frame, still);
      this.onRecovered('frame');
    } catch (e) {
      if (generation !== this.generation) return;
      this.onError(e, 'frame');
      // Busy: try again when the server says so (the camera may have moved by then).
      if (e.status === 503) {
        setTimeout(() => {
          this.dirty = true;
          this.pump();
        }, Math.max(1, e.retryAfterS) * 1000);
      }
    }
  }

  async show(frame, still) {
    const bitmap = await createImageBitmap(frame.blob);
    if (this.canvas.width !== bitmap.width || this.canvas.height !== bitmap.height) {
      this.canvas.width = bitmap.width;
      this.canvas.height = bitmap.height;
    }
    this.context.drawImage(bitmap, 0, 0);
    bitmap.close();
    this.framesShown++;
    if (still) this.stillFramesShown++;
    this.last = { stats: frame.stats, timing: frame.timing, roundTripMs: frame.roundTripMs, still };
    this.renderOverlay();
  }

  renderOverlay() {
    const { stats, timing, roundTripMs, still } = this.last;
    const s = stats || {};
    const budget = s.targetMs || this.settings.budgetMs || 0;
    const ratio = budget > 0 && Number.isFinite(s.gpuMs) ? s.gpuMs / budget : NaN;
    const level = !(ratio > 1) ? 'ok' : ratio <= 1.25 ? 'warn' : 'over';
    const levels = s.nodesPerLevel || [];
    const parts = ['select', 'upload', 'draw', 'readback', 'encode'].filter((k) => k in timing);

    this.overlay.replaceChildren(
      el('div', { class: 'ov-main' },
        el('span', { class: `ov-ms ${level}` }, formatMs(s.gpuMs)), ' ms',
        s.sharedBy > 1
          ? el('span', {
            class: 'ov-of ov-shared',
            title: 'sessions asking for frames at once share one budget ' +
              '(serve --admission share): this frame was selected for its share',
          }, ` / ${formatMs(budget)} ms: the ${formatMs(s.budgetMs)} ms budget shared by ${s.sharedBy} sessions`)
          : el('span', { class: 'ov-of' }, ` / ${formatMs(budget)} ms budget`),
        el('span', { class: `ov-kind ${still ? 'still' : 'moving'}` }, still ? 'still' : 'real-time')),
      el('div', { class: 'ov-bar', title: 'frame time; the mark is the budget' },
        el('i', { class: level, style: `width: ${Math.min(100, (ratio || 0) * 50)}%` })),
      el('div', {}, `${formatCount(s.triangles)} triangles · ${this.settings.selector}`),
      s.occlusion
        ? el('div', { class: 'ov-occlusion', title: 'occlusion culling: nodes hidden behind what was drawn' },
          `${formatCount(s.occludedNodes)} nodes occluded (${formatCount(s.occludedTriangles)} triangles) · ` +
          `${formatCount(s.occlusionQueries)} queries · ${formatMs(s.occlusionMs)} ms`)
        : null,
      el('div', { class: 'ov-levels', title: 'nodes drawn per HLOD level' },
        'nodes per level ',
        s.cellNodes ? el('span', {}, el('span', { class: 'ov-level' }, 'cells'), ` ${s.cellNodes}`) : '',
        levels.map((n, i) => el('span', {}, el('span', { class: 'ov-level' }, `L${i}`), ` ${n}`))),
      el('div', { class: 'ov-timing' },
        `server ${formatMs(timing.total)} ms · round trip ${formatMs(roundTripMs)} ms`),
      parts.length
        ? el('div', { class: 'ov-timing' }, parts.map((k) => `${k} ${formatMs(timing[k])}`).join(' · '))
        : null,
    );
  }
}
