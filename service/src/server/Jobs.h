#pragma once
// Path jobs: a camera path rendered frame by frame on a job runner (a RenderWorker of its own,
// so that long jobs never hold up interactive frames), into the job's folder: JPEG frames, an
// optional MP4, stats.json and stats.csv. Every frame's record is kept (a job has at most
// --max-frames) for the event stream, which replays them to a client that joins late.
// Studies (hlodr study) and 3D Tiles exports (hlodr export-3dtiles) are jobs too, of their own
// kinds, on the same runners, records and expiry.
//
// A job's outputs are the user's data: each job keeps its record (job.json, its API object) in
// its folder, written at every change of state, and a server started on the same jobs folder
// lists the jobs again with their frames, stats, video and reports. A job that was queued or
// running when the server stopped shows as cancelled (SIGTERM cancels it and it writes that) or,
// when the server died without a word, as failed. Finished jobs expire by a documented rule
// (JobLimits): older than keepDays, or the oldest past maxBytes in all, or past keepFinished.
#include <atomic>
#include <condition_variable>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/FrameStats.h"
#include "server/ApiTypes.h"
#include "server/FileList.h"
#include "server/Metrics.h"
#include "server/RenderWorker.h"
#include "server/SceneRegistry.h"
#include "service/ChromeTrace.h"
#include "service/Study.h"

namespace service::server {

struct JobSettings {
  RenderSettings render;
  hlod::FrameMode mode = hlod::FrameMode::Realtime;
  double fps = 30.0;
  long long frames = -1;  // render only the first N; < 0: all
  bool video = false;
  bool prefetch = false;
  std::uint32_t segments = 1;  // > 1: rendered as that many tasks on the runners, then joined
  PathSpec path;
};

struct JobLimits {
  std::size_t maxJobs = 8;         // queued or running
  std::uint64_t maxFrames = 5000;  // per job
  std::size_t keepFinished = 50;   // older finished jobs are removed with their files
  double keepDays = 7.0;           // finished jobs older than this are removed (0: never)
  std::uint64_t maxBytes = 0;      // the oldest finished jobs go past this in all (0: no cap)
};

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* jobStateName(JobState s);

class Job {
 public:
  std::string kind = "path";  // "path", "study" or "export"
  std::string id;
  std::shared_ptr<Scene> scene;
  JobSettings settings;
  std::string createdAt;
  std::filesystem::path dir;
  std::uint64_t framesTotal = 0;
  std::uint64_t sequence = 0;       // the order jobs were made in, across restarts
  std::time_t createdTime() const;  // createdAt in seconds since 1970 (0: unreadable)

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
  // The frames so far as Chrome Trace Event JSON (service/ChromeTrace.h); nullopt before the
  // first frame (a restored job: its trace.json, written when it ended).
  std::optional<std::string> traceJson() const;
  // The trace's runs of these frames (in order): the job, or each segment of a split job.
  std::vector<TraceRun> traceRuns(std::span<const hlod::FrameRecord> frames) const;
  std::filesystem::path framePath(std::uint64_t n) const;  // empty while not rendered
  std::filesystem::path videoPath() const;
  // The MP4 is closed and holds frames: the job is done, or was cancelled after its first frame.
  bool videoReady() const { return videoReady_.load(); }
  std::atomic<bool> cancel{false};
  // The bytes of its folder, counted once it has finished (for JobLimits::maxBytes).
  std::uint64_t bytes() const;
  // A job of an earlier run of the server, from its folder's record; an Error for a folder
  // without one or with one that cannot be read.
  static hlod::Result<std::shared_ptr<Job>> restore(const std::filesystem::path& dir);

