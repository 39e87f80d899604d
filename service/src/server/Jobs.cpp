#include "server/Jobs.h"

#include <algorithm>
#include <ctime>
#include <fstream>
#include <limits>
#include <tuple>

#include "hlod/AtomicFile.h"
#include "hlod/runtime/Framing.h"
#include "hlod/runtime/PathRun.h"
#include "hlod/runtime/Segments.h"
#include "hlod/tiles/TilesetExport.h"
#include "renderer/VideoWriter.h"
#include "server/SessionManager.h"
#include "service/ChromeTrace.h"
#include "service/SegmentJoin.h"

namespace service::server {

namespace fs = std::filesystem;

const char* jobStateName(JobState s) {
  switch (s) {
    case JobState::Queued:
      return "queued";
    case JobState::Running:
      return "running";
    case JobState::Done:
      return "done";
    case JobState::Failed:
      return "failed";
    case JobState::Cancelled:
      return "cancelled";
  }
  return "?";
}

namespace {

constexpr int kRecordVersion = 1;
// An export's files, listed when it is done (FileList), beside its tiles/ folder.
constexpr const char* kTileListFile = "tiles-list.json";

std::string readText(const fs::path& path, const std::string& fallback) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fallback;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The seconds since 1970 of utcNow()'s form; 0 for anything else (an old job).
std::time_t parseUtc(const std::string& text) {
  std::tm tm{};
  const char* end = strptime(text.c_str(), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return end && *end == '\0' ? timegm(&tm) : 0;
}

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The job's frames, as they come: records for the stats and the event stream.
class JobSink final : public hlod::FrameSink {
 public:
  explicit JobSink(Job& job, Metrics& metrics) : job_(job), metrics_(metrics) {}
  hlod::Status onFrame(const hlod::FrameRecord& r, const hlod::Image*) override {
    job_.addFrame(r);
    metrics_.add("hlodr_frames_total", "kind=\"job\"");
    metrics_.observeFrame(r.gpuMs * 1e-3);
    RenderWorker::yieldGl();  // a session's frame may go between two of the path's
    return hlod::Ok{};
  }
  hlod::Status finish() override { return hlod::Ok{}; }

 private:
  Job& job_;
  Metrics& metrics_;
};

}  // namespace

// What the segments of a split job share; the last one to end joins them.
struct JobManager::SplitRun {
  std::mutex mutex;
  std::uint32_t left = 0;
  bool started = false;
  bool cancelled = false;
  std::string error;        // the first segment's failure
  std::string sessionJson;  // the settings the stats record (as an unsplit job's)
};

std::time_t Job::createdTime() const {
  return parseUtc(createdAt);
}

JobState Job::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

bool Job::finished() const {
  const JobState s = state();
  return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled;
}

void Job::setState(JobState s, const std::string& error) {
  {
    std::lock_guard lock(mutex_);
    state_ = s;
    if (!error.empty()) error_ = error;
  }
  cv_.notify_all();
  saveRecord();
}

void Job::setProgress(double fraction, const std::string& what) {
  {
    std::lock_guard lock(mutex_);
    progress_ = fraction;
    doing_ = what;
  }
  cv_.notify_all();
}

fs::path Job::reportFile(const std::string& name) const {
  // Only the report's own files: a name of letters, digits and dashes with one of its
  // extensions. Nothing a client sends reaches outside the job's folder.
  if (name.empty() || name.size() > 64) return {};
  const auto dot = name.rfind('.');
  if (dot == std::string::npos || dot == 0) return {};
  for (std::size_t i = 0; i < dot; ++i) {
    const char c = name[i];
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-')) return {};
  }
  const std::string ext = name.substr(dot + 1);
  if (ext != "html" && ext != "svg" && ext != "png" && ext != "json" && ext != "csv") return {};
  std::error_code ec;
  const fs::path p = dir / name;
  return fs::is_regular_file(p, ec) ? p : fs::path{};
}

void Job::addFrame(const hlod::FrameRecord& r) {
  {
    std::lock_guard lock(mutex_);
    if (settings.segments > 1 && r.index != records_.size()) {
      waiting_.emplace(r.index, r);
      return;
    }
    records_.push_back(r);
    frameJson_.push_back(hlod::frameJson(r));
    // The frames of the next segment that were waiting for this one.
    for (auto it = waiting_.find(records_.size()); it != waiting_.end();
         it = waiting_.find(records_.size())) {
      records_.push_back(it->second);
      frameJson_.push_back(hlod::frameJson(it->second));
      waiting_.erase(it);
    }
  }
  cv_.notify_all();
}

Job::Events Job::eventsFrom(std::size_t from, JobState knownState,
                            std::chrono::milliseconds wait) const {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, wait, [&] { return frameJson_.size() > from || state_ != knownState; });
  Events e;
  for (std::size_t i = from; i < frameJson_.size(); ++i) e.frames.push_back(frameJson_[i]);
  e.state = state_;
  e.framesDone = frameJson_.size();
  e.changedState = state_ != knownState;
  return e;
}

nlohmann::json Job::json() const {
  std::lock_guard lock(mutex_);
  return jsonLocked();
}

nlohmann::json Job::jsonLocked() const {
  const std::string base = "/api/jobs/" + id;
  const bool done =
      state_ == JobState::Done || state_ == JobState::Failed || state_ == JobState::Cancelled;
  const nlohmann::json video =
      videoReady_ ? nlohmann::json(base + "/video.mp4") : nlohmann::json(nullptr);
  if (recorded_) {
    // As it was recorded, with what may have changed since: an interrupted job's state.
    nlohmann::json j = *recorded_;
    j["state"] = jobStateName(state_);
    j["finished"] = done;
    if (!error_.empty()) j["error"] = error_;
    if (kind == "path") j["outputs"]["video"] = video;
    return j;
  }
  // Exports and studies: what they are and how far along, then their settings and outputs.
  const auto progressJson = [&] {
    return nlohmann::json{{"id", id},
                          {"kind", kind},
                          {"scene", scene->id},
                          {"state", jobStateName(state_)},
                          {"progress", progress_},
                          {"doing", doing_},
                          {"createdAt", createdAt},
                          {"finished", done}};
  };
  if (kind == "export") {
    const bool ready = state_ == JobState::Done;
    nlohmann::json j = progressJson();
    j["settings"] = {{"format", "3d-tiles"}, {"version", "1.1"}};
    j["outputs"] = {
        {"tileset", ready ? nlohmann::json(base + "/tiles/tileset.json") : nlohmann::json(nullptr)},
        {"zip", ready ? nlohmann::json(base + "/tiles.zip") : nlohmann::json(nullptr)}};
    if (!exported_.is_null()) j["result"] = exported_;
    if (!error_.empty()) j["error"] = error_;
    return j;
  }
  nlohmann::json settingsJson = settings.render.json();
  settingsJson["mode"] = settings.mode == hlod::FrameMode::Settled ? "settled" : "realtime";
  settingsJson["fps"] = settings.fps;
  settingsJson["video"] = settings.video;
  settingsJson["prefetch"] = settings.prefetch;
  if (settings.segments > 1) settingsJson["segments"] = settings.segments;
  settingsJson["path"] = settings.path.json();
  if (kind == "study") {
    nlohmann::json j = progressJson();
    j["settings"] = {{"width", study.width},
                     {"height", study.height},
                     {"frames", study.frames},
                     {"budgets", study.budgets},
                     {"selectors", study.selectors},
                     {"ssePx", study.ssePx},
                     {"mode", study.settled && study.realtime ? "both"
                              : study.realtime                ? "realtime"
                                                              : "settled"},
                     {"path", settings.path.json()}};
    j["outputs"] = {{"report", state_ == JobState::Done
                                   ? nlohmann::json("/api/studies/" + id + "/report/index.html")
                                   : nlohmann::json(nullptr)}};
    if (!error_.empty()) j["error"] = error_;
    return j;
  }
  nlohmann::json j = {
      {"id", id},
      {"kind", kind},
      {"scene", scene->id},
      {"state", jobStateName(state_)},
      {"framesDone", records_.size()},
      {"framesTotal", framesTotal},
      {"progress",
       framesTotal ? double(records_.size() + waiting_.size()) / double(framesTotal) : 0.0},
      {"createdAt", createdAt},
      {"settings", settingsJson},
      {"summary", nlohmann::json::parse(hlod::summaryJson(hlod::summarize(records_)))},
      {"outputs",
       {{"video", video},
        {"statsJson", base + "/stats"},
        {"statsCsv", base + "/stats.csv"},
        {"trace", base + "/trace.json"},
        {"events", base + "/events"},
        {"frames", base + "/frames/{n}"}}}};
  if (!error_.empty()) j["error"] = error_;
  j["finished"] = done;
  return j;
}

std::string Job::statsJson() const {
  if (recorded_) return readText(dir / "stats.json", "{\"frames\": [], \"summary\": {}}");
  std::lock_guard lock(mutex_);
  return hlod::statsJson(records_, hlod::summarize(records_));
}

std::string Job::statsCsv() const {
  if (recorded_) return readText(dir / "stats.csv", "");
  std::lock_guard lock(mutex_);
  return hlod::statsCsv(records_);
}

std::vector<TraceRun> Job::traceRuns(std::span<const hlod::FrameRecord> frames) const {
  // A split job's segments ran in sessions of their own, each on its own clock: one process of
  // the trace each.
  std::vector<TraceRun> runs;
  const std::uint32_t n = std::max<std::uint32_t>(1, settings.segments);
  for (std::uint32_t i = 0; i < n; ++i) {
    const hlod::FrameRange r = hlod::segmentRange(framesTotal, i, n);
    const auto first =
        std::lower_bound(frames.begin(), frames.end(), r.first,
                         [](const hlod::FrameRecord& f, std::uint64_t at) { return f.index < at; });
    const auto end =
        std::lower_bound(first, frames.end(), r.end,
                         [](const hlod::FrameRecord& f, std::uint64_t at) { return f.index < at; });
    if (first == end && n > 1) continue;
    const std::string name =
        "job " + id + (n > 1 ? " segment " + std::to_string(i) + "/" + std::to_string(n) : "");
    runs.push_back({name, std::span<const hlod::FrameRecord>(first, end), settings.render.json()});
  }
  return runs;
}

std::optional<std::string> Job::traceJson() const {
  std::lock_guard lock(mutex_);
  if (recorded_) {
    std::string text = frameJson_.empty() ? "" : readText(dir / "trace.json", "");
    if (text.empty()) return std::nullopt;
    return text;
  }
  if (records_.empty()) return std::nullopt;
  return chromeTrace(traceRuns(records_)).dump();
}

fs::path Job::framePath(std::uint64_t n) const {
  {
    std::lock_guard lock(mutex_);
    if (n >= frameJson_.size()) return {};
  }
  return dir / "frames" / renderer::ImageSequenceSink::frameName(n, "jpg");
}

std::uint64_t Job::bytes() const {
  if (const std::uint64_t known = bytes_.load(); known > 0) return known;
  std::uint64_t total = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code e;
    if (it->is_regular_file(e)) total += it->file_size(e);
  }
  total = std::max<std::uint64_t>(total, 1);
  if (finished()) bytes_ = total;  // a finished job's folder no longer grows
  return total;
}

