// 3D Tiles exports as jobs: POST /api/scenes/{id}/export-3dtiles starts one (hlodr
// export-3dtiles, into the job's folder); the tileset's files are served from
// /api/jobs/{id}/tiles/ so that a viewer loads tileset.json straight from its URL, and the whole
// tileset downloads as one stored ZIP from /api/jobs/{id}/tiles.zip. Listing, reading and
// removing the jobs are the /api/jobs routes (JobRoutes.cpp).
#include <memory>

#include "server/ApiReply.h"
#include "server/StoredZip.h"
#include "server/routes/Routes.h"

namespace service::server {

using httplib::Request;
using httplib::Response;

namespace {

// What each file of an export is, by its extension; anything else the exporter might write is
// bytes.
const char* tileFileType(const std::string& name) {
  const auto ends = [&](const char* ext) { return name.ends_with(ext); };
  if (ends(".json")) return "application/json";
  if (ends(".glb")) return "model/gltf-binary";
  if (ends(".gltf")) return "model/gltf+json";
  if (ends(".png")) return "image/png";
  if (ends(".jpg") || ends(".jpeg")) return "image/jpeg";
  return "application/octet-stream";
}

// The done export named by the route's first parameter, with its files; answered (400, 404,
// 409, 500) when there is none.
std::shared_ptr<const FileList> exportFilesOf(ApiContext& api, const Request& req, Response& res,
                                              std::shared_ptr<Job>& job) {
  auto id = pathParam(req, 1, "job id", res);
  if (!id) return nullptr;
  job = api.jobs.find(*id);
  if (!job || job->kind != "export") {
    sendError(res, notFound("no export job " + *id));
    return nullptr;
  }
  const JobState state = job->state();
  if (state == JobState::Queued || state == JobState::Running) {
    sendError(res, {409, "conflict",
                    "job " + job->id + " is " + jobStateName(state) +
                        ": its tileset exists once it is done"});
    return nullptr;
  }
  if (state != JobState::Done) {
    sendError(res,
              notFound("job " + job->id + " is " + jobStateName(state) + ": it wrote no tileset"));
    return nullptr;
  }
  auto files = job->tileFiles();
  if (!files) sendError(res, {500, "internal", "the tileset of job " + job->id + " is missing"});
  return files;
}

}  // namespace

void installExportRoutes(httplib::Server& http, ApiContext& api) {
  http.Post(R"(/api/scenes/([^/]+)/export-3dtiles)", [&](const Request& req, Response& res) {
    auto id = pathParam(req, 1, "scene id", res);
    if (!id) return;
    if (!jsonBody(req, res)) return;
    // No settings yet: an empty body or {}.
    auto in = JsonInput::parse(req.body, {});
    if (!in) return sendError(res, badRequest(in.message()));
    auto scene = api.scenes.find(*id);
    if (!scene) return sendError(res, notFound("no scene '" + *id + "'"));
    if (api.stopping) return sendError(res, {503, "busy", "the server is shutting down"});
    auto job = api.jobs.submitExport(scene);
    if (!job) return sendError(res, job.error());
    sendJson(res, 202, *job);
  });

  http.Get(R"(/api/jobs/([^/]+)/tiles/(.+))", [&](const Request& req, Response& res) {
    // The name is checked, then looked up in the files the export wrote: only a listed name
    // becomes a path (httplib has decoded %2F and %2E already, so "..%2f" arrives as "../").
    auto name = pathParam(req, 2, "file", res);
    if (!name) return;
    if (!FileList::isInsideName(*name))
      return sendError(res, badRequest("file: must be a path inside the tileset's folder "
                                       "(relative, '/'-separated, no '.' or '..' parts)"));
    std::shared_ptr<Job> job;
    auto files = exportFilesOf(api, req, res, job);
    if (!files) return;
    const ListedFile* file = files->find(*name);
    if (!file) return sendError(res, notFound("the tileset has no file " + *name));
    if (!sendFile(res, job->tilesDir() / file->name, tileFileType(file->name)))
      return sendError(res, {500, "internal", "the tileset's file " + file->name + " is missing"});
  });

  http.Get(R"(/api/jobs/([^/]+)/tiles\.zip)", [&](const Request& req, Response& res) {
    std::shared_ptr<Job> job;
    auto files = exportFilesOf(api, req, res, job);
    if (!files) return;
    auto zip = StoredZip::make(job->tilesDir(), *files, job->createdTime());
    if (!zip)
      return sendError(res, {409, "conflict",
                             "the tileset does not fit a ZIP (" + zip.message() +
                                 "): fetch its files from /api/jobs/" + job->id + "/tiles/"});
    auto shared = std::make_shared<const StoredZip>(std::move(*zip));
    res.set_header("Content-Disposition", "attachment; filename=\"" + job->id + "-3dtiles.zip\"");
    // In pieces of at most 1 MiB: each read from the folder as it is sent.
    res.set_content_provider(
        shared->size(), "application/zip",
        [shared](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
          std::string piece;
          if (!shared->read(offset, std::min<std::size_t>(length, 1 << 20), piece)) return false;
          return sink.write(piece.data(), piece.size());
        });
  });
}

}  // namespace service::server
