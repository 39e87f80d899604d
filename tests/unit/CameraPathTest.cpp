#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "RuntimeTestScene.h"
#include "hlod/runtime/CameraPath.h"

namespace hlod {
namespace {

std::vector<CameraKeyframe> threeKeys() {
  std::vector<CameraKeyframe> k(3);
  k[0] = {0.0, {0, 0, 2}, {0, 10, 2}, {0, 0, 1}, 60.0};
  k[1] = {1.0, {5, 3, 2}, {5, 13, 0}, {0, 0, 1}, 50.0};
  k[2] = {3.0, {8, 10, 6}, {0, 0, 0}, {0, 0, 1}, 40.0};
  return k;
}

TEST(CameraPath, PassesThroughEveryKeyframe) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok()) << path.message();
  for (const CameraKeyframe& k : threeKeys()) {
    const CameraSample s = path->sample(k.time);
    EXPECT_NEAR(glm::length(s.camera.position - k.position), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(s.camera.target - k.target), 0.0, 1e-12);
    EXPECT_NEAR(s.camera.fovY, k.fovY, 1e-12);
  }
  EXPECT_DOUBLE_EQ(path->sample(1.5).camera.fovY, 47.5);  // fov is linear
}

TEST(CameraPath, PositionAndVelocityAreContinuousAcrossKeyframes) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok());
  const double eps = 1e-7;
  const CameraSample before = path->sample(1.0 - eps), after = path->sample(1.0 + eps);
  EXPECT_LT(glm::length(before.camera.position - after.camera.position), 1e-5);
  EXPECT_LT(glm::length(before.velocity - after.velocity), 1e-4);  // C1
  // The velocity is the derivative of the sampled position.
  const double t = 2.2, h = 1e-5;
  const glm::dvec3 numeric =
      (path->sample(t + h).camera.position - path->sample(t - h).camera.position) / (2 * h);
  EXPECT_LT(glm::length(numeric - path->sample(t).velocity), 1e-5);
}

TEST(CameraPath, SampleAtGivesFramesAtTheFrameRateAndClampsOutsideTheRange) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok());
  const auto frames = path->sampleAt(30.0);
  ASSERT_EQ(frames.size(), 91u);
  EXPECT_DOUBLE_EQ(frames[30].time, 1.0);
  EXPECT_NEAR(frames.back().time, 3.0, 1e-12);
  EXPECT_EQ(path->sample(-5.0).camera.position, threeKeys()[0].position);
  EXPECT_EQ(path->sample(99.0).camera.position, threeKeys()[2].position);
  EXPECT_TRUE(path->sampleAt(0.0).empty());
}

TEST(CameraPath, WritesAndReadsBackTheSameKeyframes) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok());
  const auto file = std::filesystem::temp_directory_path() / "hlodr_camera_path_test.json";
  ASSERT_TRUE(path->write(file.string()).ok());
  auto back = CameraPath::read(file.string());
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->keyframes().size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back->keyframes()[i].position, threeKeys()[i].position);
    EXPECT_EQ(back->keyframes()[i].fovY, threeKeys()[i].fovY);
  }
  std::filesystem::remove(file);
}