void Job::saveRecord() const {
  const nlohmann::json record = {{"record", kRecordVersion},
                                 {"job", json()},
                                 {"videoReady", videoReady_.load()},
                                 {"framesTotal", framesTotal},
                                 {"sequence", sequence}};
  // Whole or not at all (a full disk leaves the last record standing); one writer at a time.
  std::lock_guard lock(recordMutex_);
  [[maybe_unused]] const auto written = hlod::writeFileAtomically(dir / "job.json", record.dump(1));
}

hlod::Result<std::shared_ptr<Job>> Job::restore(const fs::path& dir) {
  const std::string text = readText(dir / "job.json", "");
  if (text.empty()) return hlod::makeError("no record");
  const nlohmann::json record = nlohmann::json::parse(text, nullptr, false);
  if (!record.is_object() || record.value("record", 0) != kRecordVersion ||
      !record.contains("job") || !record["job"].is_object())
    return hlod::makeError("not a job record");
  const nlohmann::json& j = record["job"];
  auto job = std::make_shared<Job>();
  job->id = j.value("id", "");
  job->kind = j.value("kind", "");
  job->createdAt = j.value("createdAt", "");
  job->dir = dir;
  const std::string state = j.value("state", "");
  if (job->id != dir.filename().string() ||
      (job->kind != "path" && job->kind != "study" && job->kind != "export") ||
      job->createdAt.empty() || state.empty())
    return hlod::makeError("not a job record");
  job->recorded_ = j;
  job->framesTotal = record.value("framesTotal", std::uint64_t{0});
  job->sequence = record.value("sequence", std::uint64_t{0});
  job->videoReady_ = record.value("videoReady", false);
  if (j.contains("settings") && j["settings"].is_object())
    job->settings.video = j["settings"].value("video", false);
  job->state_ = JobState::Failed;
  for (JobState s : {JobState::Done, JobState::Failed, JobState::Cancelled})
    if (state == jobStateName(s)) job->state_ = s;
  if (state == "queued" || state == "running")
    job->error_ = "interrupted: the server stopped while the job was " + state;
  // The frames it rendered, for its event stream's replay and its frame routes.
  if (job->kind == "path") {
    const nlohmann::json stats =
        nlohmann::json::parse(readText(dir / "stats.json", ""), nullptr, false);
    if (stats.is_object() && stats.contains("frames") && stats["frames"].is_array())
      for (const auto& f : stats["frames"]) job->frameJson_.push_back(f.dump());
  }
  return job;
}

