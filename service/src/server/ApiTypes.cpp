#include "server/ApiTypes.h"

#include <cmath>

namespace service::server {

std::string RenderSettings::key() const {
  char buf[200];
  std::snprintf(buf, sizeof buf, "%dx%d/%g/%s/%g/%llu/%s/%llu/%d%d", width, height, budgetMs,
                selector.c_str(), ssePx, static_cast<unsigned long long>(memoryCapBytes),
                std::string(hlod::occlusionModeName(occlusion)).c_str(),
                static_cast<unsigned long long>(gpuBudgetBytes), int(showOcclusion), int(predict));
  return buf + ("/" + effectsKey);
}

nlohmann::json RenderSettings::json() const {
  nlohmann::json j = {{"width", width},
                      {"height", height},
                      {"budgetMs", budgetMs},
                      {"selector", selector},
                      {"ssePx", ssePx},
                      {"memoryMb", double(memoryCapBytes) / (1024.0 * 1024.0)},
                      {"occlusion", std::string(hlod::occlusionModeName(occlusion))},
                      {"gpuMb", double(gpuBudgetBytes) / (1024.0 * 1024.0)},
                      {"showOcclusion", showOcclusion},
                      {"predict", predict},
                      {"effects", hlod::declaredEffects(effects)}};
  if (!sceneFile.empty()) j["sceneFile"] = sceneFile;
  return j;
}

const std::set<std::string>& renderSettingFields() {
  static const std::set<std::string> fields = {"width",         "height",   "budgetMs",  "selector",
                                               "ssePx",         "memoryMb", "occlusion", "gpuMb",
                                               "showOcclusion", "predict"};
  return fields;
}

ApiResult<RenderSettings> readRenderSettings(const JsonInput& in, int maxSize, bool memory) {
  using settings::get;
  RenderSettings s;
  auto w = in.integer(get("width"), maxSize);
  auto h = in.integer(get("height"), maxSize);
  auto budget = in.number(get("budgetMs"));
  auto selector = in.choice(get("selector"));
  auto sse = in.number(get("ssePx"));
  auto mem = in.number(get("memoryMb"));
  auto occlusion = in.choice(get("occlusion"));
  auto gpu = in.number(get("gpuMb"));
  auto show = in.boolean(get("showOcclusion"));
  auto predict = in.boolean(get("predict"));
  if (!w) return badRequest(w.message());
  if (!h) return badRequest(h.message());
  if (!budget) return badRequest(budget.message());
  if (!selector) return badRequest(selector.message());
  if (!sse) return badRequest(sse.message());
  if (!mem) return badRequest(mem.message());
  if (!occlusion) return badRequest(occlusion.message());
  if (!gpu) return badRequest(gpu.message());
  if (!show) return badRequest(show.message());
  if (!predict) return badRequest(predict.message());
  if (!memory && in.has("memoryMb")) return badRequest("memoryMb: only for sessions and jobs");
  if (!memory && in.has("gpuMb")) return badRequest("gpuMb: only for sessions and jobs");
  s.width = int(*w);
  s.height = int(*h);
  s.budgetMs = *budget;
  s.selector = *selector;
  s.ssePx = *sse;
  s.memoryCapBytes = static_cast<std::uint64_t>(*mem * 1024.0 * 1024.0);
  s.occlusion = *hlod::parseOcclusionMode(*occlusion);  // the table's choices parse
  s.gpuBudgetBytes = static_cast<std::uint64_t>(*gpu * 1024.0 * 1024.0);
  s.showOcclusion = *show;
  s.predict = *predict;
  return s;
}

ApiResult<ImageRequest> readImageRequest(const JsonInput& in) {
  ImageRequest r;
  auto format = in.choice(settings::get("format"));
  auto quality = in.integer(settings::get("quality"));
  if (!format) return badRequest(format.message());
  if (!quality) return badRequest(quality.message());
  r.format = *format == "png" ? renderer::ImageFormat::Png : renderer::ImageFormat::Jpeg;
  r.quality = int(*quality);
  return r;
}

nlohmann::json PathSpec::json() const {
  if (kind.empty()) return "keyframes";
  nlohmann::json j = {{"kind", kind}};
  if (duration) j["duration"] = *duration;
  return j;
}

ApiResult<PathSpec> readPathSpec(const JsonInput& in) {
  if (!in.has("path")) return badRequest("path: is required");
  const nlohmann::json& path = in.json()["path"];
  PathSpec spec;
  if (path.is_object() && path.contains("kind")) {
    auto p = JsonInput::of(path, "path", {"kind", "duration"});
    if (!p) return badRequest(p.message());
    auto kind = p->choice(settings::get("pathKind"));
    auto duration = p->number(settings::get("duration"));
    if (!kind) return badRequest(kind.message());
    if (!duration) return badRequest(duration.message());
    spec.kind = *kind;
    if (p->has("duration")) spec.duration = *duration;
    return spec;
  }
  if (path.is_object() && path.contains("keyframes")) {
    auto parsed = hlod::CameraPath::parse(path.dump());
    if (!parsed) return badRequest("path: " + parsed.message());
    spec.keyframes = std::make_shared<const hlod::CameraPath>(std::move(*parsed));
    return spec;
  }
  return badRequest("path: must be {\"kind\": ...} or {\"keyframes\": [...]}");
}

}  // namespace service::server