  // The runner's side.
  void setState(JobState s, const std::string& error = "");
  // Frames come in the order of their index: a split job's segments render side by side, and
  // a frame whose turn has not come waits (counted in the progress, not yet in framesDone).
  void addFrame(const hlod::FrameRecord& r);
  // Studies: how far along (0..1) and what they do now.
  void setProgress(double fraction, const std::string& what);
  std::filesystem::path reportFile(const std::string& name) const;  // empty: no such file
  StudyOptions study;
  // Writes the record (job.json) now: the runner calls it as the job's state changes.
  void saveRecord() const;

  // Exports: the tileset's folder, and its files as listed once the export is done (a restored
  // job reads its list back from the folder); null while there is none.
  std::filesystem::path tilesDir() const { return dir / "tiles"; }
  std::shared_ptr<const FileList> tileFiles() const;
  // The runner's side: what the exporter reported (for the job object) and the files it wrote,
  // kept beside them (tiles-list.json) for a server that restores the job.
  hlod::Status setExported(nlohmann::json result, FileList files);

 private:
  nlohmann::json jsonLocked() const;  // json(), with mutex_ held
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  JobState state_ = JobState::Queued;
  std::string error_;
  std::vector<hlod::FrameRecord> records_;
  std::vector<std::string> frameJson_;
  std::map<std::uint64_t, hlod::FrameRecord> waiting_;  // a split job's frames ahead of their turn
  double progress_ = 0.0;
  std::string doing_;
  std::atomic<bool> videoReady_{false};
  nlohmann::json exported_;  // an export's report, once done
  mutable std::mutex filesMutex_;
  mutable std::shared_ptr<const FileList> tileFiles_;
  // A restored job: its API object as recorded (the scene it ran may be gone), and the stats
  // files it wrote.
  std::optional<nlohmann::json> recorded_;
  mutable std::atomic<std::uint64_t> bytes_{0};
  mutable std::mutex recordMutex_;  // one writer of job.json at a time
  friend class JobManager;
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
  // The scene's store as an OGC 3D Tiles 1.1 tileset (hlodr export-3dtiles) in the job's folder,
  // as a job of kind "export".
  ApiResult<nlohmann::json> submitExport(const std::shared_ptr<Scene>& scene);
  std::vector<std::shared_ptr<Job>> list() const;  // newest first
  std::shared_ptr<Job> find(const std::string& id) const;
  // Cancels a queued or running job (true); removes a finished one with its files (false).
  ApiResult<bool> cancelOrRemove(const std::string& id);
  std::map<std::string, double> countByState() const;
  std::size_t restored() const { return restored_; }  // jobs found in the folder at start
  // Removes the finished jobs that JobLimits says go (age, bytes, count), with their folders;
  // returns how many.
  std::size_t expire();
  // Cancels every job and waits until the running ones have written what they had.
  void shutdown();

 private:
  void runPathJob(const std::shared_ptr<Job>& job, const hlod::CameraPath& path,
                  renderer::GlContext& context);
  struct SplitRun;
  // One segment of a split job ("segments": N); the last one to end joins them.
  void runPathSegment(const std::shared_ptr<Job>& job, const hlod::CameraPath& path,
                      renderer::GlContext& context, std::uint32_t index,
                      const std::shared_ptr<SplitRun>& run);
  void joinSplitJob(Job& job, SplitRun& run);
  static void runExportJob(Job& job);
  void restoreAll();
  // Gives the job its id and folder and publishes it; 429 past --max-jobs.
  ApiResult<std::shared_ptr<Job>> admitJob(std::shared_ptr<Job> job);
  ApiResult<std::shared_ptr<const hlod::CameraPath>> pathOf(const Scene& scene,
                                                            const JobSettings& s);
  RenderWorker* leastBusyRunner() const;

  std::vector<RenderWorker*> runners_;
  SceneRegistry& scenes_;
  Metrics& metrics_;
  std::filesystem::path jobsDir_;
  JobLimits limits_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Job>> jobs_;  // oldest first
  std::size_t restored_ = 0;
  std::uint64_t sequence_ = 0;  // the last job's Job::sequence
};

}  // namespace service::server