hlod::Status Job::setExported(nlohmann::json result, FileList files) {
  if (auto s = hlod::writeFileAtomically(dir / kTileListFile, files.json().dump()); !s)
    return s.error();
  {
    std::lock_guard lock(mutex_);
    exported_ = std::move(result);
    progress_ = 1.0;
  }
  std::lock_guard lock(filesMutex_);
  tileFiles_ = std::make_shared<const FileList>(std::move(files));
  return hlod::Ok{};
}

std::shared_ptr<const FileList> Job::tileFiles() const {
  if (kind != "export" || state() != JobState::Done) return nullptr;
  std::lock_guard lock(filesMutex_);
  if (!tileFiles_) {
    // A restored job: the list it wrote as it finished.
    auto list = FileList::fromJson(
        nlohmann::json::parse(readText(dir / kTileListFile, ""), nullptr, false));
    if (list) tileFiles_ = std::make_shared<const FileList>(std::move(*list));
  }
  return tileFiles_;
}

fs::path Job::videoPath() const {
  return dir / "video.mp4";
}

JobManager::JobManager(std::vector<RenderWorker*> runners, SceneRegistry& scenes, Metrics& metrics,
                       fs::path jobsDir, JobLimits limits)
    : runners_(std::move(runners)),
      scenes_(scenes),
      metrics_(metrics),
      jobsDir_(std::move(jobsDir)),
      limits_(limits) {
  restoreAll();
}

