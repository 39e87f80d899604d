// GET /healthz and GET /metrics: served by threads of their own (server/Reception.h).
#include "server/ApiReply.h"
#include "server/routes/Routes.h"

namespace service::server {

void installProbeRoutes(httplib::Server& http, ApiContext& api) {
  http.Get("/healthz", [&](const httplib::Request&, httplib::Response& res) {
    // 503 while draining or stopping: a load balancer's check takes the server out of rotation.
    const char* status = api.stopping ? "stopping" : api.draining ? "draining" : "ok";
    sendJson(
        res, std::string(status) == "ok" ? 200 : 503,
        {{"status", status}, {"workers", api.workers.size()}, {"scenes", api.scenes.all().size()}});
  });
  http.Get("/metrics", [&](const httplib::Request&, httplib::Response& res) {
    res.set_content(api.metrics.text(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace service::server
