// The HTTP API of `hlodr serve` (docs/api.md), as small async functions. Every failure becomes an
// ApiError carrying the server's `error.message`, so that callers can show it as it is.

export class ApiError extends Error {
  constructor(status, code, message, retryAfterS = 0) {
    super(message);
    this.name = 'ApiError';
    this.status = status; // HTTP status, 0 when the server could not be reached
    this.code = code; // the API's error code (bad_request, not_found, busy, ...)
    this.retryAfterS = retryAfterS; // from Retry-After on 503 busy, else 0
  }
}

// Turns a non-2xx response into an ApiError, using the JSON error body when there is one.
async function errorFrom(response) {
  const retryAfterS = Number(response.headers.get('Retry-After')) || 0;
  let code = `http_${response.status}`;
  let message = `${response.status} ${response.statusText || 'error'} from ${new URL(response.url).pathname}`;
  try {
    const body = await response.json();
    if (body && body.error) {
      code = body.error.code || code;
      message = body.error.message || message;
    }
  } catch {
    // Not JSON (a proxy's page, say): the status line is all we have.
  }
  return new ApiError(response.status, code, message, retryAfterS);
}

// Where the API is: the page's own origin (''), or for a client outside a browser (the load
// balancer test) an absolute URL set with setApiBase.
let apiBase = '';
export function setApiBase(url) {
  apiBase = url.replace(/\/$/, '');
}

async function send(method, path, body) {
  const init = { method, headers: {} };
  if (body !== undefined) {
    init.headers['Content-Type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(apiBase + path, init);
  } catch (e) {
    const why = e.cause && e.cause.code ? ` (${e.cause.code})` : ''; // node's fetch: ECONNRESET, ...
    throw new ApiError(0, 'network', `cannot reach the hlodr server (${method} ${path}): ${e.message}${why}`);
  }
  if (!response.ok) throw await errorFrom(response);
  return response;
}

async function json(method, path, body) {
  const response = await send(method, path, body);
  return response.status === 204 ? null : response.json();
}

// "queue;dur=0.2, draw;dur=21.3" -> {queue: 0.2, draw: 21.3}
export function parseServerTiming(header) {
  const out = {};
  for (const part of (header || '').split(',')) {
    const [name, ...params] = part.trim().split(';');
    const dur = params.map((p) => p.trim()).find((p) => p.startsWith('dur='));
    if (name && dur) out[name] = Number(dur.slice(4));
  }
  return out;
}

// A frame response: the image and its statistics (X-Hlodr-Stats, Server-Timing).
async function frame(method, path, body) {
  const started = performance.now();
  const response = await send(method, path, body);
  const blob = await response.blob();
  let stats = null;
  try {
    stats = JSON.parse(response.headers.get('X-Hlodr-Stats') || 'null');
  } catch {
    stats = null; // a frame without readable stats still shows
  }
  return {
    blob,
    stats,
    timing: parseServerTiming(response.headers.get('Server-Timing')),
    roundTripMs: performance.now() - started,
  };
}

export const api = {
  health: () => json('GET', '/healthz'),
  scenes: () => json('GET', '/api/scenes').then((r) => r.scenes),

  createSession: (body) => json('POST', '/api/sessions', body),
  sessionFrame: (id, body) => frame('POST', `/api/sessions/${encodeURIComponent(id)}/frame`, body),
  deleteSession: (id) => json('DELETE', `/api/sessions/${encodeURIComponent(id)}`),
  // For a page that is going away: fire and forget, the request outlives the page.
  deleteSessionOnUnload: (id) =>
    fetch(`/api/sessions/${encodeURIComponent(id)}`, { method: 'DELETE', keepalive: true }).catch(() => {}),

  jobs: () => json('GET', '/api/jobs').then((r) => r.jobs),
  job: (id) => json('GET', `/api/jobs/${encodeURIComponent(id)}`),
  createJob: (body) => json('POST', '/api/jobs', body),
  // Cancels a queued or running job; removes a finished one with its files.
  deleteJob: (id) => json('DELETE', `/api/jobs/${encodeURIComponent(id)}`),
  jobFrame: (id, n) => frame('GET', `/api/jobs/${encodeURIComponent(id)}/frames/${n}`),
  jobEventsUrl: (id) => `/api/jobs/${encodeURIComponent(id)}/events`,

  // A 3D Tiles export of a store: a job of kind "export" (GET /api/jobs/{id} follows it).
  exportTiles: (sceneId) => json('POST', `/api/scenes/${encodeURIComponent(sceneId)}/export-3dtiles`, {}),

  studies: () => json('GET', '/api/studies').then((r) => r.studies),
  createStudy: (body) => json('POST', '/api/studies', body),
  deleteStudy: (id) => json('DELETE', `/api/studies/${encodeURIComponent(id)}`),
};