TEST(CameraPath, MalformedInputGivesClearErrors) {
  struct Case {
    const char* json;
    const char* expect;
  };
  const Case cases[] = {
      {"{\"keyframes\": [", "malformed JSON"},
      {"{\"frames\": []}", "no \"keyframes\""},
      {"{\"keyframes\": [{\"time\":0,\"position\":[0,0,0],\"target\":[1,0,0]}]}",
       "at least 2 keyframes"},
      {"[{\"time\":0,\"position\":[0,0,0],\"target\":[1,0,0]},"
       "{\"time\":0,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "strictly increasing"},
      {"[{\"time\":1,\"position\":[0,0,0],\"target\":[1,0,0]},"
       "{\"time\":0.5,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "strictly increasing"},
      {"[{\"time\":0,\"position\":[0,0],\"target\":[1,0,0]},"
       "{\"time\":1,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "\"position\" must be an array of 3"},
      {"[{\"time\":0,\"position\":[0,0,0]},{\"time\":1,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "\"target\" is missing"},
      {"[{\"time\":\"a\",\"position\":[0,0,0],\"target\":[1,0,0]}]", "\"time\" must be a number"},
      {"[{\"time\":0,\"position\":[0,0,0],\"target\":[1,0,0],\"fov\":200},"
       "{\"time\":1,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "fov must be in"},
      {"[{\"time\":0,\"position\":[0,0,0],\"target\":[0,0,0]},"
       "{\"time\":1,\"position\":[1,0,0],\"target\":[2,0,0]}]",
       "target equals position"},
      {"42", "must be an array"},
  };
  for (const Case& c : cases) {
    auto p = CameraPath::parse(c.json);
    ASSERT_FALSE(p.ok()) << c.json;
    EXPECT_NE(p.message().find(c.expect), std::string::npos) << p.message();
  }
  EXPECT_FALSE(CameraPath::read("/nonexistent/path.json").ok());
}

TEST(CameraPath, NanKeyframesAreRejected) {
  auto keys = threeKeys();
  keys[1].position.x = std::nan("");
  auto p = CameraPath::fromKeyframes(keys);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.message().find("finite"), std::string::npos);
}

TEST(CameraPath, AKeyframeTooFarInTimeOrSpaceIsRejected) {
  auto keys = threeKeys();
  keys[0].time = -1e308;
  keys[2].time = 1e308;  // each finite, the duration is not
  auto p = CameraPath::fromKeyframes(keys);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.message().find("duration"), std::string::npos) << p.message();
  keys = threeKeys();
  keys[1].position.x = 1e308;
  keys[2].position.x = -1e308;  // the change between them overflows
  p = CameraPath::fromKeyframes(keys);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.message().find("position changes too much"), std::string::npos) << p.message();
}

// A walk at eye height followed by a climb: tangents from the neighbours' central differences
// (Catmull-Rom) gave the last walk keyframe an upward slope, and the walk dipped below the street
// before it (13 m on the default city).
TEST(CameraPath, AWalkFollowedByAClimbNeverDipsBelowTheWalk) {
  std::vector<CameraKeyframe> k(4);
  k[0] = {0.0, {0, 0, 1.7}, {0, 10, 1.7}, {0, 0, 1}, 60.0};
  k[1] = {2.0, {0, 4, 1.7}, {0, 14, 1.7}, {0, 0, 1}, 60.0};
  k[2] = {4.0, {0, 8, 1.7}, {0, 18, 1.7}, {0, 0, 1}, 60.0};
  k[3] = {6.0, {0, 12, 60.0}, {0, 40, -30.0}, {0, 0, 1}, 60.0};
  auto path = CameraPath::fromKeyframes(k);
  ASSERT_TRUE(path.ok()) << path.message();
  for (double t = 0.0; t <= 4.0; t += 0.01) {
    const CameraSample s = path->sample(t);
    ASSERT_NEAR(s.camera.position.z, 1.7, 1e-12) << "t=" << t;
    ASSERT_NEAR(s.camera.target.z, 1.7, 1e-12) << "t=" << t;
  }
  for (double t = 4.0; t <= 6.0; t += 0.01) {
    const CameraSample s = path->sample(t);
    EXPECT_GE(s.camera.position.z, 1.7 - 1e-12) << "t=" << t;
    EXPECT_LE(s.camera.position.z, 60.0 + 1e-12) << "t=" << t;
    EXPECT_GE(s.camera.target.z, -30.0 - 1e-12) << "t=" << t;
    EXPECT_LE(s.camera.target.z, 1.7 + 1e-12) << "t=" << t;
  }
}

// Random paths with uneven keyframe spacing, some coordinates repeating (flat stretches).
std::vector<CameraKeyframe> randomKeys(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> dt(0.05, 5.0), v(-100.0, 100.0), coin(0.0, 1.0);
  std::vector<CameraKeyframe> k(n);
  double t = v(rng);
  for (int i = 0; i < n; ++i) {
    t += dt(rng);
    k[i].time = t;
    for (int c = 0; c < 3; ++c) {
      k[i].position[c] = i > 0 && coin(rng) < 0.3 ? k[i - 1].position[c] : v(rng);
      k[i].target[c] = i > 0 && coin(rng) < 0.3 ? k[i - 1].target[c] : v(rng);
    }
    if (k[i].target == k[i].position) k[i].target.x += 1.0;
  }
  return k;
}

