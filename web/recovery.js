// A viewing session that survives its server. Behind a load balancer (docs/deploy.md) a session
// lives on one server; when that server dies or drains away, its id answers 404 (the balancer
// sent it to another server), 502 (the server died under the request) or the balancer's own 503
// (no server reachable yet). The page then opens a new session with the same settings and asks
// again for the camera it wanted: the user sees one late frame, not an error.
//
// The page (viewer.js) and the load-balancer test (tests/deploy/) both use this module, so the
// test runs the page's own recovery.

// The server's own 503s whose session is fine: retry later on the same session.
const BUSY_CODES = new Set(['busy', 'gl_memory', 'too_many_connections']);

// True when an ApiError (api.js) means the session is gone with its server.
export function isLostSession(e) {
  if (!e || typeof e.status !== 'number') return false;
  if (e.status === 404 || e.status === 502 || e.status === 504) return true;
  if (e.status !== 503) return false;
  // A stopping server's 503 "busy": it will not serve this session again.
  if (e.code === 'busy' && /shutting down/.test(e.message)) return true;
  return !BUSY_CODES.has(e.code); // the balancer's 503 (no JSON body): no server for the id
}

// A fresh session id the client proposes (POST /api/sessions {"id"}): the balancer hashes it to
// pick the server, before the session exists. getRandomValues also works on plain http pages.
export function newSessionId() {
  const bytes = crypto.getRandomValues(new Uint8Array(8));
  return 'p' + Array.from(bytes, (b) => b.toString(16).padStart(2, '0')).join('');
}

const REOPEN_TRIES = 6;
const REOPEN_PAUSE_MS = 150;

// Asks for a frame of `session`; if the session was lost with its server, opens a new one with
// open() (the same settings; it returns the session, or null when the page no longer wants it)
// and asks again. Returns {session, frame, reopened}, or null when open() gave up. Errors that
// are not a lost session (bad request, busy) are thrown as they are.
export async function frameOrReopen(session, open, frame, sleep = defaultSleep) {
  if (session) {
    try {
      return { session, frame: await frame(session), reopened: false };
    } catch (e) {
      if (!isLostSession(e)) throw e;
    }
  }
  // The new session's server may be the next to be found dead (the balancer has not seen it
  // yet): a few quick tries before the error reaches the user.
  for (let tries = 1; ; tries++) {
    try {
      const fresh = await open();
      if (!fresh) return null;
      return { session: fresh, frame: await frame(fresh), reopened: Boolean(session) };
    } catch (e) {
      if (!isLostSession(e) || tries >= REOPEN_TRIES) throw e;
      await sleep(REOPEN_PAUSE_MS * tries);
    }
  }
}

function defaultSleep(ms) {
  return new Promise((resolve) => setTimeout(resolve, ms));
}