JobManager::~JobManager() = default;

ApiResult<std::shared_ptr<const hlod::CameraPath>> JobManager::pathOf(const Scene& scene,
                                                                      const JobSettings& settings) {
  // Given as keyframes (parsed by readPathSpec), or generated for the scene: a scene file's
  // camera is where an orbit starts.
  const PathSpec& spec = settings.path;
  if (spec.keyframes) return spec.keyframes;
  const hlod::Skeleton& sk = scene.store->skeleton();
  hlod::Result<hlod::CameraPath> path = hlod::makeError("no path");
  if (spec.kind == "orbit" && settings.render.camera) {
    const double aspect = double(settings.render.width) / settings.render.height;
    path = hlod::makeOrbitPathFrom(scene.defaultCamera(aspect, settings.render.camera),
                                   hlod::modelUpFrame(sk));
  } else {
    path = hlod::makeCameraPath(spec.kind, *scene.store);
  }
  if (path && spec.duration) path = hlod::withDuration(*path, *spec.duration);
  if (!path) return badRequest("path: " + path.message());
  return std::make_shared<const hlod::CameraPath>(std::move(*path));
}

ApiResult<std::shared_ptr<Job>> JobManager::admitJob(std::shared_ptr<Job> job) {
  // The job comes whole (settings, frame count, study options): once in jobs_, HTTP threads read
  // it. Only its id, time and folder are set here, under the lock, before it is published.
  std::lock_guard lock(mutex_);
  std::size_t active = 0;
  for (const auto& j : jobs_) active += !j->finished();
  if (active >= limits_.maxJobs)
    return ApiError{429, "too_many_jobs",
                    "at most " + std::to_string(limits_.maxJobs) +
                        " jobs queued or running; wait or cancel one"};
  const char prefix = job->kind == "study" ? 'a' : job->kind == "export" ? 'e' : 'j';
  do job->id = newId(prefix);
  while (std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& j) { return j->id == job->id; }));
  job->createdAt = utcNow();
  job->sequence = ++sequence_;
  job->dir = jobsDir_ / job->id;
  std::error_code ec;
  fs::create_directories(job->kind == "export" ? job->dir : job->dir / "frames", ec);
  if (ec) return ApiError{500, "internal", "cannot create the job's folder: " + ec.message()};
  jobs_.push_back(job);
  job->saveRecord();
  return job;
}

