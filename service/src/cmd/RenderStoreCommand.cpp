// `hlodr render STORE [--camera ...] --budget-ms 33 [--mode settled] -o IMAGE`: one frame of a
// node store under a frame budget, as the server's POST /api/render draws it, without a path.
#include <cstdio>
#include <filesystem>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "cmd/SessionArgs.h"
#include "hlod/store/NodeStore.h"
#include "renderer/Renderer.h"
#include "service/SceneLoading.h"
#include "service/Session.h"
#include "service/Settings.h"

namespace service::cmd {

int runRenderStoreFrame(const Argv& argv) {
  auto args = parseWithPathRun(argv, {"quiet", "unlit", "no-textures", "fog"},
                               {"output", "camera", "up", "size", "fov", "scene", "lod"});
  if (!args) return usageError("render", args.message());
  // What only a path run or a model file takes means nothing here: said, not ignored.
  for (const char* o : {"fps", "frames", "io-mbps", "io-latency-ms", "io-requests", "upload-ms",
                        "prefetch", "plots", "segment", "warmup"})
    if (args->has(o))
      return usageError("render", std::string("--") + o + " is for a path (--path)");
  for (const char* o : {"up", "lod"})
    if (args->has(o)) return usageError("render", std::string("--") + o + " is for a model file");
  using settings::get;
  auto so = sessionFromArgs(*args);
  if (!so) return usageError("render", so.message());
  auto fov = args->number(get("fov"));
  if (!fov) return usageError("render", fov.message());
  auto mode = args->choice(get("frameMode"));
  if (!mode) return usageError("render", mode.message());
  hlod::Result<std::array<double, 6>> cameraValues = std::array<double, 6>{};
  if (auto c = args->get("camera")) cameraValues = parseCamera(*c);
  if (!cameraValues) return usageError("render", cameraValues.message());
  auto backend = renderer::backendFromEnvironment();
  if (!backend) return usageError("render", backend.message());

  auto declared = sceneFromArgs(*args, {0.0, 0.0, 1.0});
  if (!declared) return usageError("render", declared.message());
  std::string store = args->positionals().empty() ? "" : args->positionals()[0];
  if (store.empty() && declared->fromFile && !declared->scene.store.empty())
    store = (declared->file.parent_path() / declared->scene.store).string();
  auto opened = hlod::NodeStore::open(store);
  if (!opened) return commandError("render", store + ": " + opened.message());
  const hlod::Skeleton& sk = (*opened)->skeleton();
  // The default sun stands above the store's up axis, as for `hlodr render MODEL`.
  declared = sceneFromArgs(*args, hlod::upVector(sk.up));
  if (!declared) return usageError("render", declared.message());
  so->effects = declared->scene.effects;

  const double aspect = double(so->width) / so->height;
  hlod::Camera camera = storeCamera(sk, *fov, aspect);
  if (args->has("camera")) {
    const std::array<double, 6>& v = *cameraValues;
    camera.position = {v[0], v[1], v[2]};
    camera.target = {v[3], v[4], v[5]};
    camera.up = hlod::upVector(sk.up);
  } else if (const auto& sc = declared->scene.camera) {
    camera.position = sc->position;
    camera.target = sc->target;
    camera.up = sc->up.value_or(camera.up);
    camera.fovY = args->has("fov") ? *fov : sc->fov;
  }

  auto session =
      Session::create(std::shared_ptr<const hlod::NodeSource>(std::move(*opened)), *so, *backend);
  if (!session) return commandError("render", session.message());
  if (!args->has("quiet"))
    std::fprintf(stderr, "%s\n", renderer::describe((*session)->contextInfo()).c_str());
  hlod::CameraSample sample;
  sample.camera = camera;
  const hlod::FrameMode frameMode =
      *mode == "settled" ? hlod::FrameMode::Settled : hlod::FrameMode::Realtime;
  auto rec = (*session)->renderFrame(sample, frameMode);
  if (!rec) return commandError("render", rec.message());
  const std::string out = args->get("output", "");
  if (auto w = renderer::writeImage(out, (*session)->readback()); !w)
    return commandError("render", w.message());
  std::string levels;
  for (std::size_t i = 0; i < rec->nodesPerLevel.size(); ++i)
    levels += (i ? "," : "") + std::to_string(rec->nodesPerLevel[i]);
  std::printf(
      "%s: %s frame, %.2f ms of the %.1f ms budget (estimated %.2f), %llu triangles, "
      "nodes per level [%s] (%dx%d)\n",
      out.c_str(), *mode == "settled" ? "settled" : "realtime", rec->gpuMs, so->budgetMs,
      rec->estimatedMs, static_cast<unsigned long long>(rec->triangles), levels.c_str(), so->width,
      so->height);
  // A node that failed to load was drawn coarser: fail as a path run does.
  if (const std::string failure = (*session)->loadFailure(); !failure.empty())
    return commandError("render", failure);
  return 0;
}

}  // namespace service::cmd
