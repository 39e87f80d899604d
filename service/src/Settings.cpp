// The table of settings (service/Settings.h): one row per setting, read by the commands and the
// API, printed by --help and into docs/api.md.
#include "service/Settings.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace service {

namespace {

using K = Setting::Kind;

Setting row(std::string id, std::string cli, std::string api, K kind, double lo, double hi,
            std::string fallback, std::string metavar, std::string meaning, std::string where,
            std::vector<std::string> choices = {}) {
  Setting s;
  s.id = std::move(id);
  s.cli = std::move(cli);
  s.api = std::move(api);
  s.kind = kind;
  s.lo = lo;
  s.hi = hi;
  s.fallback = std::move(fallback);
  s.metavar = std::move(metavar);
  s.meaning = std::move(meaning);
  s.where = std::move(where);
  s.choices = std::move(choices);
  return s;
}

// Whole numbers in full (1000000, not 1e+06); others as %g.
std::string number(double v) {
  char buf[32];
  if (v == std::floor(v) && std::abs(v) < 1e15)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string joined(const std::vector<std::string>& items, const char* last) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? last : ", ";
    out += items[i];
  }
  return out;
}

std::vector<Setting> makeTable() {
  const char* jobs = "POST /api/jobs";
  const char* frames = "POST /api/render, /api/sessions, /api/jobs";
  return {
      // The frame and what draws it.
      row("width", "", "width", K::Integer, 16, 8192, "640", "", "frame width in pixels",
          "POST /api/render, /api/sessions, /api/jobs, /api/studies (at most --max-size)"),
      row("height", "", "height", K::Integer, 16, 8192, "360", "", "frame height in pixels",
          "POST /api/render, /api/sessions, /api/jobs, /api/studies (at most --max-size)"),
      row("size", "size", "", K::Size, 16, 8192, "1280x720", "WxH", "frame size in pixels",
          "render"),
      row("fov", "fov", "camera.fov", K::Number, 1, 170, "50", "DEG",
          "vertical field of view in degrees", "render, the camera of the API"),
      row("budgetMs", "budget-ms", "budgetMs", K::Number, 0.5, 10000, "33", "MS",
          "frame time budget in ms (the selector's c_targetTime)",
          std::string("render STORE, ") + frames),
      row("selector", "selector", "selector", K::Choice, 0, 0, "lakhia", "S",
          "the front selector: lakhia (the time budget), sse (a screen-space error), fs "
          "(Funkhouser-Sequin), full (every leaf, the reference) or vdr (view-dependent "
          "rendering of a store built with --vdr, under the budget)",
          std::string("render STORE, ") + frames, {"lakhia", "sse", "fs", "full", "vdr"}),
      row("ssePx", "", "ssePx", K::Number, 0.1, 1000, "16", "PX",
          "the sse selector's threshold in pixels (--params ssePixels=PX on the command line)",
          frames),
      row("memoryMb", "memory-mb", "memoryMb", K::Number, 0, 1e6, "0", "MB",
          "cap on the session's decoded node payloads in MB (0: none)",
          "render STORE, study, POST /api/sessions, /api/jobs"),
      row("occlusion", "occlusion", "occlusion", K::Choice, 0, 0, "auto", "on|off|auto",
          "occlusion culling with hardware queries (Manocha sec. 4): auto turns it on while the "
          "time its queries save exceeds the time they cost",
          std::string("render STORE, study, ") + frames, {"on", "off", "auto"}),
      row("gpuMb", "gpu-mb", "gpuMb", K::Number, 0, 1e6, "0", "MB",
          "GPU memory budget in MB: nodes out of the front are evicted least recently used "
          "first (0: none)",
          "render STORE, POST /api/sessions, /api/jobs"),
      row("predict", "", "predict", K::Flag, 0, 0, "off", "",
          "prefetch for the camera its recent motion predicts half a second ahead (Manocha sec. "
          "5.3; measured no better over a slow link, docs/results.md)",
          "POST /api/sessions"),
      row("showOcclusion", "show-occlusion", "showOcclusion", K::Flag, 0, 0, "off", "",
          "tint the boxes of the nodes occlusion culling hid (debug view)",
          "render STORE, POST /api/sessions"),
      row("mode", "mode", "mode", K::Choice, 0, 0, "realtime", "M",
          "realtime: never wait for loading (nodes not yet loaded are drawn coarser); settled: "
          "wait until the selected front is loaded (frames independent of I/O timing)",
          std::string("render --path, ") + jobs, {"realtime", "settled"}),
      row("frameMode", "mode", "mode", K::Choice, 0, 0, "settled", "M",
          "one frame: settled (the front the budget buys, loaded first) or realtime (what is "
          "resident now)",
          "render STORE --camera, POST /api/render", {"settled", "realtime"}),
      row("fps", "fps", "fps", K::Number, 0.1, 1000, "30", "N",
          "the path's sampling rate in frames per second",
          "render --path, study, POST /api/jobs, /api/studies"),
      row("frames", "frames", "frames", K::Integer, 1, 1e8, "", "N",
          "render only the first N frames of the path (default: all)",
          std::string("render --path, ") + jobs),
      row("segment", "segment", "", K::Text, 0, 0, "", "I/N",
          "render only segment I (from 0) of N of the path's frames, numbered as in the whole "
          "run, after a warm-up (docs/cli.md, Segments); join the parts with `hlodr concat`",
          "render --path"),
      row("warmup", "warmup", "", K::Integer, 0, 100000, "60", "W",
          "with --segment: frames rendered (not written) before the segment's first, so that "
          "the selector and the loader reach the state the whole run has there",
          "render --path"),
      row("segments", "", "segments", K::Integer, 1, 16, "1", "N",
          "split the path's frames into N segments rendered as separate tasks on the job "
          "workers (each with a warm-up), then joined: the job's files as for one run",
          jobs),
      row("prefetch", "prefetch", "prefetch", K::Flag, 0, 0, "off", "",
          "prefetch what the path needs 1 s ahead", std::string("render --path, ") + jobs),
      row("video", "", "video", K::Flag, 0, 0, "off", "",
          "also write an MP4 (needs an even width and height)", jobs),
      row("format", "", "format", K::Choice, 0, 0, "jpeg", "", "the image format of a frame",
          "POST /api/render, /api/sessions/{id}/frame", {"jpeg", "png"}),
      row("quality", "", "quality", K::Integer, 1, 100, "85", "", "JPEG quality",
          "POST /api/render, /api/sessions/{id}/frame"),
      row("still", "", "still", K::Flag, 0, 0, "off", "",
          "a settled frame (the front the budget buys, loaded first) instead of a real-time one",
          "POST /api/sessions/{id}/frame"),
      row("pathKind", "kind", "path.kind", K::Choice, 0, 0, "", "K",
          "a path generated for the store: walk-fly (a street-level walk rising into a "
          "fly-over, 35 s), drive (a loop along streets at 1.5 m), orbit (a circle around the "
          "up axis, framing the model, 30 s), facade (a slow walk at eye height past one street's "
          "facades, looking at them, 10 s), fly-around (a loop around the model's box, outside "
          "it, 40 s) or catwalk (a walk at eye height along a CAD scene's catwalks, found in its "
          "full-detail geometry, 40 s at most; docs/objects.md)",
          "path, study, POST /api/jobs, /api/studies",
          {"walk-fly", "drive", "orbit", "facade", "fly-around", "catwalk"}),
      row("duration", "duration", "path.duration", K::Number, 1, 1e6, "", "S",
          "stretch or shrink a generated path to S seconds (default: the kind's own length)",
          "path, POST /api/jobs, /api/studies"),
      // The command line's path runs only: the emulated link and the upload budget.
      row("ioMbps", "io-mbps", "", K::Number, 0, 1e7, "0", "X",
          "emulated link speed for loading in Mbit/s (0: unthrottled)", "render --path"),
      row("ioLatencyMs", "io-latency-ms", "", K::Number, 0, 1e5, "0", "Y",
          "emulated latency per request in ms (a read that goes on where the last one ended, "
          "as a node's next chunk, continues it)",
          "render --path"),
      row("ioRequests", "io-requests", "", K::Integer, 1, 1024, "4", "N",
          "requests in flight on the emulated link: the next N-1 nodes in priority order wait "
          "out their latency while one streams",
          "render --path"),
      row("uploadMs", "upload-ms", "", K::Number, 0, 1e5, "2", "MS",
          "per-frame GPU upload budget in ms", "render --path"),
      row("splats", "splats", "", K::Choice, 0, 0, "off", "on|off",
          "draw nodes smaller than splatPixels (4) on screen as their splats, where the store "
          "has them",
          "render --path, study", {"on", "off"}),
      // Accuracy studies.
      row("study.budgets", "budgets", "budgets", K::NumberList, 0.5, 10000, "8,16,33,66,133",
          "LIST", "frame budgets in ms, a run of each budgeted selector at each",
          "study, POST /api/studies"),
      row("study.ssePx", "sse-px", "ssePx", K::NumberList, 0.1, 1000, "1,2,4,8,16,32", "LIST",
          "SSE thresholds in pixels, a run of sse at each", "study, POST /api/studies"),
      row("study.referenceMb", "reference-mb", "", K::Number, 0, 1e7, "1024", "MB",
          "memory the full-detail reference holds at most (0: none): a larger front is drawn in "
          "batches, loading and freeing as it goes",
          "study"),
      row("study.selectors", "selectors", "selectors", K::ChoiceList, 0, 0, "lakhia,sse,fs", "LIST",
          "the selectors studied (vdr needs a store built with --vdr)", "study, POST /api/studies",
          {"lakhia", "sse", "fs", "vdr"}),
      row("study.size", "size", "", K::Size, 16, 8192, "640x360", "WxH", "frame size in pixels",
          "study"),
      row("study.frames", "frames", "frames", K::Integer, 1, 10000, "24", "N",
          "frames studied, spread evenly over the path", "study, POST /api/studies"),
      row("study.mode", "mode", "mode", K::Choice, 0, 0, "settled", "M",
          "settled runs, realtime runs (every frame of the path) or both",
          "study, POST /api/studies", {"settled", "realtime", "both"}),
      row("study.strips", "strips", "strips", K::Integer, 0, 20, "3", "N",
          "frames shown in strips at every Lakhia budget", "study, POST /api/studies"),
      // The server.
      row("serve.port", "port", "", K::Integer, 0, 65535, "8080", "N",
          "TCP port (0: any free port)", "serve"),
      row("serve.bind", "bind", "", K::Text, 0, 0, "127.0.0.1", "ADDR",
          "address to listen on (0.0.0.0 for all)", "serve"),
      row("serve.data", "data", "", K::Text, 0, 0, "hlodr-data", "DIR",
          "the data folder, created if missing ($HLODR_DATA, when set, is the default: the "
          "container image sets /data)",
          "serve"),
      row("serve.workers", "workers", "", K::Integer, 1, 64, "2", "N",
          "render workers, one GL context each", "serve"),
      row("serve.jobRunners", "job-runners", "", K::Integer, 1, 16, "1", "N",
          "job runners, one GL context each", "serve"),
      row("serve.maxSessions", "max-sessions", "", K::Integer, 1, 10000, "16", "N",
          "live viewing sessions at once; past it 429", "serve"),
      row("serve.admission", "admission", "", K::Choice, 0, 0, "share", "share|queue",
          "k sessions asking for frames at once (the workers take turns at GL): share (their k "
          "frames together hold one budget, each selected for budget / k) or queue (each frame "
          "gets the whole budget and waits for the others)",
          "serve", {"share", "queue"}),
      row("serve.queue", "queue", "", K::Integer, 1, 100000, "32", "N",
          "render requests waiting or running; past it 503", "serve"),
      row("serve.maxStreams", "max-streams", "", K::Integer, 1, 10000, "16", "N",
          "job event streams at once; past it 503", "serve"),
      row("serve.maxJobs", "max-jobs", "", K::Integer, 1, 10000, "8", "N",
          "jobs queued or running at once; past it 429", "serve"),
      row("serve.maxFrames", "max-frames", "", K::Integer, 1, 1e7, "5000", "N", "frames of one job",
          "serve"),
      row("serve.maxSize", "max-size", "", K::Integer, 16, 8192, "4096", "N",
          "largest frame side in pixels", "serve"),
      row("serve.memoryMb", "memory-mb", "", K::Number, 0, 1e7, "1024", "MB",
          "decoded node payloads of all sessions together in MB", "serve"),
      row("serve.glMemoryMb", "gl-memory-mb", "", K::Number, 0, 1e7, "4096", "MB",
          "GL memory of all sessions and warm contexts in MB (render targets, shadow maps, GPU "
          "copies); a session past it is 503 (0: no cap)",
          "serve"),
      row("serve.sessionIdleS", "session-idle-s", "", K::Integer, 1, 604800, "120", "S",
          "close sessions (and warm render contexts) idle this long", "serve"),
      row("serve.requestTimeoutS", "request-timeout-s", "", K::Integer, 1, 3600, "10", "S",
          "a request's line and headers must arrive within S seconds of its first byte, and "
          "its body within S more; else 408",
          "serve"),
      row("serve.maxConnectionsPerAddress", "max-connections-per-address", "", K::Integer, 0,
          100000, "64", "N",
          "open connections of one client address; past it 503, except /healthz and /metrics "
          "(0: no cap; behind a proxy, every client has the proxy's address)",
          "serve"),
      row("serve.drainS", "drain-s", "", K::Integer, 0, 3600, "0", "S",
          "on SIGTERM, answer /healthz with 503 for S seconds (a load balancer moves new sessions "
          "away; current ones are still served) before stopping; a second signal stops at once",
          "serve"),
      row("serve.keepJobsDays", "keep-jobs-days", "", K::Number, 0, 36500, "7", "D",
          "finished jobs older than D days are removed with their files (0: kept)", "serve"),
      row("serve.jobsMaxMb", "jobs-max-mb", "", K::Number, 0, 1e9, "10240", "MB",
          "past MB of finished jobs' files, the oldest are removed (0: no cap)", "serve"),
      row("serve.web", "web", "", K::Text, 0, 0, "", "DIR",
          "the page's files (default: found beside hlodr or in its source)", "serve"),
      row("serve.jobsDir", "jobs-dir", "", K::Text, 0, 0, "", "DIR",
          "where jobs write their frames, videos, stats and records (default DATA/jobs)", "serve"),
  };
}

}  // namespace