RenderWorker* JobManager::leastBusyRunner() const {
  RenderWorker* runner = runners_.front();
  for (RenderWorker* r : runners_)
    if (r->queued() < runner->queued()) runner = r;
  return runner;
}

ApiResult<nlohmann::json> JobManager::submit(const std::shared_ptr<Scene>& scene,
                                             JobSettings settings) {
  auto path = pathOf(*scene, settings);
  if (!path) return path.error();
  // One rule with `hlodr render --path --frames`: a path may be of any length when "frames"
  // takes only its first frames; the frames rendered are what --max-frames bounds.
  auto count = (*path)->frameCount(settings.fps, settings.frames >= 0
                                                     ? std::numeric_limits<std::uint64_t>::max()
                                                     : hlod::kMaxPathFrames);
  if (!count) return badRequest("path: " + count.message());
  std::uint64_t total = *count;
  if (settings.frames >= 0) total = std::min<std::uint64_t>(total, settings.frames);
  if (total > limits_.maxFrames)
    return badRequest("the path gives " + std::to_string(total) + " frames at " +
                      std::to_string(settings.fps) + " fps, more than the server's limit of " +
                      std::to_string(limits_.maxFrames) + " (give \"frames\" or a lower fps)");
  if (settings.video && (settings.render.width % 2 || settings.render.height % 2))
    return badRequest("video: an MP4 needs an even width and height");
  if (settings.segments < 1 || settings.segments > total)
    return badRequest("segments: " + std::to_string(settings.segments) + " segments of " +
                      std::to_string(total) + " frames; give 1.." +
                      std::to_string(std::max<std::uint64_t>(total, 1)));
  auto made = std::make_shared<Job>();
  made->kind = "path";
  made->scene = scene;
  made->settings = std::move(settings);
  made->framesTotal = total;
  auto admitted = admitJob(std::move(made));
  if (!admitted) return admitted.error();
  std::shared_ptr<Job> job = *admitted;
  std::shared_ptr<const hlod::CameraPath> shared = *path;
  if (job->settings.segments > 1) {
    // Each segment a task of its own, on the least busy runner: with several runners they
    // render side by side (taking turns at GL with everything else, RenderWorker::yieldGl).
    auto run = std::make_shared<SplitRun>();
    run->left = job->settings.segments;
    for (std::uint32_t i = 0; i < job->settings.segments; ++i)
      leastBusyRunner()->post([this, job, shared, i, run](renderer::GlContext& gl) {
        runPathSegment(job, *shared, gl, i, run);
      });
    expire();
    return job->json();
  }
  leastBusyRunner()->post([this, job, shared](renderer::GlContext& gl) {
    if (job->cancel) {
      job->setState(JobState::Cancelled);
      return;
    }
    job->setState(JobState::Running);
    runPathJob(job, *shared, gl);
  });
  expire();
  return job->json();
}

ApiResult<nlohmann::json> JobManager::submitStudy(const std::shared_ptr<Scene>& scene,
                                                  JobSettings settings, StudyOptions study) {
  auto path = pathOf(*scene, settings);
  if (!path) return path.error();
  auto count = (*path)->frameCount(study.fps);
  if (!count) return badRequest("path: " + count.message());
  if (study.realtime && *count > limits_.maxFrames)
    return badRequest(
        "a realtime study renders every frame of the path: " + std::to_string(*count) +
        " frames, more than the server's limit of " + std::to_string(limits_.maxFrames));
  auto made = std::make_shared<Job>();
  made->kind = "study";
  made->scene = scene;
  made->settings = std::move(settings);
  made->study = std::move(study);
  auto admitted = admitJob(std::move(made));
  if (!admitted) return admitted.error();
  std::shared_ptr<Job> job = *admitted;
  std::shared_ptr<const hlod::CameraPath> shared = *path;
  leastBusyRunner()->post([job, shared](renderer::GlContext& gl) {
    if (job->cancel) {
      job->setState(JobState::Cancelled);
      return;
    }
    job->setState(JobState::Running);
    const nlohmann::json described = job->json()["settings"];
    auto report = service::runStudy(
        job->scene->store, *shared, job->study, job->dir, described,
        [&](const std::string& what, double fraction) {
          job->setProgress(fraction, what);
          RenderWorker::yieldGl();  // a frame done: sessions may draw between two
        },
        &job->cancel, &gl);
    if (report)
      job->setState(JobState::Done);
    else
      job->setState(job->cancel ? JobState::Cancelled : JobState::Failed, report.message());
  });
  expire();
  return job->json();
}