TEST(CameraPath, EveryCoordinateStaysBetweenItsTwoKeyframesOnEachSegment) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const auto keys = randomKeys(rng, 3 + trial % 10);
    auto path = CameraPath::fromKeyframes(keys);
    ASSERT_TRUE(path.ok()) << path.message();
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      const CameraKeyframe &a = keys[i], &b = keys[i + 1];
      for (int j = 1; j < 64; ++j) {
        const double t = a.time + (b.time - a.time) * j / 64.0;
        const Camera cam = path->sample(t).camera;
        for (int c = 0; c < 3; ++c) {
          const double tol = 1e-9 * (1.0 + std::abs(a.position[c]) + std::abs(b.position[c]));
          ASSERT_GE(cam.position[c], std::min(a.position[c], b.position[c]) - tol)
              << "trial " << trial << " segment " << i << " t=" << t;
          ASSERT_LE(cam.position[c], std::max(a.position[c], b.position[c]) + tol)
              << "trial " << trial << " segment " << i << " t=" << t;
          ASSERT_GE(cam.target[c], std::min(a.target[c], b.target[c]) - tol);
          ASSERT_LE(cam.target[c], std::max(a.target[c], b.target[c]) + tol);
        }
      }
    }
  }
}

TEST(CameraPath, SpeedOnASegmentIsAtMostTwiceItsChordOverItsDuration) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const auto keys = randomKeys(rng, 3 + trial % 10);
    auto path = CameraPath::fromKeyframes(keys);
    ASSERT_TRUE(path.ok()) << path.message();
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      const CameraKeyframe &a = keys[i], &b = keys[i + 1];
      const double chordSpeed = glm::length(b.position - a.position) / (b.time - a.time);
      for (int j = 0; j <= 64; ++j) {
        const double t = a.time + (b.time - a.time) * j / 64.0;
        ASSERT_LE(glm::length(path->sample(t).velocity), 2.0 * chordSpeed * (1 + 1e-9) + 1e-12)
            << "trial " << trial << " segment " << i << " t=" << t;
      }
    }
  }
}

TEST(CameraPath, SmoothKeyframesKeepTheParabolaTangents) {
  // Evenly spaced, neighbouring slopes within a factor of 3: the tangent at an interior keyframe
  // is the central difference (Catmull-Rom), the limits do not touch it.
  std::vector<CameraKeyframe> k;
  for (int i = 0; i < 6; ++i) {
    const double t = 1.0 + i;
    k.push_back({t, {t * t * t + t, 2.0 * t, 5.0}, {0, 0, 0}, {0, 0, 1}, 60.0});
  }
  auto path = CameraPath::fromKeyframes(k);
  ASSERT_TRUE(path.ok()) << path.message();
  for (std::size_t i = 1; i + 1 < k.size(); ++i) {
    const glm::dvec3 central =
        (k[i + 1].position - k[i - 1].position) / (k[i + 1].time - k[i - 1].time);
    EXPECT_LT(glm::length(path->sample(k[i].time).velocity - central), 1e-9) << "keyframe " << i;
  }
}

TEST(CameraPath, ALoopIsSmoothAcrossItsSeam) {
  // A square loop back to its start: the velocity leaving the start is the one arriving there.
  std::vector<CameraKeyframe> k;
  const glm::dvec3 corners[] = {{0, -10, 2}, {10, 0, 2}, {0, 10, 2}, {-10, 0, 2}, {0, -10, 2}};
  for (int i = 0; i < 5; ++i) k.push_back({2.0 * i, corners[i], {0, 0, 0}, {0, 0, 1}, 60.0});
  auto path = CameraPath::fromKeyframes(k);
  ASSERT_TRUE(path.ok()) << path.message();
  const glm::dvec3 start = path->sample(path->startTime()).velocity;
  EXPECT_LT(glm::length(start - path->sample(path->endTime()).velocity), 1e-12);
  EXPECT_GT(start.x, 1.0);  // leaving (0,-10) towards (10,0) as a circle through them would
  EXPECT_NEAR(start.y, 0.0, 1e-12);
}

