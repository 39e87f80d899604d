// Following one path job: its event stream feeds the dashboard charts, and its frames play in
// the job's player as they arrive (one image request at a time, the newest frame wins). Once
// the job ends, the slider and the play button go through its frames again.

import { api } from './api.js';
import { el, formatMiB, formatMs } from './dom.js';

const FINAL_STATES = new Set(['done', 'failed', 'cancelled']);
const REOPEN_MS = 2000;

export class JobView {
  // parts: {title, state, summary, image, slider, play, caption}; dashboard: charts.Dashboard;
  // onError(error, key), onRecovered(key): the error bar; onStateChange(): the jobs list refreshes.
  constructor(parts, dashboard, { onError, onRecovered, onStateChange }) {
    this.parts = parts;
    this.dashboard = dashboard;
    this.onError = onError;
    this.onRecovered = onRecovered;
    this.reopenTimer = 0;
    this.onStateChange = onStateChange;
    this.job = null;
    this.events = null;
    this.received = -1; // highest frame index received (a reconnect replays from the start)
    this.framesDone = 0;
    this.state = null;
    this.live = true; // the player follows the newest frame
    this.player = { inFlight: false, wanted: -1, shown: -1, url: null, timer: 0 };
    this.framesShown = 0;

    parts.slider.addEventListener('input', () => {
      const n = Number(parts.slider.value);
      this.live = n >= this.framesDone - 1 && !FINAL_STATES.has(this.state);
      this.stopPlaying();
      this.showFrame(n);
    });
    parts.play.addEventListener('click', () => (this.player.timer ? this.stopPlaying() : this.play()));
  }

  // Shows a job (the object of the API): resets the charts and follows its event stream, which
  // first replays the frames so far.
  follow(job, levelCount) {
    this.close();
    this.job = job;
    this.received = -1;
    this.framesDone = 0;
    this.state = job.state;
    this.live = true;
    this.player.wanted = -1;
    this.player.shown = -1;
    this.dashboard.reset(levelCount);
    this.parts.image.removeAttribute('src');
    this.parts.slider.max = 0;
    this.parts.slider.value = 0;
    this.renderHeader(job.summary);
    this.open();
  }

  open() {
    const events = new EventSource(api.jobEventsUrl(this.job.id));
    this.events = events;
    events.addEventListener('open', () => this.onRecovered('events'));
    events.addEventListener('frame', (e) => this.frameEvent(JSON.parse(e.data)));
    events.addEventListener('state', (e) => {
      const d = JSON.parse(e.data);
      this.state = d.state;
      this.renderHeader();
      this.onStateChange();
    });
    events.addEventListener('end', (e) => {
      const d = JSON.parse(e.data);
      this.state = d.state;
      this.live = false;
      events.close(); // the stream is over; EventSource would otherwise reconnect
      this.events = null;
      this.renderHeader(d.summary);
      this.onStateChange();
    });
    events.addEventListener('error', () => {
      // While CONNECTING the browser retries by itself; CLOSED means it gave up: the server
      // refused the stream (503 when too many are open, 404 for a removed job).
      if (events.readyState === EventSource.CLOSED && this.events === events) {
        this.events = null;
        this.reopenLater();
      }
    });
  }

  // After a refused stream: says so, and tries again while the job is still there (the replay
  // brings the frames missed meanwhile; frameEvent drops those it has).
  async reopenLater() {
    const job = this.job;
    try {
      await api.job(job.id);
    } catch (e) {
      this.onError(e, 'events'); // e.g. the job was removed
      return;
    }
    if (this.job !== job) return;
    this.onError(new Error(`the event stream of job ${job.id} was refused (is the server busy?); trying again`), 'events');
    this.reopenTimer = setTimeout(() => {
      if (this.job === job) this.open();
    }, REOPEN_MS);
  }