ApiResult<nlohmann::json> JobManager::submitExport(const std::shared_ptr<Scene>& scene) {
  auto made = std::make_shared<Job>();
  made->kind = "export";
  made->scene = scene;
  auto admitted = admitJob(std::move(made));
  if (!admitted) return admitted.error();
  std::shared_ptr<Job> job = *admitted;
  // On a job runner like the other kinds (they bound how many run at once), though it draws
  // nothing: it gives the GL turn away after every tile.
  leastBusyRunner()->post([job](renderer::GlContext&) {
    if (job->cancel) {
      job->setState(JobState::Cancelled);
      return;
    }
    job->setState(JobState::Running);
    runExportJob(*job);
  });
  expire();
  return job->json();
}

void JobManager::runExportJob(Job& job) {
  // The exporter of `hlodr export-3dtiles`, into the job's folder.
  hlod::tiles::TilesetExportOptions options;
  options.cancel = &job.cancel;
  auto report = hlod::tiles::exportTileset(
      *job.scene->store, job.tilesDir(), options, [&](std::size_t done, std::size_t total) {
        job.setProgress(double(done) / double(total),
                        std::to_string(done) + "/" + std::to_string(total) + " tiles");
        RenderWorker::yieldGl();
      });
  if (!report) {
    if (job.cancel)
      job.setState(JobState::Cancelled);
    else
      job.setState(JobState::Failed, report.message());
    return;
  }
  auto files = FileList::read(job.tilesDir());
  if (!files) return job.setState(JobState::Failed, files.message());
  const nlohmann::json result = {{"tiles", report->tiles},
                                 {"contents", report->contents},
                                 {"sharedTextures", report->sharedTextures},
                                 {"files", files->files().size()},
                                 {"bytes", report->bytes},
                                 {"geoReferenced", report->geoReferenced},
                                 {"frame", report->frame}};
  if (auto s = job.setExported(result, std::move(*files)); !s)
    return job.setState(JobState::Failed, "cannot list the tileset's files: " + s.message());
  job.setState(JobState::Done);
}

namespace {

// A path job's run, whole or one segment's.
hlod::PathRunOptions pathRunOptions(const Job& job) {
  hlod::PathRunOptions o;
  o.fps = job.settings.fps;
  o.maxFrames = static_cast<long long>(job.framesTotal);
  o.mode = job.settings.mode;
  o.prefetchSeconds = job.settings.prefetch ? 1.0 : 0.0;
  return o;
}

}  // namespace

void JobManager::runPathJob(const std::shared_ptr<Job>& job, const hlod::CameraPath& path,
                            renderer::GlContext& gl) {
  auto session = openSession(*job->scene, job->settings.render, gl, scenes_.cache());
  if (!session) {
    job->setState(JobState::Failed, session.message());
    return;
  }
  std::vector<std::unique_ptr<hlod::FrameSink>> sinks;
  sinks.push_back(std::make_unique<renderer::ImageSequenceSink>(job->dir / "frames", "jpg", 85));
  if (job->settings.video) {
    auto v = renderer::VideoWriter::open(job->dir / "video.mp4", job->settings.render.width,
                                         job->settings.render.height, job->settings.fps);
    if (!v) {
      job->setState(JobState::Failed, v.message());
      return;
    }
    sinks.push_back(std::make_unique<renderer::VideoSink>(std::move(*v)));
  }
  sinks.push_back(std::make_unique<hlod::StatsSink>(
      (job->dir / "stats.json").string(), (job->dir / "stats.csv").string(), "",
      "{\"session\":" + (*session)->settingsJson() + "}"));
  sinks.push_back(std::make_unique<JobSink>(*job, metrics_));
  // Kept in the folder for GET .../trace.json after a restart (a live job's is built from its
  // records).
  sinks.push_back(std::make_unique<ChromeTraceSink>((job->dir / "trace.json").string(),
                                                    "job " + job->id, job->settings.render.json()));
  std::vector<hlod::FrameSink*> list;
  for (auto& s : sinks) list.push_back(s.get());
  hlod::PathRunOptions o = pathRunOptions(*job);
  auto ran = hlod::runPath((*session)->driver(), path, o, list, &job->cancel);
  job->scene->rememberTiming(job->settings.render.width, job->settings.render.height,
                             (*session)->driver().timing());
  session->reset();  // on this thread, with its context current
  if (!ran) {
    job->setState(JobState::Failed, ran.message());
  } else {
    // Every sink finished: the video, if any, is a closed MP4 of the frames rendered.
    job->videoReady_ = job->settings.video && ran->framesRendered > 0;
    job->setState(ran->cancelled ? JobState::Cancelled : JobState::Done);
  }
}