TEST(CameraPath, FrameCountCountsBothEndsAndRefusesTooManyFrames) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok());
  ASSERT_TRUE(path->frameCount(30.0).ok());
  EXPECT_EQ(*path->frameCount(30.0), 91u);
  EXPECT_EQ(*path->frameCount(30.0, 91), 91u);
  const auto over = path->frameCount(30.0, 90);
  ASSERT_FALSE(over.ok());
  EXPECT_NE(over.message().find("3 s at 30 fps gives 91 frames"), std::string::npos)
      << over.message();
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    EXPECT_FALSE(path->frameCount(bad).ok()) << bad;
    EXPECT_TRUE(path->sampleAt(bad).empty()) << bad;
  }
  EXPECT_TRUE(path->sampleAt(30.0, 16.0 / 9.0, 90).empty());
  // 0.1 s to 0.7 s at 10 fps: 0.6 * 10 is 5.999... in double and still counts its last frame.
  auto keys = threeKeys();
  keys.resize(2);
  keys[0].time = 0.1;
  keys[1].time = 0.7;
  auto shortPath = CameraPath::fromKeyframes(keys);
  ASSERT_TRUE(shortPath.ok());
  EXPECT_EQ(*shortPath->frameCount(10.0), 7u);
  EXPECT_EQ(shortPath->sampleFrame(6, 10.0).camera.position, keys[1].position);
}

TEST(CameraPath, SampleFrameIsTheSampleAtItsOwnTime) {
  auto path = CameraPath::fromKeyframes(threeKeys());
  ASSERT_TRUE(path.ok());
  const auto all = path->sampleAt(24.0, 1.5);
  ASSERT_EQ(all.size(), *path->frameCount(24.0));
  for (std::uint64_t i = 0; i < all.size(); ++i) {
    const CameraSample s = path->sampleFrame(i, 24.0, 1.5);
    EXPECT_EQ(s.time, path->startTime() + static_cast<double>(i) / 24.0);
    EXPECT_EQ(s.camera.position, all[i].camera.position);
    EXPECT_EQ(s.camera.aspect, 1.5);
  }
  // Past the last frame: the end of the path.
  EXPECT_EQ(path->sampleFrame(1000, 24.0).camera.position, threeKeys()[2].position);
}

// Distance from a point to the nearest block box (0 inside one).
double clearance(const Skeleton& sk, const glm::dvec3& p) {
  double best = 1e300;
  for (std::uint32_t r : sk.roots) {
    best = std::min(best, distanceToBox(p, sk.nodes[r].bounds));
  }
  return best;
}

TEST(CameraPathGenerators, WalkFlyStartsInAStreetAtEyeHeightAndEndsAboveTheModel) {
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 6;
  const Skeleton sk = test::makeSyntheticCity(c);
  auto path = makeWalkFlyPath(sk);
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_GE(path->duration(), 20.0);
  EXPECT_LE(path->duration(), 40.0);
  for (double t = 0.0; t <= 15.0; t += 0.25) {
    const CameraSample s = path->sample(t);
    // At eye height for the whole walk: the climb that follows does not pull it under the street.
    EXPECT_NEAR(s.camera.position.z, 1.7, 1e-9) << "t=" << t;
    EXPECT_LT(glm::length(s.velocity), 3.0) << "t=" << t;
    EXPECT_GT(clearance(sk, s.camera.position), 1.0) << "walk enters a block at t=" << t;
  }
  const CameraSample end = path->sample(path->endTime());
  EXPECT_GT(end.camera.position.z, c.height * 2);
  EXPECT_LT(end.camera.forward().z, -0.3);  // looking down at the model
}

