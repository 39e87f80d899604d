// The error bar under the header: every failure the page meets is shown here with the API's
// message, one line per kind of failure (a repeated one counts up instead of piling up), until
// it is dismissed or the same kind of request succeeds again.

import { el } from './dom.js';

export class ErrorBar {
  constructor(container) {
    this.container = container;
    this.lines = new Map(); // key -> {node, count, message}
  }

  // Shows error (an ApiError or any Error) under key, e.g. 'frame', 'jobs'.
  show(error, key = 'page') {
    const message = error && error.message ? error.message : String(error);
    const status = error && error.status ? ` (${error.status} ${error.code})` : '';
    const text = `${message}${status}`;
    const line = this.lines.get(key);
    if (line && line.text === text) {
      line.count++;
      line.node.querySelector('.count').textContent = `×${line.count}`;
      return;
    }
    if (line) line.node.remove();
    const node = el('div', { class: 'error', 'data-key': key },
      el('span', { class: 'what' }, key),
      el('span', { class: 'message' }, text),
      el('span', { class: 'count' }),
      el('button', { title: 'dismiss', onclick: () => this.clear(key) }, '✕'));
    this.container.append(node);
    this.lines.set(key, { node, count: 1, text });
  }

  clear(key) {
    const line = this.lines.get(key);
    if (!line) return;
    line.node.remove();
    this.lines.delete(key);
  }

  messages() {
    return [...this.lines.values()].map((l) => l.text);
  }
}
