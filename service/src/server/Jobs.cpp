#include "server/Jobs.h"

#include <algorithm>
#include <ctime>

#include "hlod/runtime/PathRun.h"
#include "renderer/VideoWriter.h"
#include "server/Sessions.h"

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
    return hlod::Ok{};
  }
  hlod::Status finish() override { return hlod::Ok{}; }

 private:
  Job& job_;
  Metrics& metrics_;
};

}  // namespace

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
    records_.push_back(r);
    frameJson_.push_back(hlod::frameJson(r));
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
  const std::string base = "/api/jobs/" + id;
  const bool done =
      state_ == JobState::Done || state_ == JobState::Failed || state_ == JobState::Cancelled;
  nlohmann::json settingsJson = settings.render.json();
  settingsJson["mode"] = settings.mode == hlod::FrameMode::Settled ? "settled" : "realtime";
  settingsJson["fps"] = settings.fps;
  settingsJson["video"] = settings.video;
  settingsJson["prefetch"] = settings.prefetch;
  settingsJson["path"] =
      settings.path.contains("kind") ? settings.path : nlohmann::json("keyframes");
  if (kind == "study") {
    nlohmann::json j = {
        {"id", id},
        {"kind", kind},
        {"scene", scene->id},
        {"state", jobStateName(state_)},
        {"progress", progress_},
        {"doing", doing_},
        {"createdAt", createdAt},
        {"settings",
         {{"width", study.width},
          {"height", study.height},
          {"frames", study.frames},
          {"budgets", study.budgets},
          {"selectors", study.selectors},
          {"ssePx", study.ssePx},
          {"mode", study.settled && study.realtime ? "both"
                   : study.realtime                ? "realtime"
                                                   : "settled"},
          {"path", settings.path.contains("kind") ? settings.path : nlohmann::json("keyframes")}}},
        {"finished", done},
        {"outputs",
         {{"report", state_ == JobState::Done
                         ? nlohmann::json("/api/studies/" + id + "/report/index.html")
                         : nlohmann::json(nullptr)}}}};
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
      {"progress", framesTotal ? double(records_.size()) / double(framesTotal) : 0.0},
      {"createdAt", createdAt},
      {"settings", settingsJson},
      {"summary", nlohmann::json::parse(hlod::summaryJson(hlod::summarize(records_)))},
      {"outputs",
       {{"video", settings.video && state_ == JobState::Done ? nlohmann::json(base + "/video.mp4")
                                                             : nlohmann::json(nullptr)},
        {"statsJson", base + "/stats"},
        {"statsCsv", base + "/stats.csv"},
        {"events", base + "/events"},
        {"frames", base + "/frames/{n}"}}}};
  if (!error_.empty()) j["error"] = error_;
  j["finished"] = done;
  return j;
}

std::string Job::statsJson() const {
  std::lock_guard lock(mutex_);
  return hlod::statsJson(records_, hlod::summarize(records_));
}

std::string Job::statsCsv() const {
  std::lock_guard lock(mutex_);
  return hlod::statsCsv(records_);
}

