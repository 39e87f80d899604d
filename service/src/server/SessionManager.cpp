#include "server/SessionManager.h"

#include <malloc.h>

#include <algorithm>
#include <future>
#include <limits>
#include <random>

#include "renderer/Renderer.h"

namespace service::server {

std::string newId(char prefix) {
  static std::mutex m;
  static std::mt19937_64 rng(std::random_device{}());
  std::lock_guard lock(m);
  char buf[24];
  std::snprintf(buf, sizeof buf, "%c%08llx", prefix,
                static_cast<unsigned long long>(rng() & 0xffffffffull));
  return buf;
}

hlod::Result<std::unique_ptr<Session>> openSession(Scene& scene, const RenderSettings& settings,
                                                   renderer::GlContext& context,
                                                   const std::shared_ptr<hlod::NodeCache>& cache) {
  SessionOptions o;
  o.width = settings.width;
  o.height = settings.height;
  o.budgetMs = settings.budgetMs;
  o.selector = settings.selector;
  o.selectorParams.ssePixels = settings.ssePx;
  o.memoryCapBytes = settings.memoryCapBytes;
  o.occlusion = settings.occlusion;
  o.gpuBudgetBytes = settings.gpuBudgetBytes;
  o.showOcclusion = settings.showOcclusion;
  o.predict = settings.predict;
  o.effects = settings.effects;
  o.cache = cache;
  o.cacheStore = scene.cacheStore;
  const hlod::FrontTiming known = scene.knownTiming(settings.width, settings.height);
  o.knownVTime = known.vTime;
  o.knownFixedMs = known.fixedMs;
  o.recentFrames = 300;
  return Session::create(scene.store, o, context);
}

// A client's viewing session. `session` and `gl` are touched only on its worker's thread.
struct SessionManager::Live {
  std::string id;
  std::shared_ptr<Scene> scene;
  RenderSettings settings;
  std::size_t worker = 0;
  GlMemory::Lease gl;  // declared first: released after the session's GL objects
  std::unique_ptr<Session> session;
  hlod::Camera camera;  // the last one drawn
  Clock::time_point lastFrameAt{};
  std::atomic<Clock::rep> lastUsed{0};
  std::atomic<Clock::rep> askedAt{std::numeric_limits<Clock::rep>::min()};  // last frame asked
  std::atomic<std::uint64_t> frames{0};
  std::atomic<bool> ready{false};  // the worker made the session (HTTP threads read this)
  std::atomic<bool> closed{false};
};

struct SessionManager::Warm {
  std::string key;
  std::shared_ptr<Scene> scene;
  GlMemory::Lease gl;
  std::unique_ptr<Session> session;
  Clock::time_point lastUsed;
};

namespace {

// Destroyed GL objects go back to the allocator (llvmpipe's are in process memory): give the
// freed pages back to the system, so that the process shrinks when sessions close.
void trimMemory() {
  malloc_trim(0);
}

std::uint64_t targetsOf(const RenderSettings& settings) {
  renderer::RenderOptions ro;
  ro.width = settings.width;
  ro.height = settings.height;
  ro.effects = settings.effects;
  return renderer::Renderer::targetBytes(ro);
}

// Runs fn on the worker and waits for its answer. A render that outlives the timeout answers
// 503; its task still runs, and its result is dropped.
template <class T, class Fn>
ApiResult<T> runOn(RenderWorker& worker, std::chrono::seconds timeout, Fn fn) {
  auto promise = std::make_shared<std::promise<ApiResult<T>>>();
  auto future = promise->get_future();
  const bool posted = worker.post([promise, fn = std::move(fn)](renderer::GlContext& gl) mutable {
    try {
      promise->set_value(fn(gl));
    } catch (const std::exception& e) {
      promise->set_value(ApiError{500, "internal", std::string("render failed: ") + e.what()});
    }
  });
  if (!posted) return ApiError{503, "busy", "the server is shutting down"};
  if (future.wait_for(timeout) != std::future_status::ready)
    return ApiError{503, "busy",
                    "the frame took longer than " + std::to_string(timeout.count()) + " s"};
  return future.get();
}

}  // namespace

SessionManager::SessionManager(std::vector<RenderWorker*> workers, SceneRegistry& scenes,
                               Metrics& metrics, GlMemory& glMemory, SessionLimits limits)
    : workers_(std::move(workers)),
      scenes_(scenes),
      metrics_(metrics),
      glMemory_(glMemory),
      limits_(std::move(limits)),
      warm_(workers_.size()) {}

ApiResult<GlMemory::Lease> SessionManager::leaseFor(const RenderSettings& settings, std::size_t w) {
  const std::uint64_t need = targetsOf(settings);
  auto lease = glMemory_.reserve(need);
  auto& warm = warm_[w];
  while (!lease && !warm.empty()) {
    warm.pop_back();  // the least recently used warm context: dies here, on its thread
    trimMemory();
    lease = glMemory_.reserve(need);
  }
  if (lease) return std::move(*lease);
  metrics_.add("hlodr_rejected_total", "reason=\"gl_memory\"");
  const auto mb = [](std::uint64_t b) { return std::to_string((b + (1 << 20) - 1) >> 20); };
  return ApiError{503, "gl_memory",
                  "not enough GL memory: a " + std::to_string(settings.width) + "x" +
                      std::to_string(settings.height) + " frame with these effects needs " +
                      mb(need) + " MB of render targets, and " + mb(glMemory_.used()) + " of " +
                      mb(glMemory_.cap()) +
                      " MB (--gl-memory-mb) are in use; close a session or ask for a smaller "
                      "frame"};
}

SessionManager::~SessionManager() = default;

std::size_t SessionManager::leastBusyWorker() const {
  std::size_t best = 0;
  for (std::size_t i = 1; i < workers_.size(); ++i)
    if (workers_[i]->queued() < workers_[best]->queued()) best = i;
  return best;
}

std::size_t SessionManager::askedSince(Clock::time_point now, const Live* besides) const {
  const Clock::rep since = (now - kAskingWindow).time_since_epoch().count();
  std::lock_guard lock(mutex_);
  return std::size_t(std::count_if(live_.begin(), live_.end(), [&](const auto& l) {
    return l.second.get() != besides && l.second->askedAt >= since;
  }));
}

std::size_t SessionManager::asking() const {
  return askedSince(limits_.now(), nullptr);
}

std::size_t SessionManager::count() const {
  std::lock_guard lock(mutex_);
  return live_.size();
}

ApiResult<nlohmann::json> SessionManager::create(const std::shared_ptr<Scene>& scene,
                                                 const RenderSettings& settings,
                                                 const std::string& id) {
  auto live = std::make_shared<Live>();
  {
    std::lock_guard lock(mutex_);
    if (live_.size() >= limits_.maxSessions)
      return ApiError{429, "too_many_sessions",
                      "at most " + std::to_string(limits_.maxSessions) +
                          " sessions at once; close one (DELETE /api/sessions/{id}) or wait for "
                          "idle ones to expire"};
    if (!id.empty() && live_.count(id))
      return ApiError{409, "conflict", "session id " + id + " is in use"};
    if (!id.empty()) {
      live->id = id;
    } else {
      do live->id = newId('s');
      while (live_.count(live->id));
    }
    live->scene = scene;
    live->settings = settings;
    live->worker = leastBusyWorker();
    live->lastUsed = limits_.now().time_since_epoch().count();
    live_[live->id] = live;  // reserves the place while the session is made
  }
  auto made = runOn<bool>(*workers_[live->worker], limits_.renderTimeout,
                          [this, live](renderer::GlContext& gl) -> ApiResult<bool> {
                            auto lease = leaseFor(live->settings, live->worker);
                            if (!lease) return lease.error();
                            live->gl = std::move(*lease);
                            auto s = openSession(*live->scene, live->settings, gl, scenes_.cache());
                            if (!s) {
                              live->gl.release();
                              return ApiError{500, "internal", s.message()};
                            }
                            live->session = std::move(*s);
                            live->camera = live->scene->defaultCamera(
                                double(live->settings.width) / live->settings.height,
                                live->settings.camera);
                            live->ready = true;
                            return true;
                          });
  if (!made) {
    std::lock_guard lock(mutex_);
    live_.erase(live->id);
    return made.error();
  }
  nlohmann::json j = live->settings.json();
  j["id"] = live->id;
  j["scene"] = scene->id;
  j["idleTimeoutS"] = limits_.idleTimeout.count();
  j["defaultCamera"] = cameraJson(live->camera);  // written before ready, read after
  return j;
}

ApiResult<FrameAnswer> SessionManager::draw(Session& session, Scene& scene,
                                            const hlod::CameraSample& sample, hlod::FrameMode mode,
                                            const ImageRequest& image, Clock::time_point posted) {
  FrameAnswer a;
  a.queueMs = msSince(posted);
  auto rec = session.renderFrame(sample, mode);
  if (!rec) {
    metrics_.add("hlodr_render_errors_total", "");
    return ApiError{500, "internal", "render failed: " + rec.message()};
  }
  a.record = *rec;
  scene.rememberTiming(session.options().width, session.options().height,
                       session.driver().timing());
  auto t = Clock::now();
  const hlod::Image pixels = session.readback();
  a.readbackMs = msSince(t);
  t = Clock::now();
  auto bytes = renderer::encodeImage(pixels, image.format, image.quality);
  if (!bytes) return ApiError{500, "internal", bytes.message()};
  a.encodeMs = msSince(t);
  a.bytes = std::move(*bytes);
  a.format = image.format;
  metrics_.observeFrame(rec->gpuMs * 1e-3);
  return a;
}

ApiResult<FrameAnswer> SessionManager::frame(const std::string& id, const nlohmann::json& camera,
                                             bool still, const ImageRequest& image) {
  std::shared_ptr<Live> live;
  {
    std::lock_guard lock(mutex_);
    auto it = live_.find(id);
    if (it != live_.end() && it->second->ready) live = it->second;
  }
  if (!live) return notFound("no session " + id + " (closed or expired)");
  live->lastUsed = limits_.now().time_since_epoch().count();
  live->askedAt = live->lastUsed.load();
  const auto posted = Clock::now();
  auto answer = runOn<FrameAnswer>(
      *workers_[live->worker], limits_.renderTimeout,
      [this, live, camera, still, image, posted](renderer::GlContext&) -> ApiResult<FrameAnswer> {
        if (live->closed || !live->session) return notFound("no session " + live->id);
        hlod::CameraSample sample;
        sample.camera = live->camera;
        if (!camera.is_null()) {
          auto c = cameraFrom(camera, live->camera);
          if (!c) return badRequest(c.message());
          sample.camera = *c;
        }
        // The camera's velocity from the last frame: nodes ahead gain priority (Lakhia III-C).
        const auto now = Clock::now();
        if (live->frames > 0) {
          const double dt = std::chrono::duration<double>(now - live->lastFrameAt).count();
          if (dt > 1e-3 && dt < 1.0)
            sample.velocity = (sample.camera.position - live->camera.position) / dt;
        }
        // The admission rule (SessionLimits::shareBudget).
        // The frame's own session counts whether or not it asked within the window.
        const std::size_t k = limits_.shareBudget ? 1 + askedSince(limits_.now(), live.get()) : 1;
        live->session->driver().selector().setTargetMs(live->settings.budgetMs / double(k));
        auto a = draw(*live->session, *live->scene, sample,
                      still ? hlod::FrameMode::Settled : hlod::FrameMode::Realtime, image, posted);
        live->gl.resize(targetsOf(live->settings) + live->session->gpuBytes());
        if (a) {
          live->camera = sample.camera;
          live->lastFrameAt = now;
          ++live->frames;
          a->session = live->id;
          a->budgetMs = live->settings.budgetMs;
          a->sharedBy = k;
        }
        return a;
      });
  live->lastUsed = limits_.now().time_since_epoch().count();
  if (answer) metrics_.add("hlodr_frames_total", "kind=\"session\"");
  return answer;
}

ApiResult<nlohmann::json> SessionManager::info(const std::string& id) {
  std::shared_ptr<Live> live;
  {
    std::lock_guard lock(mutex_);
    auto it = live_.find(id);
    if (it != live_.end() && it->second->ready) live = it->second;
  }
  if (!live) return notFound("no session " + id + " (closed or expired)");
  return runOn<nlohmann::json>(
      *workers_[live->worker], limits_.renderTimeout,
      [this, live](renderer::GlContext&) -> ApiResult<nlohmann::json> {
        if (!live->session) return notFound("no session " + live->id);
        nlohmann::json j = live->settings.json();
        j["id"] = live->id;
        j["scene"] = live->scene->id;
        j["idleTimeoutS"] = limits_.idleTimeout.count();
        j["frames"] = live->frames.load();
        j["camera"] = cameraJson(live->camera);
        nlohmann::json recent = nlohmann::json::array();
        for (const auto& r : live->session->recent())
          recent.push_back(nlohmann::json::parse(hlod::frameJson(r)));
        j["recent"] = recent;
        j["summary"] = nlohmann::json::parse(hlod::summaryJson(live->session->recentSummary()));
        return j;
      });
}

bool SessionManager::remove(const std::string& id) {
  std::shared_ptr<Live> live;
  {
    std::lock_guard lock(mutex_);
    auto it = live_.find(id);
    if (it == live_.end() || !it->second->ready) return false;
    live = it->second;
    live_.erase(it);
  }
  live->closed = true;
  runOn<bool>(*workers_[live->worker], limits_.renderTimeout,
              [live](renderer::GlContext&) -> ApiResult<bool> {
                live->session.reset();
                live->gl.release();
                trimMemory();
                return true;
              });
  return true;
}

std::size_t SessionManager::expireIdle() {
  const Clock::time_point now = limits_.now();
  const auto limit = std::chrono::duration_cast<Clock::duration>(limits_.idleTimeout).count();
  std::vector<std::string> idle;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, live] : live_)
      if (live->ready && now.time_since_epoch().count() - live->lastUsed.load() > limit)
        idle.push_back(id);
  }
  for (const auto& id : idle) remove(id);
  // Warm render contexts unused as long: their targets and GPU copies go too.
  for (std::size_t w = 0; w < workers_.size(); ++w) {
    workers_[w]->post([this, w, now](renderer::GlContext&) {
      const std::size_t before = warm_[w].size();
      std::erase_if(warm_[w],
                    [&](const auto& e) { return now - e->lastUsed > limits_.idleTimeout; });
      if (warm_[w].size() != before) trimMemory();
    });
  }
  return idle.size();
}

