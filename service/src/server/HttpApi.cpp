// The HTTP API (docs/api.md): the routes of each resource (routes/), over the server's parts.
#include "server/HttpApi.h"

#include "server/routes/Routes.h"

namespace service::server {

std::size_t ApiContext::queued() const {
  return inFlight.load();
}

void installRoutes(httplib::Server& http, ApiContext& api) {
  installProbeRoutes(http, api);
  installSceneRoutes(http, api);
  installRenderRoutes(http, api);
  installSessionRoutes(http, api);
  installJobRoutes(http, api);
  installStudyRoutes(http, api);
  installExportRoutes(http, api);
}

}  // namespace service::server
