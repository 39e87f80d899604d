// The HTTP service's request bodies, without sockets: the first byte picks the endpoint (POST
// /api/render, /api/sessions, /api/sessions/ID/frame, /api/jobs, /api/studies), the rest is the
// body, read with the same fields and in the same order as server/routes/ read it (by the
// settings table, service/Settings.h). Every
// body must give a validated request or a 400 naming the problem; what validated must be in the
// ranges the workers rely on (finite cameras, sizes and budgets in range, a path that parses).
#include <algorithm>
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

// In the table's range.
bool within(double v, const char* id) {
  const service::Setting& s = service::settings::get(id);
  return v >= s.lo && v <= s.hi;
}

bool settings(const JsonInput& in, bool memory) {
  auto s = service::server::readRenderSettings(in, kMaxSize, memory);
  if (!s) return false;
  check(s->width >= 16 && s->width <= kMaxSize && s->height >= 16 && s->height <= kMaxSize &&
        within(s->budgetMs, "budgetMs") && within(s->ssePx, "ssePx"));
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
  // Keyframes are parsed at the boundary; a generated kind is one the generators know.
  const auto kinds = hlod::cameraPathKinds();
  check(spec->kind.empty() ? spec->keyframes != nullptr
                           : std::find(kinds.begin(), kinds.end(), spec->kind) != kinds.end());
  if (spec->duration) check(within(*spec->duration, "duration"));
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
  if (!in->choice(service::settings::get("frameMode"))) return;
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
  if (!in || !in->boolean(service::settings::get("still")) || !image(*in)) return;
  checkCamera(*in);
}

void job(const std::string& body) {
  auto in = JsonInput::parse(
      body, with({"scene", "path", "fps", "mode", "video", "frames", "prefetch"}, true));
  fuzz::report("JsonInput::parse", in);
  if (!in) return;
  sceneChoice(*in);
  if (!settings(*in, true)) return;
  using service::settings::get;
  auto fps = in->number(get("fps"));
  auto frames = in->integer(get("frames"));
  if (!fps || !in->choice(get("mode")) || !in->boolean(get("video")) || !frames ||
      !in->boolean(get("prefetch")))
    return;
  check(within(*fps, "fps") && (!in->has("frames") || within(double(*frames), "frames")));
  path(*in);
}

void study(const std::string& body) {
  auto in = JsonInput::parse(body, {"scene", "path", "budgets", "selectors", "ssePx", "width",
                                    "height", "frames", "fps", "mode", "strips"});
  fuzz::report("JsonInput::parse", in);
  if (!in || !in->string("scene", 64)) return;
  using service::settings::get;
  auto budgets = in->numbers(get("study.budgets"));
  auto sse = in->numbers(get("study.ssePx"));
  if (!budgets || !sse || !in->choices(get("study.selectors"))) return;
  for (double b : *budgets) check(within(b, "study.budgets"));
  for (double s : *sse) check(within(s, "study.ssePx"));
  if (!in->integer(get("width"), kMaxSize) || !in->integer(get("height"), kMaxSize) ||
      !in->integer(get("study.frames")) || !in->number(get("fps")) ||
      !in->integer(get("study.strips")) || !in->choice(get("study.mode")))
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
