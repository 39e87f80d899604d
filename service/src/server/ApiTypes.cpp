#include "server/ApiTypes.h"

#include <cmath>

namespace service::server {

std::string RenderSettings::key() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%dx%d/%g/%s/%g/%llu", width, height, budgetMs, selector.c_str(),
                ssePx, static_cast<unsigned long long>(memoryCapBytes));
  return buf + ("/" + effectsKey);
}

nlohmann::json RenderSettings::json() const {
  nlohmann::json j = {{"width", width},
                      {"height", height},
                      {"budgetMs", budgetMs},
                      {"selector", selector},
                      {"ssePx", ssePx},
                      {"memoryMb", double(memoryCapBytes) / (1024.0 * 1024.0)},
                      {"effects", hlod::declaredEffects(effects)}};
  if (!sceneFile.empty()) j["sceneFile"] = sceneFile;
  return j;
}

const std::set<std::string>& renderSettingFields() {
  static const std::set<std::string> fields = {"width",    "height", "budgetMs",
                                               "selector", "ssePx",  "memoryMb"};
  return fields;
}

ApiResult<RenderSettings> readRenderSettings(const JsonInput& in, int maxSize, bool memory) {
  RenderSettings s;
  auto w = in.integer("width", 640, 16, maxSize);
  auto h = in.integer("height", 480, 16, maxSize);
  auto budget = in.number("budgetMs", 33.0, 1.0, 10000.0);
  auto selector = in.choice("selector", "lakhia", {"lakhia", "sse", "fs", "full"});
  auto sse = in.number("ssePx", 16.0, 0.1, 1000.0);
  auto mem = in.number("memoryMb", 0.0, 0.0, 1e6);
  if (!w) return badRequest(w.message());
  if (!h) return badRequest(h.message());
  if (!budget) return badRequest(budget.message());
  if (!selector) return badRequest(selector.message());
  if (!sse) return badRequest(sse.message());
  if (!mem) return badRequest(mem.message());
  if (!memory && in.has("memoryMb")) return badRequest("memoryMb: only for sessions");
  s.width = int(*w);
  s.height = int(*h);
  s.budgetMs = *budget;
  s.selector = *selector;
  s.ssePx = *sse;
  s.memoryCapBytes = static_cast<std::uint64_t>(*mem * 1024.0 * 1024.0);
  return s;
}

ApiResult<ImageRequest> readImageRequest(const JsonInput& in) {
  ImageRequest r;
  auto format = in.choice("format", "jpeg", {"jpeg", "png"});
  auto quality = in.integer("quality", 85, 1, 100);
  if (!format) return badRequest(format.message());
  if (!quality) return badRequest(quality.message());
  r.format = *format == "png" ? renderer::ImageFormat::Png : renderer::ImageFormat::Jpeg;
  r.quality = int(*quality);
  return r;
}

// A list of numbers in a range (the study's budgets, thresholds).
ApiResult<std::vector<double>> numbers(const JsonInput& in, const char* name,
                                       std::vector<double> fallback, double lo, double hi) {
  if (!in.has(name)) return fallback;
  const auto& v = in.json()[name];
  const std::string err = std::string(name) + ": must be a list of 1..16 numbers in " +
                          std::to_string(lo).substr(0, 5) + ".." + std::to_string(hi).substr(0, 6);
  if (!v.is_array() || v.empty() || v.size() > 16) return badRequest(err);
  std::vector<double> out;
  for (const auto& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
        x.get<double>() > hi)
      return badRequest(err);
    out.push_back(x.get<double>());
  }
  return out;
}

// The "path" field of a job or a study: {"kind", "duration"} or {"keyframes": [...]}.
ApiResult<nlohmann::json> readPathSpec(const JsonInput& in) {
  if (!in.has("path")) return badRequest("path: is required");
  const nlohmann::json& path = in.json()["path"];
  if (path.is_object() && path.contains("kind")) {
    auto p = JsonInput::of(path, "path", {"kind", "duration"});
    if (!p) return badRequest(p.message());
    auto kind = p->choice("kind", "", {"walk-fly", "drive", "orbit", "fly-around", "catwalk"});
    auto duration = p->number("duration", 0.0, 1.0, 3600.0);
    if (!kind) return badRequest(kind.message());
    if (!duration) return badRequest(duration.message());
    nlohmann::json spec = {{"kind", *kind}};
    if (p->has("duration")) spec["duration"] = *duration;
    return spec;
  }
  if (path.is_object() && path.contains("keyframes")) return path;
  return badRequest("path: must be {\"kind\": ...} or {\"keyframes\": [...]}");
}

}  // namespace service::server
