#pragma once
// Path jobs: a camera path rendered frame by frame on a job runner (a RenderWorker of its own,
// so that long jobs never hold up interactive frames), into the job's folder: JPEG frames, an
// optional MP4, stats.json and stats.csv. Every frame's record is kept (a job has at most
// --max-frames) for the event stream, which replays them to a client that joins late.
#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/FrameStats.h"
#include "server/ApiTypes.h"
#include "server/Metrics.h"
#include "server/RenderWorker.h"
#include "server/SceneRegistry.h"
#include "service/Study.h"

namespace service::server {

struct JobSettings {
  RenderSettings render;
  hlod::FrameMode mode = hlod::FrameMode::Realtime;
  double fps = 30.0;
  long long frames = -1;  // render only the first N; < 0: all
  bool video = false;
  bool prefetch = false;
  nlohmann::json path;  // as given: {"kind": ...} or {"keyframes": [...]}
};

struct JobLimits {
  std::size_t maxJobs = 8;         // queued or running
  std::uint64_t maxFrames = 5000;  // per job
  std::size_t keepFinished = 50;   // older finished jobs are removed with their files
};

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* jobStateName(JobState s);

class Job {
 public:
  std::string kind = "path";  // "path" or "study"
  std::string id;
  std::shared_ptr<Scene> scene;
  JobSettings settings;
  std::string createdAt;
  std::filesystem::path dir;
  std::uint64_t framesTotal = 0;

  JobState state() const;
  bool finished() const;
  nlohmann::json json() const;
  // Frames [from, ...) as JSON lines, and the state; waits up to `wait` for news when there are
  // none. For the event stream.
  struct Events {
    std::vector<std::string> frames;
    JobState state = JobState::Queued;
    std::uint64_t framesDone = 0;
    bool changedState = false;
  };
  Events eventsFrom(std::size_t from, JobState knownState, std::chrono::milliseconds wait) const;
  std::string statsJson() const;
  std::string statsCsv() const;
  std::filesystem::path framePath(std::uint64_t n) const;  // empty while not rendered
  std::filesystem::path videoPath() const;
  std::atomic<bool> cancel{false};

  // The runner's side.
  void setState(JobState s, const std::string& error = "");
  void addFrame(const hlod::FrameRecord& r);
  // Studies: how far along (0..1) and what they do now.
  void setProgress(double fraction, const std::string& what);
  std::filesystem::path reportFile(const std::string& name) const;  // empty: no such file
  StudyOptions study;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  JobState state_ = JobState::Queued;
  std::string error_;
  std::vector<hlod::FrameRecord> records_;
  std::vector<std::string> frameJson_;
  double progress_ = 0.0;
  std::string doing_;
};

class JobManager {
 public:
  JobManager(std::vector<RenderWorker*> runners, SceneRegistry& scenes, Metrics& metrics,
             std::filesystem::path jobsDir, JobLimits limits);
  ~JobManager();
  // Parses nothing: settings are validated by the API; the path is made here (for the scene).
  ApiResult<nlohmann::json> submit(const std::shared_ptr<Scene>& scene, JobSettings settings);
  // An accuracy study of the scene along the path (hlodr study), as a job of kind "study".
  ApiResult<nlohmann::json> submitStudy(const std::shared_ptr<Scene>& scene, JobSettings path,
                                        StudyOptions study);
  std::vector<std::shared_ptr<Job>> list() const;  // newest first
  std::shared_ptr<Job> find(const std::string& id) const;
  // Cancels a queued or running job (true); removes a finished one with its files (false).
  ApiResult<bool> cancelOrRemove(const std::string& id);
  std::map<std::string, double> countByState() const;
  // Cancels every job and waits until the running ones have written what they had.
  void shutdown();

 private:
  void runPathJob(const std::shared_ptr<Job>& job, const hlod::CameraPath& path,
                  renderer::GlContext& context);
  void trimFinished();
  // Gives the job its id and folder and publishes it; 429 past --max-jobs.
  ApiResult<std::shared_ptr<Job>> admitJob(std::shared_ptr<Job> job);
  ApiResult<std::shared_ptr<hlod::CameraPath>> pathOf(const Scene& scene, const JobSettings& s);
  RenderWorker* leastBusyRunner() const;

  std::vector<RenderWorker*> runners_;
  SceneRegistry& scenes_;
  Metrics& metrics_;
  std::filesystem::path jobsDir_;
  JobLimits limits_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Job>> jobs_;  // oldest first
};

}  // namespace service::server
