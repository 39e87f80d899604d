#pragma once
// What the server's parts hand each other: errors with their HTTP status, a rendered frame with
// its timings, and the render settings a request carries (validated in one place).
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/OcclusionAuto.h"
#include "hlod/scene/SceneFile.h"
#include "renderer/ImageEncoder.h"
#include "server/JsonInput.h"

namespace service::server {

struct ApiError {
  int status = 500;
  std::string code = "internal";
  std::string message;
};

inline ApiError badRequest(std::string message) {
  return {400, "bad_request", std::move(message)};
}
inline ApiError notFound(std::string message) {
  return {404, "not_found", std::move(message)};
}

template <class T>
class ApiResult {
 public:
  ApiResult(T value) : v_(std::move(value)) {}
  ApiResult(ApiError error) : v_(std::move(error)) {}
  explicit operator bool() const { return v_.index() == 0; }
  T& operator*() { return std::get<0>(v_); }
  T* operator->() { return &std::get<0>(v_); }
  const ApiError& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, ApiError> v_;
};

// Frame size, budget and selector of a session or a one-off render.
struct RenderSettings {
  int width = 640;
  int height = 480;
  double budgetMs = 33.0;
  std::string selector = "lakhia";
  double ssePx = 16.0;
  std::uint64_t memoryCapBytes = 0;
  hlod::OcclusionMode occlusion = hlod::OcclusionMode::Auto;
  std::uint64_t gpuBudgetBytes = 0;
  bool showOcclusion = false;
  bool predict = false;
  hlod::SceneEffects effects = hlod::defaultEffects();  // from the request's `scene`
  std::string effectsKey;                   // SceneChoice::key: equal effects, equal key
  std::optional<hlod::SceneCamera> camera;  // the scene file's: where sessions and orbits start
  std::string sceneFile;    // the scene file's name ("" for a store id or a scene inline)
  std::string key() const;  // equal for settings that can share a warm session
  nlohmann::json json() const;
};

// Reads width, height, budgetMs, selector, ssePx, occlusion, showOcclusion (and memoryMb and
// gpuMb when allowed), by the settings
// table (service/Settings.h); width and height at most maxSize.
ApiResult<RenderSettings> readRenderSettings(const JsonInput& in, int maxSize, bool memory);
const std::set<std::string>& renderSettingFields();

struct ImageRequest {
  renderer::ImageFormat format = renderer::ImageFormat::Jpeg;
  int quality = 85;
};
ApiResult<ImageRequest> readImageRequest(const JsonInput& in);

// The "path" of a job or a study, checked and parsed at the boundary: a path generated for the
// scene ({"kind": "walk-fly" | "drive" | "orbit", "duration": S}) or keyframes (the camera-path
// JSON of `hlodr path`, {"keyframes": [...]}).
struct PathSpec {
  std::string kind;                                   // "" for keyframes
  std::optional<double> duration;                     // a generated kind's length, when given
  std::shared_ptr<const hlod::CameraPath> keyframes;  // when given as keyframes
  // As the job object shows it: {"kind", "duration"} or "keyframes".
  nlohmann::json json() const;
};
ApiResult<PathSpec> readPathSpec(const JsonInput& in);

struct FrameAnswer {
  std::vector<std::uint8_t> bytes;
  renderer::ImageFormat format = renderer::ImageFormat::Jpeg;
  hlod::FrameRecord record;
  std::string session;  // id, for session frames
  // Session frames: the session's budget, and the sessions that shared it (the frame was
  // selected for budgetMs / sharedBy; SessionLimits::shareBudget).
  double budgetMs = 0.0;
  std::size_t sharedBy = 0;
  double queueMs = 0.0, readbackMs = 0.0, encodeMs = 0.0;
};

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace service::server