double Setting::fallbackNumber() const {
  return fallback.empty() ? 0.0 : std::strtod(fallback.c_str(), nullptr);
}

std::string Setting::range() const {
  switch (kind) {
    case K::Number:
    case K::Integer:
      return number(lo) + ".." + number(hi);
    case K::Size:
      return number(lo) + ".." + number(hi) + " each side";
    case K::NumberList:
      return "1..16 numbers in " + number(lo) + ".." + number(hi);
    case K::Choice:
      return joined(choices, " or ");
    case K::ChoiceList:
      return "a list of " + joined(choices, " and ");
    case K::Flag:
      return "on or off";
    case K::Text:
      return "text";
  }
  return "";
}

namespace settings {

const std::vector<Setting>& all() {
  static const std::vector<Setting> table = makeTable();
  return table;
}

const Setting* find(std::string_view id) {
  for (const Setting& s : all())
    if (s.id == id) return &s;
  return nullptr;
}

const Setting& get(std::string_view id) {
  const Setting* s = find(id);
  assert(s && "no such setting");
  if (!s) std::abort();
  return *s;
}

}  // namespace settings

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= text.size()) {
    std::size_t end = text.find(',', at);
    if (end == std::string::npos) end = text.size();
    out.push_back(text.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

std::string helpLine(const Setting& s) {
  std::string head =
      "  --" + s.cli + (s.metavar.empty() || s.kind == K::Flag ? "" : " " + s.metavar);
  std::string text = s.meaning;
  if (s.kind != K::Text && s.kind != K::Flag && s.kind != K::Choice) text += ": " + s.range();
  // "(default 33)" is kept on one line: \x01 stands for its space while the text is wrapped.
  if (!s.fallback.empty() && s.kind != K::Flag) text += " (default\x01" + s.fallback + ")";
  // Two columns: the option in 26, its text wrapped at 100.
  constexpr std::size_t kColumn = 26, kWidth = 100;
  std::string out = head;
  if (out.size() + 1 > kColumn) {
    out += "\n";
    out += std::string(kColumn, ' ');
  } else {
    out += std::string(kColumn - out.size(), ' ');
  }
  std::size_t col = kColumn;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(' ', at);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(at, end - at);
    if (col > kColumn && col + 1 + word.size() > kWidth) {
      out += "\n" + std::string(kColumn, ' ');
      col = kColumn;
    } else if (col > kColumn) {
      out += ' ';
      ++col;
    }
    out += word;
    col += word.size();
    at = end + 1;
  }
  std::replace(out.begin(), out.end(), '\x01', ' ');
  return out + "\n";
}

std::string expandUsage(const char* usage) {
  std::string out;
  const std::string text = usage;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size() - 1;
    const std::string line = text.substr(at, end - at + 1);
    const Setting* s = line.size() > 3 && line[0] == '{' && line.substr(line.size() - 2) == "}\n"
                           ? settings::find(line.substr(1, line.size() - 3))
                           : nullptr;
    out += s ? helpLine(*s) : line;  // an unknown {id} stays as written (a test finds it)
    at = end + 1;
  }
  return out;
}

