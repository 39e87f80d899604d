// GET /healthz and GET /metrics: served by threads of their own (server/Reception.h).
#include "server/ApiReply.h"
#include "server/routes/Routes.h"

namespace service::server {

void installProbeRoutes(httplib::Server& http, ApiContext& api) {
  http.Get("/healthz", [&](const httplib::Request&, httplib::Response& res) {
    sendJson(res, 200,
             {{"status", api.stopping ? "stopping" : "ok"},
              {"workers", api.workers.size()},
              {"scenes", api.scenes.all().size()}});
  });
  http.Get("/metrics", [&](const httplib::Request&, httplib::Response& res) {
    res.set_content(api.metrics.text(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace service::server
