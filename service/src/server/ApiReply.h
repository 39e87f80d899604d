#pragma once
// What every route of the API does with its request and its answer: JSON answers and errors
// (docs/api.md "Errors"), frames with their timing headers, files, the media type of a body,
// parameters taken from the path, and a place in the render queue.
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/ApiTypes.h"

namespace service::server {

struct ApiContext;

void sendJson(httplib::Response& res, int status, const nlohmann::json& body);
// The error object; 503 and 429 carry Retry-After. Whatever bytes the message holds (an id
// from the path), the answer is valid JSON.
void sendError(httplib::Response& res, const ApiError& e);
// A body, when there is one, must be JSON: its media type is compared case-insensitively and
// exactly (parameters after ';' aside). false: answered 415.
bool jsonBody(const httplib::Request& req, httplib::Response& res);
void sendFrame(httplib::Response& res, const FrameAnswer& a, double totalMs);
bool sendFile(httplib::Response& res, const std::filesystem::path& path, const char* type);
// Path parameter `index` of the route (an id, a file name), named `name` in errors: 400 when
// it is not UTF-8 text of at most 256 bytes without control characters (ids are compared as
// bytes; such a one can name nothing).
std::optional<std::string> pathParam(const httplib::Request& req, std::size_t index,
                                     const char* name, httplib::Response& res);

// A place in the render queue, held from admission until the answer is ready (the worker's own
// task counter would still count a task whose answer has gone out).
class QueueSlot {
 public:
  explicit QueueSlot(std::atomic<std::size_t>* n) : n_(n) {}
  QueueSlot(QueueSlot&& o) noexcept : n_(o.n_) { o.n_ = nullptr; }
  QueueSlot(const QueueSlot&) = delete;
  ~QueueSlot() {
    if (n_) --*n_;
  }
  explicit operator bool() const { return n_ != nullptr; }

 private:
  std::atomic<std::size_t>* n_;
};

// Room in the render queue: past it, 503 with Retry-After (the client tries again).
QueueSlot admit(ApiContext& api, httplib::Response& res);

}  // namespace service::server