void JobManager::runPathSegment(const std::shared_ptr<Job>& job, const hlod::CameraPath& path,
                                renderer::GlContext& gl, std::uint32_t index,
                                const std::shared_ptr<SplitRun>& run) {
  auto end = [&](const std::string& error, bool cancelled) {
    bool last = false;
    {
      std::lock_guard lock(run->mutex);
      if (!error.empty() && run->error.empty()) run->error = error;
      run->cancelled = run->cancelled || cancelled;
      last = --run->left == 0;
    }
    if (!error.empty()) job->cancel = true;  // the others stop: the job has failed
    if (last) joinSplitJob(*job, *run);
  };
  if (job->cancel) return end("", true);
  {
    std::lock_guard lock(run->mutex);
    if (!run->started) job->setState(JobState::Running);
    run->started = true;
  }
  auto session = openSession(*job->scene, job->settings.render, gl, scenes_.cache());
  if (!session) return end(session.message(), false);
  {
    std::lock_guard lock(run->mutex);
    if (run->sessionJson.empty()) run->sessionJson = (*session)->settingsJson();
  }
  std::vector<std::unique_ptr<hlod::FrameSink>> sinks;
  // Frames are named by their number in the whole run: the segments share the folder.
  sinks.push_back(std::make_unique<renderer::ImageSequenceSink>(job->dir / "frames", "jpg", 85));
  if (job->settings.video) {
    auto v = renderer::VideoWriter::open(job->dir / ("segment-" + std::to_string(index) + ".mp4"),
                                         job->settings.render.width, job->settings.render.height,
                                         job->settings.fps);
    if (!v) {
      session->reset();
      return end(v.message(), false);
    }
    sinks.push_back(std::make_unique<renderer::VideoSink>(std::move(*v)));
  }
  sinks.push_back(std::make_unique<JobSink>(*job, metrics_));
  std::vector<hlod::FrameSink*> list;
  for (auto& s : sinks) list.push_back(s.get());
  hlod::PathRunOptions o = pathRunOptions(*job);
  o.segmentIndex = index;
  o.segmentCount = job->settings.segments;
  auto ran = hlod::runPath((*session)->driver(), path, o, list, &job->cancel);
  job->scene->rememberTiming(job->settings.render.width, job->settings.render.height,
                             (*session)->driver().timing());
  session->reset();  // on this thread, with its context current
  if (!ran) return end(ran.message(), false);
  end("", ran->cancelled);
}

void JobManager::joinSplitJob(Job& job, SplitRun& run) {
  // The stats as an unsplit job writes them, from the frames in order.
  std::vector<hlod::FrameRecord> frames;
  {
    std::lock_guard lock(job.mutex_);
    frames = job.records_;
  }
  const std::string extra = run.sessionJson.empty() ? "" : "{\"session\":" + run.sessionJson + "}";
  std::string error = run.error;
  if (auto s = hlod::writeStatsJson((job.dir / "stats.json").string(), frames,
                                    hlod::summarize(frames), extra);
      !s && error.empty())
    error = s.message();
  if (auto s = hlod::writeStatsCsv((job.dir / "stats.csv").string(), frames); !s && error.empty())
    error = s.message();
  if (auto s = writeChromeTrace((job.dir / "trace.json").string(), job.traceRuns(frames));
      !s && error.empty())
    error = s.message();
  std::vector<fs::path> videos;
  for (std::uint32_t i = 0; i < job.settings.segments; ++i)
    videos.push_back(job.dir / ("segment-" + std::to_string(i) + ".mp4"));
  const bool complete = error.empty() && !run.cancelled && frames.size() == job.framesTotal;
  if (job.settings.video && complete) {
    if (auto s = concatVideos(videos, job.videoPath()); !s) error = s.message();
    job.videoReady_ = error.empty();
  }
  std::error_code ec;
  for (const fs::path& v : videos) fs::remove(v, ec);
  if (!error.empty())
    job.setState(JobState::Failed, error);
  else
    job.setState(complete ? JobState::Done : JobState::Cancelled);
}