fs::path Job::framePath(std::uint64_t n) const {
  {
    std::lock_guard lock(mutex_);
    if (n >= records_.size()) return {};
  }
  return dir / "frames" / renderer::ImageSequenceSink::frameName(n, "jpg");
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
      limits_(limits) {}

JobManager::~JobManager() = default;

ApiResult<std::shared_ptr<hlod::CameraPath>> JobManager::pathOf(const Scene& scene,
                                                                const JobSettings& settings) {
  // The path: generated for the scene, or given. A scene file's camera is where an orbit starts.
  hlod::Result<hlod::CameraPath> path = hlod::makeError("no path");
  if (settings.path.contains("kind")) {
    const std::string kind = settings.path["kind"].get<std::string>();
    const hlod::Skeleton& sk = scene.store->skeleton();
    if (kind == "orbit" && settings.render.camera) {
      const double aspect = double(settings.render.width) / settings.render.height;
      path = hlod::makeOrbitPathFrom(scene.defaultCamera(aspect, settings.render.camera), sk.up);
    } else {
      path = hlod::makeCameraPath(kind, *scene.store);
    }
    if (path && settings.path.contains("duration"))
      path = hlod::withDuration(*path, settings.path["duration"].get<double>());
  } else {
    path = hlod::CameraPath::parse(settings.path.dump());
  }
  if (!path) return badRequest("path: " + path.message());
  return std::make_shared<hlod::CameraPath>(std::move(*path));
}

ApiResult<std::shared_ptr<Job>> JobManager::admitJob(const std::shared_ptr<Scene>& scene,
                                                     JobSettings settings,
                                                     const std::string& kind) {
  auto job = std::make_shared<Job>();
  {
    std::lock_guard lock(mutex_);
    std::size_t active = 0;
    for (const auto& j : jobs_) active += !j->finished();
    if (active >= limits_.maxJobs)
      return ApiError{429, "too_many_jobs",
                      "at most " + std::to_string(limits_.maxJobs) +
                          " jobs queued or running; wait or cancel one"};
    do job->id = newId(kind == "study" ? 'a' : 'j');
    while (
        std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& j) { return j->id == job->id; }));
    job->kind = kind;
    job->scene = scene;
    job->settings = std::move(settings);
    job->createdAt = utcNow();
    job->dir = jobsDir_ / job->id;
    jobs_.push_back(job);
  }
  std::error_code ec;
  fs::create_directories(job->dir / "frames", ec);
  if (ec) {
    job->setState(JobState::Failed, "cannot create the job's folder: " + ec.message());
    return ApiError{500, "internal", "cannot create the job's folder: " + ec.message()};
  }
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
  auto count = (*path)->frameCount(settings.fps);
  if (!count) return badRequest("path: " + count.message());
  std::uint64_t total = *count;
  if (settings.frames >= 0) total = std::min<std::uint64_t>(total, settings.frames);
  if (total > limits_.maxFrames)
    return badRequest("the path gives " + std::to_string(total) + " frames at " +
                      std::to_string(settings.fps) + " fps, more than the server's limit of " +
                      std::to_string(limits_.maxFrames) + " (give \"frames\" or a lower fps)");
  if (settings.video && (settings.render.width % 2 || settings.render.height % 2))
    return badRequest("video: an MP4 needs an even width and height");
  auto admitted = admitJob(scene, std::move(settings), "path");
  if (!admitted) return admitted.error();
  std::shared_ptr<Job> job = *admitted;
  job->framesTotal = total;
  std::shared_ptr<hlod::CameraPath> shared = *path;
  leastBusyRunner()->post([this, job, shared](renderer::GlContext& gl) {
    if (job->cancel) {
      job->setState(JobState::Cancelled);
      return;
    }
    job->setState(JobState::Running);
    runPathJob(job, *shared, gl);
  });
  trimFinished();
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
  auto admitted = admitJob(scene, std::move(settings), "study");
  if (!admitted) return admitted.error();
  std::shared_ptr<Job> job = *admitted;
  job->study = std::move(study);
  std::shared_ptr<hlod::CameraPath> shared = *path;
  leastBusyRunner()->post([job, shared](renderer::GlContext& gl) {
    if (job->cancel) {
      job->setState(JobState::Cancelled);
      return;
    }
    job->setState(JobState::Running);
    const nlohmann::json described = job->json()["settings"];
    auto report = service::runStudy(
        job->scene->store, *shared, job->study, job->dir, described,
        [&](const std::string& what, double fraction) { job->setProgress(fraction, what); },
        &job->cancel, &gl);
    if (report)
      job->setState(JobState::Done);
    else
      job->setState(job->cancel ? JobState::Cancelled : JobState::Failed, report.message());
  });
  trimFinished();
  return job->json();
}

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
  std::vector<hlod::FrameSink*> list;
  for (auto& s : sinks) list.push_back(s.get());
  hlod::PathRunOptions o;
  o.fps = job->settings.fps;
  o.maxFrames = static_cast<long long>(job->framesTotal);
  o.mode = job->settings.mode;
  o.prefetchSeconds = job->settings.prefetch ? 1.0 : 0.0;
  auto ran = hlod::runPath((*session)->driver(), path, o, list, &job->cancel);
  job->scene->rememberVTime(job->settings.render.width, job->settings.render.height,
                            (*session)->selector().vTime());
  session->reset();  // on this thread, with its context current
  if (!ran)
    job->setState(JobState::Failed, ran.message());
  else
    job->setState(ran->cancelled ? JobState::Cancelled : JobState::Done);
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

void JobManager::trimFinished() {
  std::vector<std::shared_ptr<Job>> gone;
  {
    std::lock_guard lock(mutex_);
    std::size_t finished = 0;
    for (const auto& j : jobs_) finished += j->finished();
    for (auto it = jobs_.begin(); it != jobs_.end() && finished > limits_.keepFinished;) {
      if ((*it)->finished()) {
        gone.push_back(*it);
        it = jobs_.erase(it);
        --finished;
      } else {
        ++it;
      }
    }
  }
  for (const auto& j : gone) {
    std::error_code ec;
    fs::remove_all(j->dir, ec);
  }
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