ApiResult<FrameAnswer> SessionManager::renderOnce(const std::shared_ptr<Scene>& scene,
                                                  const RenderSettings& settings,
                                                  const hlod::Camera& camera, hlod::FrameMode mode,
                                                  const ImageRequest& image) {
  const std::size_t w = leastBusyWorker();
  const auto posted = Clock::now();
  const std::string key = scene->id + "/" + settings.key();
  auto answer =
      runOn<FrameAnswer>(*workers_[w], limits_.renderTimeout,
                         [this, w, key, scene, settings, camera, mode, image,
                          posted](renderer::GlContext& gl) -> ApiResult<FrameAnswer> {
                           auto& warm = warm_[w];  // this worker's: only its thread touches it
                           auto it = std::find_if(warm.begin(), warm.end(),
                                                  [&](const auto& e) { return e->key == key; });
                           std::shared_ptr<Warm> entry;
                           if (it != warm.end()) {
                             entry = *it;
                             warm.erase(it);
                           } else {
                             auto lease = leaseFor(settings, w);
                             if (!lease) return lease.error();
                             auto s = openSession(*scene, settings, gl, scenes_.cache());
                             if (!s) return ApiError{500, "internal", s.message()};
                             entry = std::make_shared<Warm>();
                             entry->key = key;
                             entry->scene = scene;
                             entry->gl = std::move(*lease);
                             entry->session = std::move(*s);
                           }
                           entry->lastUsed = limits_.now();
                           warm.insert(warm.begin(), entry);  // most recently used first
                           while (warm.size() > kWarmPerWorker)
                             warm.pop_back();  // dies here, on this thread
                           hlod::CameraSample sample;
                           sample.camera = camera;
                           auto a = draw(*entry->session, *scene, sample, mode, image, posted);
                           entry->gl.resize(targetsOf(settings) + entry->session->gpuBytes());
                           return a;
                         });
  if (answer) metrics_.add("hlodr_frames_total", "kind=\"render\"");
  return answer;
}

void SessionManager::shutdown() {
  std::map<std::string, std::shared_ptr<Live>> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(live_);
  }
  // Not a structured binding: clang 14 cannot capture one in a lambda.
  for (auto& entry : all) {
    const std::shared_ptr<Live>& live = entry.second;
    live->closed = true;
    workers_[live->worker]->post([live](renderer::GlContext&) {
      live->session.reset();
      live->gl.release();
    });
  }
  for (std::size_t w = 0; w < workers_.size(); ++w)
    workers_[w]->post([this, w](renderer::GlContext&) { warm_[w].clear(); });
}

}  // namespace service::server