std::vector<std::shared_ptr<Job>> JobManager::list() const {
  std::lock_guard lock(mutex_);
  return {jobs_.rbegin(), jobs_.rend()};
}

std::shared_ptr<Job> JobManager::find(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& j : jobs_)
    if (j->id == id) return j;
  return nullptr;
}

ApiResult<bool> JobManager::cancelOrRemove(const std::string& id) {
  auto job = find(id);
  if (!job) return notFound("no job " + id);
  if (!job->finished()) {
    job->cancel = true;
    return true;
  }
  {
    std::lock_guard lock(mutex_);
    std::erase_if(jobs_, [&](const auto& j) { return j->id == id; });
  }
  std::error_code ec;
  fs::remove_all(job->dir, ec);
  return false;
}

void JobManager::restoreAll() {
  std::error_code ec;
  std::vector<std::shared_ptr<Job>> found;
  for (const auto& e : fs::directory_iterator(jobsDir_, ec)) {
    std::error_code e2;
    if (!e.is_directory(e2)) continue;
    auto job = Job::restore(e.path());
    if (job) {
      found.push_back(*job);
      continue;
    }
    // A job's folder without its record (written by an older server, or by one that died while
    // admitting it): nobody can reach it; it goes once it is as old as a finished job would.
    const std::string name = e.path().filename().string();
    const bool jobName = name.size() == 9 && (name[0] == 'j' || name[0] == 'a' || name[0] == 'e') &&
                         name.find_first_not_of("0123456789abcdef", 1) == std::string::npos;
    const auto written = fs::last_write_time(e.path(), e2);
    if (jobName && !e2 && limits_.keepDays > 0 &&
        fs::file_time_type::clock::now() - written >
            std::chrono::duration<double>(limits_.keepDays * 86400.0))
      fs::remove_all(e.path(), e2);
  }
  // In the order they were made (createdAt has whole seconds: the sequence breaks ties).
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return std::tie(a->createdAt, a->sequence) < std::tie(b->createdAt, b->sequence);
  });
  {
    std::lock_guard lock(mutex_);
    jobs_ = std::move(found);
    for (const auto& j : jobs_) sequence_ = std::max(sequence_, j->sequence);
  }
  restored_ = jobs_.size();
  // An interrupted job's record says so from now on.
  for (const auto& j : jobs_)
    if (j->recorded_ && j->recorded_->value("state", "") != jobStateName(j->state()))
      j->saveRecord();
  expire();
}

std::size_t JobManager::expire() {
  std::vector<std::shared_ptr<Job>> finished;
  {
    std::lock_guard lock(mutex_);
    for (const auto& j : jobs_)
      if (j->finished()) finished.push_back(j);  // oldest first
  }
  // Sizes and ages outside the lock: the first count of a folder reads the disk.
  const std::time_t now = std::time(nullptr);
  std::vector<std::shared_ptr<Job>> gone;
  std::uint64_t total = 0;
  for (const auto& j : finished) total += j->bytes();
  std::size_t left = finished.size();
  for (const auto& j : finished) {
    const bool old =
        limits_.keepDays > 0 && double(now - parseUtc(j->createdAt)) > limits_.keepDays * 86400.0;
    const bool tooMany = left > limits_.keepFinished;
    const bool tooLarge = limits_.maxBytes > 0 && total > limits_.maxBytes;
    if (!old && !tooMany && !tooLarge) continue;
    gone.push_back(j);
    --left;
    total -= j->bytes();
  }
  {
    std::lock_guard lock(mutex_);
    for (const auto& j : gone) std::erase(jobs_, j);
  }
  for (const auto& j : gone) {
    std::error_code ec;
    fs::remove_all(j->dir, ec);
  }
  return gone.size();
}

std::map<std::string, double> JobManager::countByState() const {
  std::map<std::string, double> n;
  for (JobState s :
       {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed, JobState::Cancelled})
    n[jobStateName(s)] = 0;
  std::lock_guard lock(mutex_);
  for (const auto& j : jobs_) ++n[jobStateName(j->state())];
  return n;
}

void JobManager::shutdown() {
  std::vector<std::shared_ptr<Job>> all;
  {
    std::lock_guard lock(mutex_);
    all = jobs_;
  }
  for (const auto& j : all) j->cancel = true;
  // The runners finish their current frame, close the video and write the stats; queued jobs
  // see the cancel flag and end at once.
  for (RenderWorker* r : runners_) r->stop();
}

}  // namespace service::server
