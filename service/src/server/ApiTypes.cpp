#include "server/ApiTypes.h"

namespace service::server {

std::string RenderSettings::key() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%dx%d/%g/%s/%g/%llu", width, height, budgetMs, selector.c_str(),
                ssePx, static_cast<unsigned long long>(memoryCapBytes));
  return buf + ("/" + effectsKey);
}

nlohmann::json RenderSettings::json() const {
  return {{"width", width},       {"height", height},
          {"budgetMs", budgetMs}, {"selector", selector},
          {"ssePx", ssePx},       {"memoryMb", double(memoryCapBytes) / (1024.0 * 1024.0)}};
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

}  // namespace service::server
