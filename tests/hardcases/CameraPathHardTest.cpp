// Camera paths over absurd time ranges (issue 14): sampling a path meant a vector of every frame:
// 10^6 s at 30 fps was 4.2 GB before --frames applied, and a path from 0 to 1e300 s overflowed
// the frame count into one frame.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "hlod/CameraPath.h"

namespace hlod {
namespace {

CameraPath straightPath(double start, double duration, int keys, glm::dvec3 from,
                        glm::dvec3 velocity) {
  std::vector<CameraKeyframe> k;
  for (int i = 0; i < keys; ++i) {
    const double dt = duration * i / (keys - 1);
    CameraKeyframe key;
    key.time = start + dt;
    key.position = from + velocity * dt;
    key.target = key.position + glm::dvec3(0, 10, 0);
    k.push_back(key);
  }
  auto p = CameraPath::fromKeyframes(std::move(k));
  EXPECT_TRUE(p.ok()) << p.message();
  return std::move(*p);
}

TEST(CameraPathHard, AMillionSecondPathAt30FpsIsRefusedBeforeAnythingIsAllocated) {
  const CameraPath path = straightPath(0.0, 1e6, 3, {0, 0, 2}, {0, 1, 0});
  const auto n = path.frameCount(30.0);
  ASSERT_FALSE(n.ok());
  EXPECT_NE(n.message().find("1e+06 s at 30 fps gives 3e+07 frames"), std::string::npos)
      << n.message();
  EXPECT_NE(n.message().find(std::to_string(kMaxPathFrames)), std::string::npos) << n.message();
  // A caller that wants that many asks for them, and gets the count without a frame in memory.
  const auto allowed = path.frameCount(30.0, 40'000'000);
  ASSERT_TRUE(allowed.ok()) << allowed.message();
  EXPECT_EQ(*allowed, 30'000'001u);
  // sampleAt, which would hold all 4 GB of them, refuses.
  EXPECT_TRUE(path.sampleAt(30.0).empty());
}

TEST(CameraPathHard, APathOf1e300SecondsIsAClearErrorNotOneFrame) {
  const CameraPath path = straightPath(0.0, 1e300, 2, {0, 0, 2}, {0, 1e-300, 0});
  for (double fps : {30.0, 1e10}) {  // 3e301 frames, and a product that overflows to infinity
    const auto n = path.frameCount(fps, ~std::uint64_t{0});
    ASSERT_FALSE(n.ok()) << fps;
    EXPECT_NE(n.message().find("1e+300 s at"), std::string::npos) << n.message();
  }
  EXPECT_TRUE(path.sampleAt(30.0).empty());
}

TEST(CameraPathHard, FramesOfADayLongPathAreWhereTheyShouldBeToTheLast) {
  // 24 h at 60 fps, starting at 1000 s, at 1.5 m/s along a straight line: keyframes every
  // hour on it, so the spline is that line and frame i is at from + velocity * i / 60.
  const double start = 1000.0;
  const glm::dvec3 from{10.0, -20.0, 1.7}, velocity{1.5, 0.25, 0.0};
  const CameraPath path = straightPath(start, 86400.0, 25, from, velocity);
  const auto n = path.frameCount(60.0);
  ASSERT_TRUE(n.ok()) << n.message();
  ASSERT_EQ(*n, 86400u * 60u + 1u);
  for (std::uint64_t i = *n - 600; i < *n; ++i) {
    const CameraSample s = path.sampleFrame(i, 60.0);
    // i / 60 = q + r / 60 exactly: the frame's time is that to rounding (1 ulp of 87400 s is
    // 1.5e-11 s; adding 1/60 five million times instead drifts by microseconds).
    const double exact = start + static_cast<double>(i / 60) + static_cast<double>(i % 60) / 60.0;
    ASSERT_LE(std::abs(s.time - exact), 2.0 * (std::nextafter(exact, 1e300) - exact))
        << "frame " << i;
    const glm::dvec3 expected = from + velocity * (exact - start);
    ASSERT_LT(glm::length(s.camera.position - expected), 1e-9) << "frame " << i;
  }
  // The last frame is the last keyframe, exactly.
  const CameraSample last = path.sampleFrame(*n - 1, 60.0);
  EXPECT_EQ(last.time, path.endTime());
  EXPECT_EQ(last.camera.position, path.keyframes().back().position);
  EXPECT_EQ(last.camera.target, path.keyframes().back().target);
}

}  // namespace
}  // namespace hlod