TEST(CameraPathGenerators, WalkFlyFindsAStreetWhereBlocksMeetAtItsCentreLine) {
  // Blocks whose ground reaches the street's middle (as the procedural city's do) leave no gap:
  // the street is the line where one box ends and the next begins.
  Skeleton sk;
  for (int i = 0; i < 4; ++i) {
    NodeInfo n;
    n.bounds.extend(glm::dvec3(i * 40.0, 0.0, 0.0));
    n.bounds.extend(glm::dvec3(i * 40.0 + 40.0, 200.0, 20.0));
    sk.roots.push_back(static_cast<std::uint32_t>(sk.nodes.size()));
    sk.nodes.push_back(n);
  }
  auto path = makeWalkFlyPath(sk);
  ASSERT_TRUE(path.ok()) << path.message();
  // The street nearest the centre (x = 80), not the model's edge.
  EXPECT_NEAR(path->sample(0.0).camera.position.x, 80.0, 1e-9);
}

// A store with cell nodes: the one root is the top cell, whose box holds its underlay far below
// the streets (1% of the city's size: 216 m under the 100 M city). The walk and the drive find
// the street from the blocks.
TEST(CameraPathGenerators, TheWalkAndTheDriveStayAtEyeHeightOnAStoreWithCells) {
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 6;
  c.depth = 1;
  Skeleton sk = test::makeSyntheticCity(c);
  NodeInfo top;
  top.block = kCellBlock;
  for (std::uint32_t r : sk.roots) top.bounds.extend(sk.nodes[r].bounds);
  top.bounds.min.z -= 200.0;  // the underlay
  top.centre = top.bounds.centre();
  for (std::uint32_t r : sk.roots) sk.nodes[r].parent = std::uint32_t(sk.nodes.size());
  sk.nodes.push_back(top);
  sk.roots = {std::uint32_t(sk.nodes.size() - 1)};
  ASSERT_TRUE(sk.hasCells());
  auto walk = makeWalkFlyPath(sk);
  ASSERT_TRUE(walk.ok()) << walk.message();
  for (double t = 0.0; t <= 15.0; t += 0.25)
    EXPECT_NEAR(walk->sample(t).camera.position.z, 1.7, 1e-9) << "t=" << t;
  auto drive = makeDrivePath(sk);
  ASSERT_TRUE(drive.ok()) << drive.message();
  for (const CameraSample& s : drive->sampleAt(10.0))
    EXPECT_NEAR(s.camera.position.z, 1.5, 1e-6) << "t=" << s.time;
}

// A city 30 km from the origin of its east-north-up frame (its blocks anchored there, moved into
// the city's frame through the curved earth): its ground drops by d^2 / 2R from the origin, 71 m
// there and 4.5 m more across this 670 m city, and each block's box tilts with it. The store's
// box bottom, its far corner, lies 2.3 m below the street the walk takes through the middle; the
// blocks beside the walk tell its ground, low by at most the tilt across one block.
TEST(CameraPathGenerators, TheWalkFollowsTheGroundOfACityFarFromItsOrigin) {
  constexpr double kEarth = 6371000.0;
  const glm::dvec2 origin(-21213.0, -21213.0);  // 30 km to the south-west
  const auto groundAt = [&](double x, double y) {
    const glm::dvec2 d = glm::dvec2(x, y) - origin;
    return -glm::dot(d, d) / (2.0 * kEarth);
  };
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 6;
  c.blockSize = 100.0;
  c.depth = 0;
  Skeleton sk = test::makeSyntheticCity(c);
  Aabb city;
  for (std::uint32_t r : sk.roots) {
    Aabb& b = sk.nodes[r].bounds;
    double lo = 1e300, hi = -1e300;
    for (double x : {b.min.x, b.max.x})
      for (double y : {b.min.y, b.max.y}) {
        lo = std::min(lo, groundAt(x, y));
        hi = std::max(hi, groundAt(x, y));
      }
    b.min.z = lo;
    b.max.z = hi + c.height;
    city.extend(b);
  }
  auto walk = makeWalkFlyPath(sk);
  ASSERT_TRUE(walk.ok()) << walk.message();
  for (double t = 0.0; t <= 15.0; t += 0.25) {
    const glm::dvec3 p = walk->sample(t).camera.position;
    const double overGround = p.z - groundAt(p.x, p.y);
    // Tilt across a block: 100 m x 30 km / R on each axis, 0.67 m in all.
    EXPECT_GT(overGround, 1.7 - 0.7) << "t=" << t;
    EXPECT_LT(overGround, 1.7 + 0.05) << "t=" << t;
  }
  // What the store's box bottom would have given at the middle of the walk: under the street.
  const glm::dvec3 mid = walk->sample(10.0).camera.position;
  EXPECT_LT(city.min.z + 1.7 - groundAt(mid.x, mid.y), 0.0);
  auto drive = makeDrivePath(sk);
  ASSERT_TRUE(drive.ok()) << drive.message();
  for (const CameraSample& s : drive->sampleAt(10.0)) {
    const double overGround =
        s.camera.position.z - groundAt(s.camera.position.x, s.camera.position.y);
    EXPECT_GT(overGround, 1.5 - 0.7) << "t=" << s.time;
    EXPECT_LT(overGround, 1.5 + 0.05) << "t=" << s.time;
  }
}

