// Accuracy studies (POST /api/studies): a small form, the list with progress, and the finished
// study's report (its index.html, served by hlodr) one click away.

import { api } from './api.js';
import { el } from './dom.js';

const ACTIVE = new Set(['queued', 'running']);

// "8, 16,33" -> [8, 16, 33]; an empty or malformed entry is an Error naming the field.
function numbers(text, field) {
  const parts = text.split(',').map((s) => s.trim()).filter((s) => s.length);
  const values = parts.map(Number);
  if (!values.length || values.some((v) => !Number.isFinite(v) || v <= 0))
    throw new Error(`${field}: give positive numbers separated by commas`);
  return values;
}

export class StudiesPanel {
  // form: the study <form>; body: the list's <tbody>; scene(): the current scene; size(): [w, h].
  constructor(form, body, { scene, onError, onRecovered }) {
    this.form = form;
    this.body = body;
    this.scene = scene;
    this.onError = onError;
    this.onRecovered = onRecovered;
    this.studies = [];
    this.timer = 0;
    form.addEventListener('submit', (e) => this.start(e));
  }

  async start(event) {
    event.preventDefault();
    const scene = this.scene();
    if (!scene) return this.onError(new Error('no scene to study'), 'study');
    const f = this.form.elements;
    const selectors = ['lakhia', 'sse', 'fs'].filter((s) => f[`use-${s}`].checked);
    let body;
    try {
      body = {
        scene: scene.id,
        path: { kind: f['study-path'].value },
        frames: Number(f['study-frames'].value),
        budgets: numbers(f['study-budgets'].value, 'budgets'),
        ssePx: numbers(f['study-sse-px'].value, 'SSE thresholds'),
        selectors,
        width: 640,
        height: 360,
      };
    } catch (e) {
      return this.onError(e, 'study');
    }
    const button = f['start-study'];
    button.disabled = true;
    try {
      await api.createStudy(body);
      this.onRecovered('study');
    } catch (e) {
      this.onError(e, 'study');
    } finally {
      button.disabled = false;
      this.refresh();
    }
  }

  refresh() {
    clearTimeout(this.timer);
    return api
      .studies()
      .then((list) => {
        this.studies = list;
        this.render();
        this.onRecovered('studies');
      })
      .catch((e) => this.onError(e, 'studies'))
      .finally(() => {
        const active = this.studies.some((s) => ACTIVE.has(s.state));
        this.timer = setTimeout(() => this.refresh(), active ? 1000 : 5000);
      });
  }

  async remove(study) {
    try {
      await api.deleteStudy(study.id);
    } catch (e) {
      this.onError(e, 'studies');
    }
    this.refresh();
  }

  render() {
    if (!this.studies.length) {
      this.body.replaceChildren(el('tr', {}, el('td', { colspan: 3, class: 'empty' }, 'no studies yet')));
      return;
    }
    this.body.replaceChildren(...this.studies.map((s) => this.row(s)));
  }

  row(study) {
    const progress = Math.round((study.progress || 0) * 100);
    const report = study.outputs && study.outputs.report;
    return el('tr', { 'data-study': study.id, 'data-state': study.state },
      el('td', {},
        report ? el('a', { href: report, target: '_blank', rel: 'noopener' }, 'report') : study.id,
        el('div', { class: 'sub' }, `${study.scene} · ${(study.settings.path && study.settings.path.kind) || 'keyframes'}`)),
      el('td', {},
        el('span', { class: `state ${study.state}` }, study.state),
        el('div', { class: 'progress' }, el('i', { style: `width: ${progress}%` })),
        el('div', { class: 'sub' }, ACTIVE.has(study.state) ? study.doing || '' : `${study.settings.frames} frames`),
        study.state === 'failed' && study.error ? el('div', { class: 'job-error' }, study.error) : null),
      el('td', {},
        el('button', {
          class: ACTIVE.has(study.state) ? 'cancel' : 'remove',
          title: ACTIVE.has(study.state) ? 'stop the study' : 'delete the study and its report',
          onclick: () => this.remove(study),
        }, ACTIVE.has(study.state) ? 'Cancel' : '✕')),
    );
  }
}
