// `hlodr calibrate`: measures c_tex of Lakhia eq. 1 on this machine's GL and stores it.
//
// Lakhia III-B: "The constant weight, c_tex, is calculated empirically by comparing the render
// time of a set of triangles both with texture and with flat shading." With eq. 1,
// cost = numTexTri * c_tex + numUnTexTri * (1 - c_tex), the ratio of the two weights must equal
// the ratio of the two times, so c_tex = t_tex / (t_tex + t_flat).
#include <algorithm>
#include <cstdio>
#include <vector>

#include "cmd/Commands.h"
#include "hlod/builder/Calibration.h"
#include "hlod/city/City.h"
#include "renderer/GlContext.h"
#include "renderer/Renderer.h"
#include "service/Args.h"
#include "service/SceneLoading.h"

namespace service::cmd {

const char* const kCalibrateUsage =
    "usage: hlodr calibrate [--blocks N] [--frames N] [--size WxH] [--dry-run]\n"
    "\n"
    "Measures c_tex (Lakhia eq. 1: the weight of a textured triangle against a flat-shaded one)\n"
    "by rendering the same city blocks with and without textures, and writes it to the\n"
    "calibration file that `hlodr build` reads ($HLODR_CALIBRATION, else\n"
    "$XDG_CONFIG_HOME/hlodr/calibration.json). Without calibration, build uses 0.6.\n"
    "\n"
    "  --blocks N   city blocks to draw (default 8)\n"
    "  --frames N   frames timed per variant; the median is used (default 7)\n"
    "  --size WxH   frame size (default 1280x720)\n"
    "  --dry-run    print the value, do not store it\n";

namespace {

// Median wall time of the frames of one variant (textures on or off).
double medianFrameMs(renderer::GlContext& context, const std::vector<hlod::Mesh>& blocks,
                     bool textures, int width, int height, int frames, std::string& error) {
  renderer::RenderOptions options;
  options.width = width;
  options.height = height;
  options.effects.textures = textures;
  auto r = renderer::Renderer::create(context, options);
  if (!r) {
    error = r.message();
    return 0.0;
  }
  std::vector<renderer::GpuMesh> gpu;
  hlod::Model model;
  for (const auto& b : blocks) {
    auto g = renderer::GpuMesh::upload(context.gl(), hlod::toLocal(b));
    if (!g) {
      error = g.message();
      return 0.0;
    }
    gpu.push_back(std::move(*g));
    model.meshes.push_back(b);
  }
  std::vector<const renderer::GpuMesh*> list;
  for (const auto& g : gpu) list.push_back(&g);
  const double aspect = double(width) / height;
  const auto cam = defaultCamera(model.bounds(), hlod::UpAxis::Z, 50.0, aspect);
  double zNear = 0.1, zFar = 1e5;
  clipPlanes(cam, model.bounds(), zNear, zFar);
  const auto view =
      renderer::makeFrameView(cam.position, cam.target, cam.up, cam.fovY, aspect, zNear, zFar);
  (*r)->drawFrame(view, list);  // warm-up
  std::vector<double> ms;
  for (int i = 0; i < frames; ++i) ms.push_back((*r)->drawFrame(view, list).cpuMs);
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int runCalibrate(const Argv& argv) {
  auto args = Args::parse(argv, {"dry-run"}, {"blocks", "frames", "size"});
  if (!args || !args->positionals().empty()) {
    std::fprintf(stderr, "hlodr calibrate: %s\n%s",
                 args ? "unexpected argument" : args.message().c_str(), kCalibrateUsage);
    return 2;
  }
  auto blocks = args->integer("blocks", 8, 1, 256);
  auto frames = args->integer("frames", 7, 1, 100);
  for (const auto* r : {&blocks, &frames})
    if (!*r) {
      std::fprintf(stderr, "hlodr calibrate: %s\n%s", r->message().c_str(), kCalibrateUsage);
      return 2;
    }
  auto size = args->size("size", "1280x720", 1, 8192);
  if (!size) {
    std::fprintf(stderr, "hlodr calibrate: %s\n%s", size.message().c_str(), kCalibrateUsage);
    return 2;
  }
  const int width = size->width, height = size->height;
  auto backend = renderer::backendFromEnvironment();
  if (!backend) {
    std::fprintf(stderr, "hlodr calibrate: %s\n", backend.message().c_str());
    return 2;
  }
  auto context = renderer::createContext(*backend);
  if (!context) {
    std::fprintf(stderr, "hlodr calibrate: %s\n", context.message().c_str());
    return 1;
  }
  std::fprintf(stderr, "%s\n", renderer::describe((*context)->info()).c_str());

  hlod::CityOptions city;
  city.blocks = static_cast<int>(*blocks);
  std::vector<hlod::Mesh> meshes;
  std::size_t triangles = 0;
  for (int i = 0; i < city.blocks; ++i) {
    meshes.push_back(hlod::generateBlock(city, i));
    triangles += meshes.back().triangleCount();
  }
  std::string error;
  const double tTex = medianFrameMs(**context, meshes, true, width, height, int(*frames), error);
  const double tFlat = medianFrameMs(**context, meshes, false, width, height, int(*frames), error);
  if (!error.empty() || tTex <= 0.0 || tFlat <= 0.0) {
    std::fprintf(stderr, "hlodr calibrate: %s\n",
                 error.empty() ? "no time measured" : error.c_str());
    return 1;
  }
  const double cTex = tTex / (tTex + tFlat);
  std::printf("%zu triangles at %dx%d: textured %.2f ms, flat %.2f ms -> c_tex = %.4f\n", triangles,
              width, height, tTex, tFlat, cTex);
  if (args->has("dry-run")) return 0;
  const auto written = hlod::writeCalibration(cTex);
  if (!written) {
    std::fprintf(stderr, "hlodr calibrate: %s\n", written.message().c_str());
    return 1;
  }
  auto path = hlod::calibrationPath();
  std::printf("stored in %s\n", path ? path->c_str() : "the calibration file");
  return 0;
}

}  // namespace service::cmd