  close() {
    clearTimeout(this.reopenTimer);
    if (this.events) this.events.close();
    this.events = null;
    this.stopPlaying();
  }

  frameEvent(record) {
    if (record.index <= this.received) return; // replayed after a reconnect
    this.received = record.index;
    this.framesDone = record.index + 1;
    this.dashboard.add(record);
    this.parts.slider.max = Math.max(0, this.framesDone - 1);
    if (this.live) {
      this.parts.slider.value = record.index;
      this.showFrame(record.index);
    }
    this.renderCaption();
  }

  // Asks for frame n; while a request is in flight only the newest wish is kept.
  async showFrame(n) {
    this.player.wanted = n;
    if (this.player.inFlight) return;
    const job = this.job;
    while (this.player.wanted !== this.player.shown && this.job === job) {
      const want = this.player.wanted;
      this.player.inFlight = true;
      try {
        const frame = await api.jobFrame(job.id, want);
        if (this.job !== job) break;
        if (this.player.url) URL.revokeObjectURL(this.player.url);
        this.player.url = URL.createObjectURL(frame.blob);
        this.parts.image.src = this.player.url;
        this.player.shown = want;
        // Counted once decoded: until then the image has no size (a newer frame may replace it first).
        await this.parts.image.decode().then(() => this.framesShown++, () => {});
        this.renderCaption();
      } catch (e) {
        this.onError(e, 'job-frame');
        this.player.shown = want; // do not ask again for a frame that failed
      } finally {
        this.player.inFlight = false;
      }
    }
  }

  // Plays the rendered frames from the slider's position at the job's frame rate.
  play() {
    if (this.framesDone === 0) return;
    let n = Number(this.parts.slider.value);
    if (n >= this.framesDone - 1) n = 0;
    this.live = false;
    const fps = (this.job.settings && this.job.settings.fps) || 30;
    this.parts.play.textContent = '❚❚';
    this.player.timer = setInterval(() => {
      if (n >= this.framesDone) {
        this.stopPlaying();
        return;
      }
      this.parts.slider.value = n;
      // Skips frames rather than falling behind when images come slower than fps.
      if (!this.player.inFlight) this.showFrame(n);
      n++;
    }, 1000 / fps);
  }

  stopPlaying() {
    clearInterval(this.player.timer);
    this.player.timer = 0;
    this.parts.play.textContent = '▶';
  }

  renderCaption() {
    const total = this.job.framesTotal || '?';
    const shown = this.player.shown >= 0 ? `frame ${this.player.shown + 1}` : 'no frame yet';
    this.parts.caption.textContent = `${shown} · ${this.framesDone} / ${total} rendered`;
  }

  renderHeader(summary) {
    const job = this.job;
    const path = job.settings && job.settings.path;
    const kind = path ? path.kind || 'keyframes' : '';
    this.parts.title.textContent = `${job.id} · ${job.scene} · ${kind}`;
    this.parts.state.textContent = this.state;
    this.parts.state.className = `state ${this.state}`;
    if (summary && summary.frames) {
      const s = summary;
      const pct = (v) => `${(v * 100).toFixed(1)}%`;
      const figures = [
        ['frames', s.frames, String],
        ['mean frame', s.meanGpuMs, (v) => `${formatMs(v)} ms`],
        ['median |error|', s.medianRelError, pct],
        ['over 1.25× target', s.shareOver125, pct],
        ['toggles/frame', s.togglesPerFrame, (v) => v.toFixed(2)],
        ['peak resident', s.peakResidentBytes, formatMiB],
      ];
      this.parts.summary.replaceChildren(
        ...figures
          .filter(([, v]) => Number.isFinite(v))
          .map(([name, v, format]) => el('span', {}, `${name} `, el('b', {}, format(v)))),
      );
    } else if (!summary) {
      // Keep what is there (a state change carries no summary).
    } else {
      this.parts.summary.replaceChildren();
    }
    this.renderCaption();
  }
}
