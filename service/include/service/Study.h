#pragma once
// `hlodr study`: renders the accuracy study of a node store along a camera path (see
// hlod/study/Study.h for what is measured, hlod/study/StudyReport.h for the report).
// For each studied frame the reference (the `full` selector, settled) is drawn once; then each
// selector at each budget (and SSE at each pixel threshold) runs through the same frames in a
// session of its own: settled (only the studied frames, each loaded before it is drawn) and/or
// realtime (every frame of the path at fps, never waiting, measured at the studied frames).
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/OcclusionAuto.h"
#include "hlod/runtime/Selector.h"
#include "hlod/scene/SceneFile.h"
#include "hlod/store/NodeSource.h"
#include "hlod/study/StudyReport.h"
#include "renderer/GlContext.h"

namespace service {

struct StudyOptions {
  std::vector<double> budgets{8, 16, 33, 66, 133};
  std::vector<std::string> selectors{"lakhia", "sse", "fs"};
  std::vector<double> ssePx{1, 2, 4, 8, 16, 32};
  int width = 640;
  int height = 360;
  std::size_t frames = 24;  // frames studied, spread evenly over the path
  double fps = 30.0;
  bool settled = true;
  bool realtime = false;
  std::size_t stripFrames = 3;  // frames shown in strips at every Lakhia budget
  std::uint64_t memoryCapBytes = 0;
  // Occlusion culling of the studied runs (the reference draws every node): with it on, each
  // settled studied frame follows two unmeasured frames 1/fps apart, so that it is culled with
  // the answers of the frame before, as on a walk, not drawn as a path's first frame.
  hlod::OcclusionMode occlusion = hlod::OcclusionMode::Auto;
  // The full-detail reference holds at most this many decoded bytes (0: no cap): a front larger
  // than that is drawn in batches, loading and freeing as it goes (BatchedReference).
  std::uint64_t referenceCapBytes = std::uint64_t(1) << 30;
  // Selector constants of every studied run (`--params`: splats, progressive, c_aim ...); the
  // reference draws full detail with the defaults.
  hlod::SelectorParams selectorParams;
  // What every frame draws, the reference's too: what `hlodr render` draws without a scene
  // (textures, lambert, sun), so that the errors are those a user sees, not of flat silhouettes.
  hlod::SceneEffects effects = hlod::defaultEffects();
  // Not empty: every run's frames as Chrome Trace Event JSON here, a process per run
  // (service/ChromeTrace.h); the reference is not traced.
  std::filesystem::path trace;
};

// what: a line for a person; fraction: of the whole study.
using StudyProgress = std::function<void(const std::string& what, double fraction)>;

// Renders the study into outDir (created) and writes its report there. context: the GL context
// to render on (current on this thread), or nullptr for one of its own. A set cancel flag ends
// it early with an Error.
hlod::Result<hlod::study::StudyReport> runStudy(
    std::shared_ptr<const hlod::NodeSource> source, const hlod::CameraPath& path,
    const StudyOptions& options, const std::filesystem::path& outDir,
    const nlohmann::json& settings, const StudyProgress& progress = {},
    const std::atomic<bool>* cancel = nullptr, renderer::GlContext* context = nullptr);

}  // namespace service
