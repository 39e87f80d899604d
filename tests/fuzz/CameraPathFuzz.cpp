// Camera path JSON (`hlodr render --path`, a job's keyframes): the input is the file's text. A
// path that parses must sample to finite cameras everywhere (never NaN, whatever its times and
// keyframes), and must write out as JSON that parses again to the same keyframes.
#include <cmath>
#include <cstdlib>

#include "FuzzSupport.h"
#include "hlod/runtime/CameraPath.h"

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkSample(const hlod::CameraSample& s) {
  const auto& c = s.camera;
  if (!std::isfinite(s.time) || !finite(c.position) || !finite(c.target) || !finite(c.up) ||
      !finite(s.velocity) || !(c.fovY > 0.0 && c.fovY < 180.0) || !finite(c.forward()) ||
      !finite(c.right()) || !finite(c.trueUp()))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto path = hlod::CameraPath::parse(fuzz::view(data, size));
  fuzz::report("CameraPath::parse", path);
  if (!path.ok()) return 0;
  const double t0 = path->startTime(), t1 = path->endTime();
  for (double f : {0.0, 0.25, 0.5, 0.999, 1.0}) checkSample(path->sample(t0 + (t1 - t0) * f));
  checkSample(path->sample(t0 - 1.0));
  checkSample(path->sample(t1 + 1.0));
  for (double fps : {30.0, 1e-3}) {
    auto frames = path->frameCount(fps);
    if (!frames.ok()) continue;
    for (std::uint64_t i : {std::uint64_t{0}, *frames / 2, *frames > 0 ? *frames - 1 : 0, *frames})
      checkSample(path->sampleFrame(i, fps));
  }
  auto again = hlod::CameraPath::parse(path->toJson());
  if (!again.ok() || again->keyframes().size() != path->keyframes().size()) std::abort();
  for (std::size_t i = 0; i < path->keyframes().size(); ++i) {
    const auto &a = path->keyframes()[i], &b = again->keyframes()[i];
    if (a.time != b.time || a.position != b.position || a.target != b.target || a.up != b.up ||
        a.fovY != b.fovY)
      std::abort();
  }
  return 0;
}