std::string settingsMarkdown(std::string_view which) {
  const bool api = which == "api", serve = which == "serve";
  std::string out =
      api     ? "| field | range | default | meaning | taken by |\n|---|---|---|---|---|\n"
      : serve ? "| option | range | default | meaning |\n|---|---|---|---|\n"
              : "| option | API field | range | default | meaning | taken by |\n"
                "|---|---|---|---|---|---|\n";
  const auto code = [](const std::string& prefix, const std::string& name) {
    return name.empty() ? std::string() : "`" + prefix + name + "`";
  };
  for (const Setting& s : settings::all()) {
    if (api && s.api.empty()) continue;
    if (serve && s.id.rfind("serve.", 0) != 0) continue;
    std::string range = s.range(), fallback = s.fallback;
    if (s.kind == K::Flag) {
      range = api ? "true or false" : "a flag";
      fallback = api ? (s.fallback == "on" ? "true" : "false") : "";
    }
    out += "| ";
    if (!api) out += code("--", s.cli) + " | ";
    if (!serve) out += code("", s.api) + " | ";
    out += range + " | " + code("", fallback) + " | " + s.meaning;
    out += serve ? " |\n" : " | " + s.where + " |\n";
  }
  return out;
}

std::string settingsText() {
  std::string out;
  for (const Setting& s : settings::all()) {
    out += (s.cli.empty() ? std::string("(API only)") : "--" + s.cli) +
           (s.api.empty() ? std::string() : ", API \"" + s.api + "\"") + "  [" + s.where + "]\n";
    out += "    " + s.meaning + "; " + s.range() +
           (s.fallback.empty() ? std::string() : "; default " + s.fallback) + "\n";
  }
  return out;
}

}  // namespace service
