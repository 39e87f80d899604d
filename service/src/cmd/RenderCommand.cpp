// `hlodr render MODEL -o frame.png`: one frame of a mesh file or city folder at full detail;
// `hlodr render STORE --path PATH.json -o OUT`: a camera path through a node store (PathCommand).
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "hlod/runtime/Framing.h"
#include "renderer/GlContext.h"
#include "renderer/Renderer.h"
#include "service/Args.h"
#include "service/SceneLoading.h"
#include "service/Settings.h"

namespace service::cmd {

const char* const kRenderUsage =
    "usage: hlodr render [MODEL] -o IMAGE [options]\n"
    "\n"
    "Renders one frame of MODEL (a mesh file: .obj .ply .off .stl .gltf .glb, a CityJSON file:\n"
    ".city.json .cityjson, or a city folder written by `hlodr city`) at full detail, and prints\n"
    "the triangle count, the draw calls and the frame's time (wall, through glFinish; and the\n"
    "GPU's own where its timer queries time it: not on llvmpipe). The image format follows the\n"
    "extension of IMAGE (.png .jpg .exr).\n"
    "\n"
    "options:\n"
    "  -o, --output IMAGE      output image (required)\n"
    "  --camera PX,PY,PZ,TX,TY,TZ   camera position and target in world units\n"
    "                          (default: a three-quarter view from above framing the model)\n"
    "  --up x|y|z              world up axis (default: z for cities and CityJSON, y for mesh\n"
    "                          files)\n"
    "  --lod X                 CityJSON: the level of detail to draw, as the file names it (1,\n"
    "                          2, 2.2 ...; default: each city object at its highest)\n"
    "{size}\n"
    "{fov}\n"
    "  --scene FILE            a scene file (docs/scene.md): the effects, background and\n"
    "                          camera; its store stands in for MODEL when MODEL is omitted\n"
    "  --unlit                 no lighting (without --scene: textures, lambert and a sun)\n"
    "  --no-textures           ignore textures\n"
    "  --fog                   distance fog (density from the view distance)\n"
    "  --quiet                 no progress output\n"
    "\n"
    "\n"
    "usage: hlodr render STORE [--camera PX,PY,PZ,TX,TY,TZ] -o IMAGE [options]\n"
    "\n"
    "One frame of the node STORE (from `hlodr build`) as the server's POST /api/render draws it:\n"
    "the front the budget buys, chosen by the selector and loaded by the streaming loader.\n"
    "Prints the frame's time against the budget, its triangles and nodes per level.\n"
    "\n"
    "options:\n"
    "  --camera PX,PY,PZ,TX,TY,TZ   as above (default: the store's framing, as the server's)\n"
    "{budgetMs}\n"
    "{selector}\n"
    "{frameMode}\n"
    "{memoryMb}\n"
    "{occlusion}\n"
    "{gpuMb}\n"
    "{showOcclusion}\n"
    "  --size, --fov, --scene, --unlit, --no-textures, --fog, --quiet   as above\n"
    "  --params, --splats      as for a path, below\n"
    "\n"
    "\n"
    "usage: hlodr render STORE --path PATH.json -o OUT [options]\n"
    "\n"
    "Runs a camera path (from `hlodr path`) through the node STORE (from `hlodr build`) with the\n"
    "time-budgeted front selector and the streaming loader. OUT is a folder for a PNG sequence\n"
    "(frame_00000.png ...) or a file ending .mp4 (needs ffmpeg). Writes stats.json and\n"
    "stats.csv into the folder, or STEM.stats.json / STEM.stats.csv beside the .mp4. Each file\n"
    "is written whole under a temporary name, then renamed: a full disk leaves no torn frame.\n"
    "\n"
    "options:\n"
    "{budgetMs}\n"
    "{selector}\n"
    "{mode}\n"
    "{size}\n"
    "{fps}\n"
    "{frames}\n"
    "{segment}\n"
    "{warmup}\n"
    "{memoryMb}\n"
    "{ioMbps}\n"
    "{ioLatencyMs}\n"
    "{ioRequests}\n"
    "{uploadMs}\n"
    "{prefetch}\n"
    "{occlusion}\n"
    "{gpuMb}\n"
    "{showOcclusion}\n"
    "  --plots                 also levels.svg, toggles.svg, frametime.svg (Lakhia Figs. 7-9)\n"
    "  --trace FILE            per-frame timing as Chrome Trace Event JSON (Perfetto UI,\n"
    "                          chrome://tracing): select, upload, the passes, readback and\n"
    "                          encode as slices; resident bytes, GPU bytes and v_time as counters\n"
    "{splats}\n"
    "  --params N=V,...        selector constants by their names in the code, e.g.\n"
    "                          c_aim=0.95,c_vis=4,feedbackGain=0.2,ssePixels=16; each has a\n"
    "                          range (a wrong name or value lists them; meanings:\n"
    "                          hlod/include/hlod/runtime/Selector.h)\n"
    "  --scene, --quiet, --unlit, --no-textures, --fog   as above\n"
    "\n"
    "environment: HLODR_GL_BACKEND=egl|osmesa forces a GL backend (default: EGL, then OSMesa).\n";

hlod::Result<std::array<double, 6>> parseCamera(const std::string& s) {
  const hlod::Error usage =
      hlod::makeError("--camera needs six numbers PX,PY,PZ,TX,TY,TZ, not '" + s + "'");
  std::array<double, 6> v{};
  std::size_t start = 0;
  for (int i = 0; i < 6; ++i) {
    const std::size_t comma = s.find(',', start);
    if ((comma == std::string::npos) != (i == 5)) return usage;
    const std::string field = s.substr(start, comma == std::string::npos ? comma : comma - start);
    start = comma + 1;
    char* end = nullptr;
    v[i] = std::strtod(field.c_str(), &end);  // out of range gives inf, refused below
    if (field.empty() || *end != '\0') return usage;
    static const char* const names[6] = {"PX", "PY", "PZ", "TX", "TY", "TZ"};
    if (!std::isfinite(v[i]))
      return hlod::makeError("--camera: " + std::string(names[i]) + " is '" + field +
                             "', not a finite number");
  }
  if (v[0] == v[3] && v[1] == v[4] && v[2] == v[5])
    return hlod::makeError("--camera: the position and the target are the same point");
  return v;
}

int runRender(const Argv& argv) {
  auto args =
      parseWithPathRun(argv, {"unlit", "no-textures", "fog", "quiet"},
                       {"output", "camera", "up", "size", "fov", "path", "scene", "lod", "trace"});
  if (!args) {
    std::fprintf(stderr, "hlodr render: %s\n", args.message().c_str());
    return 2;
  }
  // No MODEL: the scene file's store, relative to the scene file.
  std::string model = args->positionals().empty() ? "" : args->positionals()[0];
  if (model.empty() && args->has("scene") && args->has("output")) {
    auto scene = hlod::readSceneFile(*args->get("scene"));
    if (!scene) {
      std::fprintf(stderr, "hlodr render: %s\n", scene.message().c_str());
      return 2;
    }
    if (!scene->store.empty())
      model = (std::filesystem::path(*args->get("scene")).parent_path() / scene->store).string();
  }
  if ((args->positionals().size() != 1 && model.empty()) || args->positionals().size() > 1 ||
      !args->has("output")) {
    const std::size_t n = args->positionals().size();
    const std::string why = n == 0  ? "no MODEL given"
                            : n > 1 ? "give one MODEL, not " + std::to_string(n) + " ('" +
                                          args->positionals()[1] + "' is the second)"
                                    : "an output is required (-o IMAGE, or -o OUT with --path)";
    std::fprintf(stderr, "hlodr render: %s\n\n%s", why.c_str(), expandUsage(kRenderUsage).c_str());
    return 2;
  }
  // Any --path: a camera path run (PathCommand.cpp checks the rest); a node store without one:
  // one budget-bound frame (RenderStoreCommand.cpp).
  if (args->has("path")) return runRenderPath(argv);
  if (args->has("trace")) {
    std::fprintf(stderr, "hlodr render: --trace is for a path (--path)\n");
    return 2;
  }
  if (isNodeStore(model)) return runRenderStoreFrame(argv);
  for (const auto* names : {&kPathRunOptions, &kPathRunFlags}) {
    for (const std::string& o : *names) {
      if (!args->has(o)) continue;
      std::fprintf(stderr, "hlodr render: --%s needs a node store\n", o.c_str());
      return 2;
    }
  }
  renderer::RenderOptions options;
  auto size = args->size(settings::get("size"));
  if (!size) {
    std::fprintf(stderr, "hlodr render: %s\n", size.message().c_str());
    return 2;
  }
  options.width = size->width;
  options.height = size->height;
  auto fov = args->number(settings::get("fov"));
  if (!fov) {
    std::fprintf(stderr, "hlodr render: %s\n", fov.message().c_str());
    return 2;
  }
  // Checked before the model loads, which can take long.
  hlod::Result<std::array<double, 6>> cameraValues = std::array<double, 6>{};
  if (auto c = args->get("camera")) cameraValues = parseCamera(*c);
  if (!cameraValues) {
    std::fprintf(stderr, "hlodr render: %s\n", cameraValues.message().c_str());
    return 2;
  }
  const bool quiet = args->has("quiet");

  auto backend = renderer::backendFromEnvironment();
  if (!backend) {
    std::fprintf(stderr, "hlodr render: %s\n", backend.message().c_str());
    return 2;
  }

  hlod::ImportOptions importOptions;
  importOptions.lod = args->get("lod", "");
  auto scene = loadScene(model, quiet, importOptions);
  if (!scene) {
    std::fprintf(stderr, "hlodr render: %s\n", scene.message().c_str());
    return 1;
  }
  if (auto up = args->get("up")) {
    const auto axis = hlod::parseUpAxis(*up);
    if (!axis) {
      std::fprintf(stderr, "hlodr render: --up must be x, y or z\n");
      return 2;
    }
    scene->up = *axis;
  }
  // An earth-centred model (a terrain in ECEF) stands on its ellipsoid normal, not an axis.
  const glm::dvec3 upVector = hlod::modelUpFrame(scene->up, scene->model.bounds()).up;
  options.up = upVector;
  auto declared = sceneFromArgs(*args, upVector);
  if (!declared) {
    std::fprintf(stderr, "hlodr render: %s\n", declared.message().c_str());
    return 2;
  }
  options.effects = declared->scene.effects;

  auto context = renderer::createContext(*backend);
  if (!context) {
    std::fprintf(stderr, "hlodr render: %s\n", context.message().c_str());
    return 1;
  }
  std::fprintf(stderr, "%s\n", renderer::describe((*context)->info()).c_str());
  auto r = renderer::Renderer::create(**context, options);
  if (!r) {
    std::fprintf(stderr, "hlodr render: %s\n", r.message().c_str());
    return 1;
  }

  const hlod::Aabb bounds = scene->model.bounds();
  std::vector<renderer::GpuMesh> meshes;
  meshes.reserve(scene->model.meshes.size());
  for (auto& m : scene->model.meshes) {
    auto gpu = renderer::GpuMesh::upload((*r)->gl(), hlod::toLocal(m));
    if (!gpu) {
      std::fprintf(stderr, "hlodr render: %s: %s\n", m.name.c_str(), gpu.message().c_str());
      return 1;
    }
    meshes.push_back(std::move(*gpu));
    m = hlod::Mesh{};  // the GPU copy is all we need now
  }
  std::vector<const renderer::GpuMesh*> drawList;
  for (const auto& m : meshes) drawList.push_back(&m);

  CameraPose camera;
  const double aspect = static_cast<double>(options.width) / options.height;
  if (auto c = args->get("camera")) {
    const std::array<double, 6>& v = *cameraValues;
    camera.position = {v[0], v[1], v[2]};
    camera.target = {v[3], v[4], v[5]};
    camera.up = upVector;
    camera.fovY = *fov;
  } else if (const auto& sc = declared->scene.camera) {
    camera.position = sc->position;
    camera.target = sc->target;
    camera.up = sc->up.value_or(upVector);
    camera.fovY = args->has("fov") ? *fov : sc->fov;
  } else {
    camera = defaultCamera(bounds, scene->up, *fov, aspect);
  }
  double zNear = 0.1, zFar = 1e5;
  clipPlanes(camera, bounds, zNear, zFar);
  auto view = renderer::makeFrameView(camera.position, camera.target, camera.up, camera.fovY,
                                      aspect, zNear, zFar);
  view.sceneCentre = bounds.centre();
  view.sceneRadius = std::max(glm::length(bounds.size()) * 0.5, 1e-3);

  (*r)->drawFrame(view, drawList);  // warm-up: first-use costs (shader JIT) are not the frame
  const auto timing = (*r)->drawFrame(view, drawList);
  const auto image = (*r)->readback();
  const auto written = renderer::writeImage(args->get("output", ""), image);
  if (!written) {
    std::fprintf(stderr, "hlodr render: %s\n", written.message().c_str());
    return 1;
  }
  // The frame's wall time through glFinish always; the GPU's own time only where its timer
  // queries time the passes (not on llvmpipe: renderer/GlContext.h).
  char gpu[48] = "";
  if (timing.gpuTimed) std::snprintf(gpu, sizeof gpu, ", GPU %.2f ms", timing.gpuMs);
  std::printf(
      "%s: %llu triangles, %llu draw calls, frame %.2f ms (wall, through glFinish)%s "
      "(%dx%d)\n",
      args->get("output", "").c_str(), static_cast<unsigned long long>(timing.triangles),
      static_cast<unsigned long long>(timing.drawCalls), timing.cpuMs, gpu, options.width,
      options.height);
  return 0;
}

}  // namespace service::cmd
