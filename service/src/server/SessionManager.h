#pragma once
// Viewing sessions of the server and frames on request. A session is bound to one render worker
// at creation (the least busy) and lives on its thread: created, drawn and destroyed there. The
// HTTP threads post tasks and wait for their answer with a timeout.
//
// Frames on request (POST /api/render) use warm sessions kept per worker for each scene and
// render settings (at most kWarmPerWorker, least recently used go first): hlod_0 is not loaded
// again for every request, and the selector's v_time stays calibrated.
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/ApiTypes.h"
#include "server/GlMemory.h"
#include "server/Metrics.h"
#include "server/RenderWorker.h"
#include "server/SceneRegistry.h"
#include "service/Session.h"

namespace service::server {

struct SessionLimits {
  std::size_t maxSessions = 16;
  // The admission rule of sessions that ask for frames at once (a frame asked within
  // kAskingWindow). The workers take turns at GL (RenderWorker.h): the k sessions' frames are
  // drawn one after the other whatever worker holds them. true: they share one budget, each
  // frame selected for budgetMs / k, so that the k frames together take one budget as one
  // session's frame alone would (each session's frame rate held, its detail lowered); false:
  // each frame is selected for the whole budget and waits for the others' (detail held, frame
  // rate divided by k).
  bool shareBudget = true;
  std::chrono::seconds idleTimeout{120};    // sessions and warm render contexts
  std::chrono::seconds renderTimeout{120};  // longest wait for one frame
  std::function<Clock::time_point()> now = [] { return Clock::now(); };  // idle time's clock
};

class SessionManager {
 public:
  static constexpr std::size_t kWarmPerWorker = 4;
  static constexpr std::chrono::seconds kAskingWindow{1};

  SessionManager(std::vector<RenderWorker*> workers, SceneRegistry& scenes, Metrics& metrics,
                 GlMemory& glMemory, SessionLimits limits);
  ~SessionManager();

  // id: the client's proposed id (a load balancer routes by it, docs/deploy.md), checked by the
  // caller; empty: a random one. An id in use is 409.
  ApiResult<nlohmann::json> create(const std::shared_ptr<Scene>& scene,
                                   const RenderSettings& settings, const std::string& id = {});
  // camera: the request's "camera" object, or null for the session's last camera.
  ApiResult<FrameAnswer> frame(const std::string& id, const nlohmann::json& camera, bool still,
                               const ImageRequest& image);
  ApiResult<nlohmann::json> info(const std::string& id);
  // Destroys the session on its worker and waits for it: its GL memory is free on return.
  bool remove(const std::string& id);
  ApiResult<FrameAnswer> renderOnce(const std::shared_ptr<Scene>& scene,
                                    const RenderSettings& settings, const hlod::Camera& camera,
                                    hlod::FrameMode mode, const ImageRequest& image);
  // Closes sessions idle longer than the limit, by the limits' clock, and drops warm render
  // contexts as idle; returns how many sessions.
  std::size_t expireIdle();
  std::size_t count() const;
  // Sessions that asked for a frame within kAskingWindow, by the limits' clock: the k that
  // shares one budget under SessionLimits::shareBudget.
  std::size_t asking() const;
  // Destroys every session on its worker (before the workers stop).
  void shutdown();

 private:
  struct Live;
  struct Warm;
  std::size_t leastBusyWorker() const;
  // Sessions other than `besides` that asked for a frame within kAskingWindow of now.
  std::size_t askedSince(Clock::time_point now, const Live* besides) const;
  // A lease of GL memory for a session of these settings: on the worker's thread (w), where
  // warm contexts of that worker are dropped, least recently used first, to make room.
  ApiResult<GlMemory::Lease> leaseFor(const RenderSettings& settings, std::size_t w);
  ApiResult<FrameAnswer> draw(Session& session, Scene& scene, const hlod::CameraSample& sample,
                              hlod::FrameMode mode, const ImageRequest& image,
                              Clock::time_point posted);

  std::vector<RenderWorker*> workers_;
  SceneRegistry& scenes_;
  Metrics& metrics_;
  GlMemory& glMemory_;
  SessionLimits limits_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Live>> live_;
  std::vector<std::vector<std::shared_ptr<Warm>>> warm_;  // per worker; used on its thread only
};

// Makes a Session on `context` for a scene and settings (the v_time known from earlier sessions
// of the same scene and size, the server's shared node cache).
hlod::Result<std::unique_ptr<Session>> openSession(Scene& scene, const RenderSettings& settings,
                                                   renderer::GlContext& context,
                                                   const std::shared_ptr<hlod::NodeCache>& cache);

// A random id with a prefix ("s" sessions, "j" jobs): 8 hex digits.
std::string newId(char prefix);

}  // namespace service::server
