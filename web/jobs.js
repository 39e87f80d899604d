// The jobs list (GET /api/jobs, refreshed while any job runs): progress, the outputs of a finished
// job (MP4, stats CSV and JSON, straight from the API; an export's tileset.json and ZIP), cancel
// for a running one.

import { api } from './api.js';
import { el } from './dom.js';

const ACTIVE = new Set(['queued', 'running']);
const REFRESH_ACTIVE_MS = 1000;
const REFRESH_IDLE_MS = 5000;

// The store a job ran on, and the scene file when it ran with one.
function sceneLabel(job) {
  const file = job.settings && job.settings.sceneFile;
  return file ? `${job.scene} (${file})` : job.scene;
}

export class JobsList {
  // body: the table's <tbody>; onShow(job): follow a job in the dashboard; onError(error, key).
  constructor(body, { onShow, onError, onRecovered }) {
    this.body = body;
    this.onShow = onShow;
    this.onError = onError;
    this.onRecovered = onRecovered;
    this.jobs = [];
    this.timer = 0;
    this.loading = null;
  }

  // Reloads the list now, then again after a while (sooner while a job is active).
  refresh() {
    clearTimeout(this.timer);
    if (!this.loading) {
      this.loading = api
        .jobs()
        .then((jobs) => {
          this.jobs = jobs;
          this.render();
          this.onRecovered('jobs');
        })
        .catch((e) => this.onError(e, 'jobs'))
        .finally(() => {
          this.loading = null;
          const active = this.jobs.some((j) => ACTIVE.has(j.state));
          this.timer = setTimeout(() => this.refresh(), active ? REFRESH_ACTIVE_MS : REFRESH_IDLE_MS);
        });
    }
    return this.loading;
  }

  async remove(job) {
    try {
      await api.deleteJob(job.id);
    } catch (e) {
      this.onError(e, 'jobs');
    }
    this.refresh();
  }

  render() {
    if (this.jobs.length === 0) {
      this.body.replaceChildren(el('tr', {}, el('td', { colspan: 4, class: 'empty' }, 'no jobs yet')));
      return;
    }
    this.body.replaceChildren(...this.jobs.map((job) => this.row(job)));
  }

  // The remove or cancel button of a row.
  action(job) {
    return ACTIVE.has(job.state)
      ? el('button', { class: 'cancel', title: 'stop the job', onclick: () => this.remove(job) }, 'Cancel')
      : el('button', { class: 'remove', title: 'delete the job and its files', onclick: () => this.remove(job) }, '✕');
  }

  // A 3D Tiles export: no frames to show in the dashboard; its tileset and ZIP once done.
  exportRow(job) {
    const progress = Math.round((job.progress || 0) * 100);
    const out = job.outputs || {};
    const links = [];
    if (out.tileset) links.push(el('a', { href: out.tileset, target: '_blank', rel: 'noopener' }, 'tileset'));
    if (out.zip) links.push(el('a', { href: out.zip, download: `${job.id}-3dtiles.zip` }, 'ZIP'));
    const result = job.result || {};
    return el('tr', { 'data-job': job.id, 'data-state': job.state },
      el('td', {},
        el('span', { class: 'id' }, job.id),
        el('div', { class: 'sub' }, `${job.scene} · 3D Tiles export`)),
      el('td', {},
        el('span', { class: `state ${job.state}` }, job.state),
        el('div', { class: 'progress' }, el('i', { style: `width: ${progress}%` })),
        el('div', { class: 'sub' }, job.state === 'done' ? `${result.tiles} tiles` : job.doing || ''),
        job.state === 'failed' && job.error ? el('div', { class: 'job-error' }, job.error) : null),
      el('td', { class: 'outputs' }, links.length ? links : el('span', { class: 'sub' }, '–')),
      el('td', {}, this.action(job)),
    );
  }

  row(job) {
    if (job.kind === 'export') return this.exportRow(job);
    const path = (job.settings && job.settings.path) || {};
    const progress = Math.round((job.progress || 0) * 100);
    const out = job.outputs || {};
    const links = [];
    if (job.state === 'done' && out.video) links.push(el('a', { href: out.video, download: `${job.id}.mp4` }, 'MP4'));
    if (job.framesDone > 0 && out.statsCsv) links.push(el('a', { href: out.statsCsv, download: `${job.id}-stats.csv`, class: 'csv' }, 'CSV'));
    if (job.framesDone > 0 && out.statsJson) links.push(el('a', { href: out.statsJson, target: '_blank', rel: 'noopener' }, 'JSON'));
    // Per-frame timing for Perfetto UI or chrome://tracing (docs/api.md).
    if (job.framesDone > 0 && out.trace) links.push(el('a', { href: out.trace, download: `${job.id}.trace.json`, class: 'trace', title: 'per-frame timing: open in ui.perfetto.dev or chrome://tracing' }, 'trace'));
    const action = this.action(job);
    if (ACTIVE.has(job.state)) action.title = 'stop after the current frame';
    return el('tr', { 'data-job': job.id, 'data-state': job.state },
      el('td', {},
        el('button', { class: 'link', title: 'show in the dashboard', onclick: () => this.onShow(job) }, job.id),
        el('div', { class: 'sub' }, `${sceneLabel(job)} · ${path.kind || 'keyframes'}`)),
      el('td', {},
        el('span', { class: `state ${job.state}` }, job.state),
        el('div', { class: 'progress' }, el('i', { style: `width: ${progress}%` })),
        el('div', { class: 'sub' }, `${job.framesDone} / ${job.framesTotal}`),
        job.state === 'failed' && job.error ? el('div', { class: 'job-error' }, job.error) : null),
      el('td', { class: 'outputs' }, links.length ? links : el('span', { class: 'sub' }, '–')),
      el('td', {}, action),
    );
  }
}
