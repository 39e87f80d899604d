// The occlusion-switch across processes (Manocha sec. 4.2-4.5). See service/OcclusionSwitch.h.
#include "service/OcclusionSwitch.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/Framing.h"
#include "hlod/runtime/Selector.h"
#include "hlod/runtime/VisibleSetDelta.h"
#include "hlod/store/NodeStore.h"
#include "renderer/GlContext.h"
#include "renderer/GpuNodeRenderer.h"

namespace service {

namespace fs = std::filesystem;

namespace {

using SwitchClock = std::chrono::steady_clock;
double elapsedMs(SwitchClock::time_point t) {
  return std::chrono::duration<double, std::milli>(SwitchClock::now() - t).count();
}

// A peer that says nothing for this long has failed (a frame takes well under a second).
constexpr int kReceiveTimeoutS = 120;

// A socket, closed with its owner.
class Socket {
 public:
  explicit Socket(int fd = -1) : fd_(fd) {}
  Socket(Socket&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  Socket& operator=(Socket&& o) noexcept {
    if (this != &o) reset(std::exchange(o.fd_, -1));
    return *this;
  }
  ~Socket() { reset(); }
  void reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }
  int fd() const { return fd_; }

 private:
  int fd_;
};

hlod::Result<Socket> listenLoopback(std::uint16_t& port) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (s.fd() < 0) return hlod::makeError(std::string("socket: ") + std::strerror(errno));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (::bind(s.fd(), reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(s.fd(), 1) != 0 ||
      ::getsockname(s.fd(), reinterpret_cast<sockaddr*>(&a), &len) != 0)
    return hlod::makeError(std::string("loopback listener: ") + std::strerror(errno));
  port = ntohs(a.sin_port);
  return s;
}

void configure(const Socket& s) {
  const int one = 1;
  ::setsockopt(s.fd(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  timeval tv{kReceiveTimeoutS, 0};
  ::setsockopt(s.fd(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
}

hlod::Result<Socket> acceptOne(const Socket& listener) {
  int fd;
  do fd = ::accept4(listener.fd(), nullptr, nullptr, SOCK_CLOEXEC);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) return hlod::makeError(std::string("accept: ") + std::strerror(errno));
  Socket s(fd);
  configure(s);
  return s;
}

hlod::Result<Socket> connectTo(std::uint16_t port) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (s.fd() < 0) return hlod::makeError(std::string("socket: ") + std::strerror(errno));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(port);
  if (::connect(s.fd(), reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
    return hlod::makeError(std::string("connect: ") + std::strerror(errno));
  configure(s);
  return s;
}

hlod::Status sendAll(const Socket& s, std::span<const std::byte> bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::send(s.fd(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return hlod::makeError(std::string("send: ") + std::strerror(errno));
    bytes = bytes.subspan(std::size_t(n));
  }
  return hlod::Ok{};
}

hlod::Status receiveExactly(const Socket& s, std::span<std::byte> out) {
  while (!out.empty()) {
    const ssize_t n = ::recv(s.fd(), out.data(), out.size(), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) return hlod::makeError("the peer closed the connection");
    if (n < 0) return hlod::makeError(std::string("receive: ") + std::strerror(errno));
    out = out.subspan(std::size_t(n));
  }
  return hlod::Ok{};
}

// One message, checked (hlod::decodeSwitchMessage); its size on the wire in `bytes`.
hlod::Result<hlod::SwitchMessage> receiveMessage(const Socket& s, std::uint32_t nodeCount,
                                                 std::uint64_t& bytes) {
  std::vector<std::byte> buf(hlod::kSwitchHeaderBytes);
  if (auto r = receiveExactly(s, buf); !r) return r.error();
  auto body = hlod::switchBodyBytes(buf);
  if (!body) return body.error();
  buf.resize(hlod::kSwitchHeaderBytes + *body);
  if (auto r = receiveExactly(s, std::span(buf).subspan(hlod::kSwitchHeaderBytes)); !r)
    return r.error();
  bytes = buf.size();
  return hlod::decodeSwitchMessage(buf, nodeCount);
}

std::array<double, 9> cameraWords(const hlod::Camera& c) {
  return {c.position.x, c.position.y, c.position.z, c.target.x, c.target.y,
          c.target.z,   c.up.x,       c.up.y,       c.up.z};
}

// What every process shares: the store, the path's cameras, a GL context and a renderer.
struct Role {
  std::unique_ptr<hlod::NodeStore> store;
  std::unique_ptr<renderer::GlContext> context;
  std::unique_ptr<renderer::GpuNodeRenderer> renderer;
  std::vector<hlod::Camera> cameras;
  std::vector<std::uint32_t> visible;  // V_{i-1}, then V_i

  // Reads and uploads the nodes that are not on the GPU yet (the paper's GPUs each hold the
  // scene; here each process reads it from the store).
  hlod::Status load(std::span<const std::uint32_t> nodes) {
    const hlod::Skeleton& sk = store->skeleton();
    bool queued = false;
    for (std::uint32_t n : nodes) {
      if (renderer->onGpu().isResident(n)) continue;
      std::vector<std::byte> bytes(sk.nodes[n].payloadSize);
      if (auto r = store->readPayloadChunk(n, 0, bytes); !r) return r.error();
      auto mesh = store->decodePayload(n, bytes);
      if (!mesh) return mesh.error();
      renderer->queueUpload(n, std::make_shared<const hlod::LocalMesh>(std::move(*mesh)));
      queued = true;
    }
    if (!queued) return hlod::Ok{};
    auto up = renderer->upload(1e12, ~std::uint64_t(0));
    if (!up) return up.error();
    return hlod::Ok{};
  }

  hlod::Status draw(std::uint32_t frame) {
    const hlod::Camera& camera = cameras[frame];
    const auto front = hlod::nearToFar(store->skeleton(), camera.position, visible);
    if (auto l = load(front); !l) return l;
    auto drawn = renderer->draw(camera, front, {});
    if (!drawn) return drawn.error();
    return hlod::Ok{};
  }

  hlod::Status apply(const hlod::SwitchMessage& m, std::uint32_t frame) {
    if (m.frame != frame)
      return hlod::makeError("got frame " + std::to_string(m.frame) + ", expected " +
                             std::to_string(frame));
    auto v = hlod::applyVisibleSetDelta(visible, m.delta);
    if (!v) return v.error();
    visible = std::move(*v);
    return hlod::Ok{};
  }
};

hlod::Result<Role> makeRole(const std::string& storePath, const hlod::CameraPath& path,
                            const SwitchOptions& o, std::uint64_t frames, bool depthOnly) {
  Role r;
  auto opened = hlod::NodeStore::open(storePath);
  if (!opened) return opened.error();
  r.store = std::move(*opened);
  auto context = renderer::createContext(renderer::Backend::Auto);
  if (!context) return context.error();
  r.context = std::move(*context);
  if (!r.context->makeCurrent()) return hlod::makeError("cannot make the GL context current");
  renderer::RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  ro.up = hlod::modelUpFrame(r.store->skeleton()).up;
  // OR's image is never looked at: its depth is the occlusion representation.
  if (!depthOnly) ro.effects = o.effects;
  auto made = renderer::GpuNodeRenderer::create(*r.context, r.store->skeleton(), ro);
  if (!made) return made.error();
  r.renderer = std::move(*made);
  const double aspect = double(o.width) / o.height;
  for (std::uint64_t f = 0; f < frames; ++f) {
    hlod::Camera c = path.sampleFrame(f, o.fps, aspect).camera;
    c.aspect = aspect;
    r.cameras.push_back(c);
  }
  return r;
}

// A, B: HC in the frames of their parity, OR in the others. Writes per frame
// "frame,role,candidates,ms" to `log`.
hlod::Status runSwitchSide(int side, const std::string& storePath, const hlod::CameraPath& path,
                           const SwitchOptions& o, std::uint64_t frames, const Socket& peer,
                           const Socket& rvg, std::FILE* log) {
  auto role = makeRole(storePath, path, o, frames, true);
  if (!role) return role.error();
  const hlod::Skeleton& sk = role->store->skeleton();
  hlod::SelectorParams sp;
  sp.ssePixels = o.ssePx;
  auto selector = hlod::makeSelector(o.selector, sk, sp);
  if (!selector) return selector.error();
  const hlod::AllResident all;
  for (std::uint64_t f = 0; f < frames; ++f) {
    const auto start = SwitchClock::now();
    if (int(f % 2) == side) {
      // HC: the candidates against the depth this process drew last frame as OR.
      hlod::View view{role->cameras[f], glm::dvec3(0.0), o.width, o.height};
      std::vector<std::uint32_t> candidates = (*selector)->select(view, all).front;
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::vector<std::uint32_t> now;
      if (f == 0) {
        now = candidates;
      } else {
        const auto shown = role->renderer->queryBoxesOnLastDraw(candidates);
        for (std::size_t k = 0; k < candidates.size(); ++k)
          if (shown[k]) now.push_back(candidates[k]);
      }
      hlod::SwitchMessage m;
      m.frame = std::uint32_t(f);
      m.camera = cameraWords(role->cameras[f]);
      m.delta = hlod::visibleSetDelta(role->visible, now);
      role->visible = std::move(now);
      const auto bytes = hlod::encodeSwitchMessage(m);
      if (auto s = sendAll(peer, bytes); !s) return s;
      if (auto s = sendAll(rvg, bytes); !s) return s;
      std::fprintf(log, "%llu,hc,%zu,%.3f\n", (unsigned long long)f, candidates.size(),
                   elapsedMs(start));
    } else {
      // OR: V_f from HC, drawn with the next frame's camera for this process's HC then.
      std::uint64_t bytes = 0;
      auto m = receiveMessage(peer, std::uint32_t(sk.nodes.size()), bytes);
      if (!m) return m.error();
      if (auto a = role->apply(*m, std::uint32_t(f)); !a) return a;
      if (f + 1 < frames)
        if (auto d = role->draw(std::uint32_t(f + 1)); !d) return d;
      std::fprintf(log, "%llu,or,0,%.3f\n", (unsigned long long)f, elapsedMs(start));
    }
  }
  return hlod::Ok{};
}

// RVG: each frame's V_i, from the process that did its HC, drawn and written. Writes per frame
// "frame,visible,added,removed,bytes,fullBytes,ms" to `log`, and a byte to `tick`.
hlod::Status runRvg(const std::string& storePath, const hlod::CameraPath& path,
                    const SwitchOptions& o, std::uint64_t frames, const Socket& fromA,
                    const Socket& fromB, const fs::path& outDir, std::FILE* log, int tick) {
  auto role = makeRole(storePath, path, o, frames, false);
  if (!role) return role.error();
  const auto nodeCount = std::uint32_t(role->store->skeleton().nodes.size());
  for (std::uint64_t f = 0; f < frames; ++f) {
    std::uint64_t bytes = 0;
    auto m = receiveMessage(f % 2 == 0 ? fromA : fromB, nodeCount, bytes);
    if (!m) return m.error();
    const auto start = SwitchClock::now();
    if (auto a = role->apply(*m, std::uint32_t(f)); !a) return a;
    if (auto d = role->draw(std::uint32_t(f)); !d) return d;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05llu.png", (unsigned long long)f);
    if (auto w = renderer::writeImage((outDir / name).string(), role->renderer->readback()); !w)
      return w;
    // HC sent the same message to OR and to RVG.
    const std::uint64_t full =
        hlod::kSwitchHeaderBytes + hlod::kSwitchCameraBytes + 4 * role->visible.size();
    std::fprintf(log, "%llu,%zu,%zu,%zu,%llu,%llu,%.3f\n", (unsigned long long)f,
                 role->visible.size(), m->delta.added.size(), m->delta.removed.size(),
                 (unsigned long long)(2 * bytes), (unsigned long long)(2 * full), elapsedMs(start));
    const char one = 1;
    [[maybe_unused]] const auto n = ::write(tick, &one, 1);
  }
  return hlod::Ok{};
}

// Runs body in a child process; its error goes to stderr and the exit status.
pid_t forkRole(const char* name, const std::function<hlod::Status()>& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  hlod::Status s = hlod::makeError("not run");
  try {
    s = body();
  } catch (const std::exception& e) {
    s = hlod::makeError(e.what());
  }
  if (!s) std::fprintf(stderr, "hlodr switch: %s: %s\n", name, s.message().c_str());
  std::fflush(nullptr);
  ::_exit(s ? 0 : 1);
}

}  // namespace

hlod::Result<SwitchReport> runOcclusionSwitch(
    const std::string& storePath, const hlod::CameraPath& path, const SwitchOptions& o,
    const fs::path& outDir, const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
  if (o.selector != "sse" && o.selector != "full")
    return hlod::makeError("the switch's candidates come from sse or full, not " + o.selector);
  auto total = path.frameCount(o.fps);
  if (!total) return total.error();
  const std::uint64_t frames = o.frames > 0 ? std::min<std::uint64_t>(o.frames, *total) : *total;
  if (frames == 0) return hlod::makeError("no frames");
  {
    // Fails here, before any process starts, on a store that does not open.
    auto store = hlod::NodeStore::open(storePath);
    if (!store) return store.error();
  }
  std::error_code ec;
  fs::create_directories(outDir, ec);
  if (!fs::is_directory(outDir, ec))
    return hlod::makeError("cannot create the folder " + outDir.string());

  // The links: A-B (A listens), A-RVG and B-RVG (RVG listens). Listening before the fork, so a
  // connect never comes before its listen.
  std::uint16_t portAB = 0, portAR = 0, portBR = 0;
  auto lAB = listenLoopback(portAB);
  auto lAR = listenLoopback(portAR);
  auto lBR = listenLoopback(portBR);
  for (auto* l : {&lAB, &lAR, &lBR})
    if (!*l) return l->error();
  int ticks[2];
  if (::pipe2(ticks, O_CLOEXEC) != 0) return hlod::makeError("pipe failed");
  const fs::path logA = outDir / ".switch-A.csv", logB = outDir / ".switch-B.csv",
                 logR = outDir / ".switch-rvg.csv";
  auto withLog = [](const fs::path& p, const std::function<hlod::Status(std::FILE*)>& f) {
    std::FILE* log = std::fopen(p.string().c_str(), "w");
    if (!log) return hlod::Status(hlod::makeError("cannot write " + p.string()));
    auto s = f(log);
    std::fclose(log);
    return s;
  };
  std::vector<std::pair<const char*, pid_t>> children;
  children.emplace_back("A", forkRole("A", [&]() -> hlod::Status {
                          auto b = acceptOne(*lAB);
                          if (!b) return b.error();
                          auto r = connectTo(portAR);
                          if (!r) return r.error();
                          return withLog(logA, [&](std::FILE* log) {
                            return runSwitchSide(0, storePath, path, o, frames, *b, *r, log);
                          });
                        }));
  children.emplace_back("B", forkRole("B", [&]() -> hlod::Status {
                          auto a = connectTo(portAB);
                          if (!a) return a.error();
                          auto r = connectTo(portBR);
                          if (!r) return r.error();
                          return withLog(logB, [&](std::FILE* log) {
                            return runSwitchSide(1, storePath, path, o, frames, *a, *r, log);
                          });
                        }));
  children.emplace_back("RVG", forkRole("RVG", [&]() -> hlod::Status {
                          ::close(ticks[0]);
                          auto a = acceptOne(*lAR);
                          if (!a) return a.error();
                          auto b = acceptOne(*lBR);
                          if (!b) return b.error();
                          return withLog(logR, [&](std::FILE* log) {
                            return runRvg(storePath, path, o, frames, *a, *b, outDir, log,
                                          ticks[1]);
                          });
                        }));
  ::close(ticks[1]);
  for (auto* l : {&lAB, &lAR, &lBR}) (*l)->reset();
  std::uint64_t done = 0;
  char c;
  ssize_t n;
  while ((n = ::read(ticks[0], &c, 1)) != 0) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    if (progress) progress(++done, frames);
  }
  ::close(ticks[0]);
  std::string failed;
  for (auto& [name, pid] : children) {
    int status = 0;
    if (pid < 0) {
      failed += std::string(failed.empty() ? "" : ", ") + name + " did not start";
      continue;
    }
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      failed += std::string(failed.empty() ? "" : ", ") + name + " failed";
  }
  if (!failed.empty()) return hlod::makeError("the occlusion-switch stopped: " + failed);

  // The processes' logs, joined per frame.
  SwitchReport report;
  report.frames.resize(frames);
  for (std::uint64_t f = 0; f < frames; ++f) report.frames[f].frame = std::uint32_t(f);
  for (const auto& [log, side] : {std::pair{logA, 'A'}, std::pair{logB, 'B'}}) {
    std::ifstream in(log);
    std::string line;
    while (std::getline(in, line)) {
      unsigned long long f = 0;
      char what[4] = {};
      std::size_t candidates = 0;
      double ms = 0.0;
      if (std::sscanf(line.c_str(), "%llu,%2[a-z],%zu,%lf", &f, what, &candidates, &ms) != 4 ||
          f >= frames)
        return hlod::makeError("a switch log line is not one: " + line);
      SwitchFrame& r = report.frames[f];
      if (std::string(what) == "hc") {
        r.hc = side;
        r.candidates = candidates;
        r.hcMs = ms;
      } else {
        r.orMs = ms;
      }
    }
  }
  {
    std::ifstream in(logR);
    std::string line;
    std::uint64_t rows = 0;
    while (std::getline(in, line)) {
      unsigned long long f = 0, bytes = 0, full = 0;
      std::size_t visible = 0, added = 0, removed = 0;
      double ms = 0.0;
      if (std::sscanf(line.c_str(), "%llu,%zu,%zu,%zu,%llu,%llu,%lf", &f, &visible, &added,
                      &removed, &bytes, &full, &ms) != 7 ||
          f >= frames)
        return hlod::makeError("an RVG log line is not one: " + line);
      SwitchFrame& r = report.frames[f];
      r.visible = visible, r.added = added, r.removed = removed;
      r.bytes = bytes, r.fullBytes = full, r.rvgMs = ms;
      ++rows;
    }
    if (rows != frames) return hlod::makeError("RVG drew fewer frames than the path has");
  }
  for (const fs::path& p : {logA, logB, logR}) fs::remove(p, ec);
  const double h = double(hlod::kSwitchHeaderBytes);
  for (const SwitchFrame& r : report.frames) {
    const double ids = double(r.added + r.removed), all = double(r.visible);
    report.meanBytes += double(r.bytes);
    report.meanFullBytes += double(r.fullBytes);
    report.meanFormulaBytes += hlod::switchBandwidthBytes(ids, h, std::max(1.0, ids));
    report.meanFormulaFullBytes += hlod::switchBandwidthBytes(all, h, std::max(1.0, all));
  }
  for (double* v : {&report.meanBytes, &report.meanFullBytes, &report.meanFormulaBytes,
                    &report.meanFormulaFullBytes})
    *v /= double(frames);

  nlohmann::json j;
  j["frames"] = nlohmann::json::array();
  for (const SwitchFrame& r : report.frames)
    j["frames"].push_back({{"frame", r.frame},
                           {"hc", std::string(1, r.hc)},
                           {"candidates", r.candidates},
                           {"visible", r.visible},
                           {"added", r.added},
                           {"removed", r.removed},
                           {"bytes", r.bytes},
                           {"fullBytes", r.fullBytes},
                           {"hcMs", r.hcMs},
                           {"orMs", r.orMs},
                           {"rvgMs", r.rvgMs}});
  j["summary"] = {{"frames", frames},
                  {"meanBytes", report.meanBytes},
                  {"meanFullBytes", report.meanFullBytes},
                  {"savedShare", report.savedShare()},
                  {"meanFormulaBytes", report.meanFormulaBytes},
                  {"meanFormulaFullBytes", report.meanFormulaFullBytes},
                  {"headerBytes", hlod::kSwitchHeaderBytes},
                  {"cameraBytes", hlod::kSwitchCameraBytes}};
  std::ofstream out(outDir / "switch.json");
  out << j.dump(1) << "\n";
  if (!out) return hlod::makeError("cannot write " + (outDir / "switch.json").string());
  return report;
}

}  // namespace service
