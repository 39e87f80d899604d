#include "server/ApiReply.h"

#include <cstdio>
#include <fstream>

#include "server/HttpApi.h"

namespace service::server {

using httplib::Request;
using httplib::Response;

namespace {

// Well-formed UTF-8 (no overlong forms, no surrogates, nothing past U+10FFFF).
bool isUtf8(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    }
    if ((c & 0xe0) == 0xc0) {
      n = 1;
      cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      n = 2;
      cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      n = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return false;
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3f);
    }
    static const std::uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    i += n + 1;
  }
  return true;
}

}  // namespace

void sendJson(Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

void sendError(Response& res, const ApiError& e) {
  if (e.status == 503 || e.status == 429) res.set_header("Retry-After", "1");
  sendJson(res, e.status, {{"error", {{"code", e.code}, {"message", e.message}}}});
}

bool jsonBody(const Request& req, Response& res) {
  if (req.body.empty()) return true;
  std::string type = req.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  while (!type.empty() && (type.back() == ' ' || type.back() == '\t')) type.pop_back();
  for (char& c : type) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (type != "application/json") {
    sendError(res, {415, "unsupported_media_type", "the body must be application/json"});
    return false;
  }
  return true;
}

void sendFrame(Response& res, const FrameAnswer& a, double totalMs) {
  const hlod::FrameRecord& r = a.record;
  char timing[400];
  std::snprintf(timing, sizeof timing,
                "queue;dur=%.2f, select;dur=%.2f, upload;dur=%.2f, draw;dur=%.2f, "
                "readback;dur=%.2f, encode;dur=%.2f, total;dur=%.2f",
                a.queueMs, r.selectorMs, r.uploadMs, r.drawMs, a.readbackMs, a.encodeMs, totalMs);
  res.set_header("Server-Timing", timing);
  nlohmann::json stats = nlohmann::json::parse(hlod::frameJson(r));
  if (!a.session.empty()) {
    stats["session"] = a.session;
    stats["budgetMs"] = a.budgetMs;
    stats["sharedBy"] = a.sharedBy;
  }
  res.set_header("X-Hlodr-Stats", stats.dump());
  res.set_header("Cache-Control", "no-store");
  res.status = 200;
  res.set_content(reinterpret_cast<const char*>(a.bytes.data()), a.bytes.size(),
                  renderer::mimeType(a.format));
}

bool sendFile(Response& res, const std::filesystem::path& path, const char* type) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  res.status = 200;
  res.set_content(std::move(bytes), type);
  return true;
}

std::optional<std::string> pathParam(const Request& req, std::size_t index, const char* name,
                                     Response& res) {
  const std::string v = req.matches[index];
  bool text = v.size() <= 256 && isUtf8(v);
  for (const char c : v)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) text = false;
  if (!text) {
    sendError(res, badRequest(std::string(name) +
                              ": must be UTF-8 text of at most 256 bytes without control "
                              "characters"));
    return std::nullopt;
  }
  return v;
}

QueueSlot admit(ApiContext& api, Response& res) {
  if (api.stopping) {
    sendError(res, {503, "busy", "the server is shutting down"});
    return QueueSlot(nullptr);
  }
  if (++api.inFlight > api.queueLimit) {
    --api.inFlight;
    api.metrics.add("hlodr_rejected_total", "reason=\"queue\"");
    sendError(res, {503, "busy",
                    "the render queue is full (" + std::to_string(api.queueLimit) +
                        " requests); try again"});
    return QueueSlot(nullptr);
  }
  return QueueSlot(&api.inFlight);
}

}  // namespace service::server
