// The scene's 3D Tiles export (POST /api/scenes/{id}/export-3dtiles): a button, the job's
// progress, and once it is done the tileset.json URL a viewer loads (CesiumJS,
// 3DTilesRendererJS), ready to copy, and the whole tileset as a ZIP.

import { api } from './api.js';
import { el, formatMiB } from './dom.js';

const ACTIVE = new Set(['queued', 'running']);
const POLL_MS = 1000;

export class ExportPanel {
  // button: "Export 3D Tiles"; status: where the export shows; scene(): the picked store;
  // onStarted(): the jobs list refreshes; onError(error, key), onRecovered(key): the error bar.
  constructor(button, status, { scene, onStarted, onError, onRecovered }) {
    this.button = button;
    this.status = status;
    this.scene = scene;
    this.onStarted = onStarted;
    this.onError = onError;
    this.onRecovered = onRecovered;
    this.latest = new Map(); // scene id -> its latest export job
    this.timer = 0;
    button.addEventListener('click', () => this.start());
  }

  async start() {
    const scene = this.scene();
    if (!scene) return this.onError(new Error('no scene to export'), 'export');
    this.button.disabled = true;
    try {
      const job = await api.exportTiles(scene.id);
      this.onRecovered('export');
      this.latest.set(scene.id, job);
      this.onStarted();
      this.show();
    } catch (e) {
      this.onError(e, 'export');
    } finally {
      this.button.disabled = false;
    }
  }

  // Shows the picked scene's latest export, and follows it while it runs.
  show() {
    clearTimeout(this.timer);
    const scene = this.scene();
    const job = scene && this.latest.get(scene.id);
    this.render(job);
    if (!job || !ACTIVE.has(job.state)) return;
    this.timer = setTimeout(async () => {
      try {
        this.latest.set(job.scene, await api.job(job.id));
        this.onRecovered('export');
      } catch (e) {
        this.onError(e, 'export');
        if (e.status === 404) this.latest.delete(job.scene); // removed meanwhile
      }
      if (!ACTIVE.has((this.latest.get(job.scene) || {}).state)) this.onStarted();
      this.show();
    }, POLL_MS);
  }

  render(job) {
    if (!job) {
      this.status.replaceChildren();
      return;
    }
    const head = el('div', { class: 'export-head' },
      el('span', { class: `state ${job.state}`, 'data-export': job.id }, job.state),
      el('span', { class: 'sub' }, job.id));
    if (ACTIVE.has(job.state)) {
      const progress = Math.round((job.progress || 0) * 100);
      this.status.replaceChildren(head,
        el('div', { class: 'progress' }, el('i', { style: `width: ${progress}%` })),
        el('div', { class: 'sub' }, job.doing || 'waiting for a job runner'));
      return;
    }
    if (job.state !== 'done') {
      this.status.replaceChildren(head, job.error ? el('div', { class: 'job-error' }, job.error) : null);
      return;
    }
    const out = job.outputs || {};
    const result = job.result || {};
    const url = new URL(out.tileset, window.location.href).href;
    const field = el('input', { id: 'export-url', type: 'text', readonly: true, value: url,
      title: 'the tileset URL: load it in CesiumJS or 3DTilesRendererJS',
      onfocus: (e) => e.target.select() });
    const copy = el('button', { type: 'button', class: 'copy', title: 'copy the URL',
      onclick: () => this.copy(field, copy) }, 'Copy');
    this.status.replaceChildren(head,
      el('div', { class: 'sub' },
        `${result.tiles} tiles · ${result.files} files · ${formatMiB(result.bytes)}` +
        (result.geoReferenced ? ' · on the globe' : '')),
      el('div', { class: 'export-url' }, field, copy),
      el('div', { class: 'sub' }, 'load this URL in CesiumJS (Cesium3DTileset.fromUrl) or 3DTilesRendererJS (new TilesRenderer(url))'),
      el('div', { class: 'export-links' },
        el('a', { id: 'export-zip', href: out.zip, download: `${job.id}-3dtiles.zip` }, 'Download ZIP'),
        el('a', { href: out.tileset, target: '_blank', rel: 'noopener' }, 'open tileset.json')));
  }

  // The clipboard API where the page may use it (a secure origin); else the selected text is
  // there for Ctrl+C.
  async copy(field, button) {
    field.select();
    try {
      await navigator.clipboard.writeText(field.value);
      button.textContent = 'Copied';
    } catch {
      button.textContent = 'Ctrl+C';
    }
    setTimeout(() => (button.textContent = 'Copy'), 1500);
  }
}
