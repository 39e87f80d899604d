// The HTTP service's request bodies, without sockets: the first byte picks the endpoint (POST
// /api/render, /api/sessions, /api/sessions/ID/frame, /api/jobs, /api/studies), the rest is the
// body, read with the same fields and in the same order as server/HttpApi.cpp reads it. Every
// body must give a validated request or a 400 naming the problem; what validated must be in the
// ranges the workers rely on (finite cameras, sizes and budgets in range, a path that parses).
#include <cmath>
#include <cstdlib>

#include "FuzzSupport.h"
#include "hlod/runtime/CameraPath.h"
#include "server/ApiTypes.h"
#include "server/JsonInput.h"
#include "server/SceneChoice.h"
#include "server/SceneRegistry.h"

namespace {

using service::server::JsonInput;
constexpr int kMaxSize = 4096;  // hlodr serve's default --max-size

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check(bool ok) {
  if (!ok) std::abort();
}

void checkCamera(const JsonInput& in) {
  if (!in.has("camera")) return;
  hlod::Camera fallback;
  auto c = service::server::cameraFrom(in.json()["camera"], fallback);
  if (!c) return;
  check(finite(c->position) && finite(c->target) && finite(c->up) && c->fovY >= 1.0 &&
        c->fovY <= 170.0 && finite(c->forward()) && finite(c->right()) && finite(c->trueUp()));
}

// The "scene" of a render, session or job: a store id, a scene file in the data folder, or an
// inline scene. The fuzz's data folder holds one scene file (scene.json) and no store, so every
// choice ends in an error (404 at best); the rest of the body is read anyway, as it is for a
// store that exists.
void sceneChoice(const JsonInput& in) {
  static const service::server::SceneRegistry registry = [] {
    fuzz::writeFile("scene.json",
                    R"({"store": "city.hlod", "effects": {"shading": "lambert", "fog": true}})");
    return service::server::SceneRegistry(fuzz::tempFolder(), 1 << 20);
  }();
  auto choice =
      service::server::readSceneChoice(in.json().value("scene", nlohmann::json()), registry);
  check(!choice);  // no store here
}

bool settings(const JsonInput& in, bool memory) {
  auto s = service::server::readRenderSettings(in, kMaxSize, memory);
  if (!s) return false;
  check(s->width >= 16 && s->width <= kMaxSize && s->height >= 16 && s->height <= kMaxSize &&
        s->budgetMs >= 1.0 && s->budgetMs <= 10000.0 && s->ssePx >= 0.1 && s->ssePx <= 1000.0);
  return true;
}

bool image(const JsonInput& in) {
  auto r = service::server::readImageRequest(in);
  if (!r) return false;
  check(r->quality >= 1 && r->quality <= 100);
  return true;
}

// The path a job or study runs: a generated kind, or keyframes parsed as JobManager::pathOf does.
void path(const JsonInput& in) {
  auto spec = service::server::readPathSpec(in);
  if (!spec) return;
  if (spec->contains("kind")) {
    check((*spec)["kind"].is_string());
    if (spec->contains("duration")) check((*spec)["duration"].is_number());
    return;
  }
  (void)hlod::CameraPath::parse(spec->dump());
}

std::set<std::string> with(std::initializer_list<const char*> extra, bool memory) {
  std::set<std::string> fields = service::server::renderSettingFields();
  if (!memory) fields.erase("memoryMb");
  for (const char* f : extra) fields.insert(f);
  return fields;
}

void render(const std::string& body) {
  auto in = JsonInput::parse(body, with({"scene", "camera", "mode", "format", "quality"}, false));
  fuzz::report("JsonInput::parse", in);
  if (!in) return;
  sceneChoice(*in);
  if (!settings(*in, false) || !image(*in)) return;
  if (!in->choice("mode", "settled", {"settled", "realtime"})) return;
  checkCamera(*in);
}

void session(const std::string& body) {
  auto in = JsonInput::parse(body, with({"scene"}, true));
  fuzz::report("JsonInput::parse", in);
  if (!in) return;
  sceneChoice(*in);
  settings(*in, true);
}

void frame(const std::string& body) {
  auto in = JsonInput::parse(body, {"camera", "still", "format", "quality"});
  fuzz::report("JsonInput::parse", in);
  if (!in || !in->boolean("still", false) || !image(*in)) return;
  checkCamera(*in);
}

void job(const std::string& body) {
  auto in = JsonInput::parse(
      body, with({"scene", "path", "fps", "mode", "video", "frames", "prefetch"}, true));
  fuzz::report("JsonInput::parse", in);
  if (!in) return;
  sceneChoice(*in);
  if (!settings(*in, true)) return;
  auto fps = in->number("fps", 30.0, 1.0, 240.0);
  auto frames = in->integer("frames", -1, 1, 100000000);
  if (!fps || !in->choice("mode", "realtime", {"realtime", "settled"}) ||
      !in->boolean("video", false) || !frames || !in->boolean("prefetch", false))
    return;
  check(*fps >= 1.0 && *fps <= 240.0 && (*frames == -1 || (*frames >= 1 && *frames <= 100000000)));
  path(*in);
}

void study(const std::string& body) {
  auto in = JsonInput::parse(body, {"scene", "path", "budgets", "selectors", "ssePx", "width",
                                    "height", "frames", "fps", "mode", "strips"});
  fuzz::report("JsonInput::parse", in);
  if (!in || !in->string("scene", 64)) return;
  auto budgets = service::server::numbers(*in, "budgets", {33.0}, 1.0, 10000.0);
  auto sse = service::server::numbers(*in, "ssePx", {16.0}, 0.1, 1000.0);
  if (!budgets || !sse) return;
  for (double b : *budgets) check(b >= 1.0 && b <= 10000.0);
  for (double s : *sse) check(s >= 0.1 && s <= 1000.0);
  if (!in->integer("width", 640, 16, kMaxSize) || !in->integer("height", 360, 16, kMaxSize) ||
      !in->integer("frames", 24, 1, 1000) || !in->number("fps", 30.0, 1.0, 240.0) ||
      !in->integer("strips", 3, 0, 10) ||
      !in->choice("mode", "settled", {"settled", "realtime", "both"}))
    return;
  path(*in);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string body(fuzz::view(data + 1, size - 1));
  switch (data[0] % 5) {
    case 0:
      render(body);
      break;
    case 1:
      session(body);
      break;
    case 2:
      frame(body);
      break;
    case 3:
      job(body);
      break;
    default:
      study(body);
      break;
  }
  return 0;
}