TEST(CameraPathGenerators, DriveFollowsStreetsAtCarSpeed) {
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 6;
  const Skeleton sk = test::makeSyntheticCity(c);
  auto path = makeDrivePath(sk);
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_GE(path->duration(), 20.0);
  EXPECT_LE(path->duration(), 40.0);
  double sumSpeed = 0.0;
  int n = 0;
  for (const CameraSample& s : path->sampleAt(10.0)) {
    EXPECT_NEAR(s.camera.position.z, 1.5, 1e-6);
    EXPECT_GT(clearance(sk, s.camera.position), 1.0) << "drive enters a block at t=" << s.time;
    sumSpeed += glm::length(s.velocity);
    ++n;
  }
  EXPECT_GT(sumSpeed / n, 14.0);
  EXPECT_LT(sumSpeed / n, 21.0);
}

TEST(CameraPathGenerators, OrbitKeepsTheWholeModelInView) {
  const Skeleton sk = test::makeSyntheticCity({});
  auto path = makeCameraPath("orbit", sk);
  ASSERT_TRUE(path.ok());
  for (const CameraSample& s : path->sampleAt(2.0)) {
    const Frustum f = s.camera.frustum();
    for (std::uint32_t r : sk.roots) EXPECT_TRUE(f.intersects(sk.nodes[r].bounds));
  }
  EXPECT_FALSE(makeCameraPath("spiral", sk).ok());
  EXPECT_FALSE(makeOrbitPath(Skeleton{}).ok());
}

// A scene file's camera as the start of a path job's orbit.
TEST(CameraPathGenerators, OrbitFromACameraStartsThereAndCirclesItsTarget) {
  Camera start;
  start.position = {-180, -260, 160};
  start.target = {420, 420, 0};
  start.fovY = 50;
  auto path = makeOrbitPathFrom(start, UpAxis::Z, 20.0);
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_DOUBLE_EQ(path->duration(), 20.0);
  const CameraSample first = path->sample(0.0);
  EXPECT_LT(glm::length(first.camera.position - start.position), 1e-9);
  const double rho = glm::length(glm::dvec2(start.position - start.target));
  double turned = 0.0;
  glm::dvec2 previous(start.position - start.target);
  for (const CameraSample& s : path->sampleAt(10.0)) {
    const glm::dvec3 offset = s.camera.position - start.target;
    EXPECT_NEAR(glm::length(glm::dvec2(offset)), rho, 1e-4 * rho);  // on the circle
    EXPECT_NEAR(offset.z, 160.0, 1e-9);                             // at the camera's height
    EXPECT_LT(glm::length(s.camera.target - start.target), 1e-9);
    EXPECT_DOUBLE_EQ(s.camera.fovY, 50.0);
    const glm::dvec2 now(offset);
    turned += std::atan2(previous.x * now.y - previous.y * now.x, glm::dot(previous, now));
    previous = now;
  }
  EXPECT_NEAR(std::abs(turned), 2.0 * std::numbers::pi, 1e-6);  // once round, back at the start
  // Straight down the up axis there is no circle to follow: an error, not NaN.
  start.position = {420, 420, 500};
  auto above = makeOrbitPathFrom(start, UpAxis::Z);
  ASSERT_FALSE(above.ok());
  EXPECT_NE(above.message().find("up axis"), std::string::npos);
}

}  // namespace
}  // namespace hlod
