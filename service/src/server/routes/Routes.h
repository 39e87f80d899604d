#pragma once
// The routes of docs/api.md, one installer per resource (installRoutes in HttpApi.cpp calls
// them all). Each parses and validates on the HTTP thread and hands rendering to the server's
// parts in ApiContext.
#include <string>
#include <vector>

#include <httplib.h>

#include "server/HttpApi.h"

namespace service::server {

void installProbeRoutes(httplib::Server& http, ApiContext& api);    // /healthz, /metrics
void installSceneRoutes(httplib::Server& http, ApiContext& api);    // /api/scenes
void installRenderRoutes(httplib::Server& http, ApiContext& api);   // /api/render
void installSessionRoutes(httplib::Server& http, ApiContext& api);  // /api/sessions
void installJobRoutes(httplib::Server& http, ApiContext& api);      // /api/jobs
void installStudyRoutes(httplib::Server& http, ApiContext& api);    // /api/studies
// POST /api/scenes/{id}/export-3dtiles, and the exported tileset's files and ZIP
void installExportRoutes(httplib::Server& http, ApiContext& api);

// GET /api/COLLECTION, GET and DELETE /api/COLLECTION/{id} for the jobs of some kinds ("path"
// and "export", "study"): a DELETE cancels a queued or running one (200, its object) or removes
// a finished one (204). noun names it in messages ("job", "study").
void installJobCollectionRoutes(httplib::Server& http, ApiContext& api,
                                const std::string& collection,
                                const std::vector<std::string>& kinds, const std::string& noun);

}  // namespace service::server
