// The camera prediction of sessions without a path (Manocha sec. 5.3; MotionPredictor.h):
// extrapolation of position and view direction, widening, and when it predicts nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "hlod/runtime/MotionPredictor.h"

using namespace hlod;

namespace {

CameraSample at(double time, glm::dvec3 position, glm::dvec3 target, double fovY = 50.0) {
  CameraSample s;
  s.time = time;
  s.camera.position = position;
  s.camera.target = target;
  s.camera.up = {0.0, 0.0, 1.0};
  s.camera.fovY = fovY;
  return s;
}

}  // namespace

TEST(MotionPredictor, AStraightWalkIsPredictedWhereItWillBeHalfASecondOnWithAWiderView) {
  MotionPredictor p;                      // c_ahead 0.5 s, c_widen 0.25
  EXPECT_FALSE(p.predict().has_value());  // nothing seen yet
  p.observe(at(0.0, {0, 0, 1.7}, {100, 0, 1.7}));
  EXPECT_FALSE(p.predict().has_value());               // one frame is no motion
  p.observe(at(0.1, {0.2, 0, 1.7}, {100.2, 0, 1.7}));  // 2 m/s along x
  p.observe(at(0.2, {0.4, 0, 1.7}, {100.4, 0, 1.7}));
  const auto q = p.predict();
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->time, 0.7, 1e-12);
  EXPECT_NEAR(q->camera.position.x, 0.4 + 2.0 * 0.5, 1e-9);
  EXPECT_NEAR(q->camera.position.y, 0.0, 1e-9);
  EXPECT_NEAR(q->velocity.x, 2.0, 1e-9);
  // Looking the same way, at the same distance; the view a quarter wider.
  EXPECT_NEAR(glm::length(q->camera.forward() - glm::dvec3(1, 0, 0)), 0.0, 1e-9);
  EXPECT_NEAR(q->camera.fovY, 62.5, 1e-9);
}

TEST(MotionPredictor, ATurningCameraIsPredictedTurnedFurther) {
  MotionPredictor p;
  // Turning left (towards +y) at about 0.5 rad/s on the spot.
  for (int i = 0; i <= 3; ++i) {
    const double a = 0.05 * i;
    p.observe(at(0.1 * i, {0, 0, 0}, {std::cos(a) * 10, std::sin(a) * 10, 0}));
  }
  const auto q = p.predict();
  ASSERT_TRUE(q.has_value());
  const double heading = std::atan2(q->camera.forward().y, q->camera.forward().x);
  EXPECT_GT(heading, 0.15 + 0.1);  // beyond the last frame's, by about 0.25 rad
  EXPECT_LT(heading, 0.15 + 0.4);
  EXPECT_NEAR(glm::length(q->camera.position), 0.0, 1e-12);  // the turn moves nothing
}

TEST(MotionPredictor, ARestingCameraOrAGapBetweenFramesPredictsNothing) {
  MotionPredictor still;
  still.observe(at(0.0, {1, 2, 3}, {4, 5, 6}));
  still.observe(at(0.1, {1, 2, 3}, {4, 5, 6}));
  EXPECT_FALSE(still.predict().has_value());  // nothing new to fetch

  MotionPredictor gap;
  gap.observe(at(0.0, {0, 0, 0}, {10, 0, 0}));
  gap.observe(at(0.1, {1, 0, 0}, {11, 0, 0}));
  ASSERT_TRUE(gap.predict().has_value());
  gap.observe(at(5.0, {50, 0, 0}, {60, 0, 0}));  // a jump: a new motion starts
  EXPECT_FALSE(gap.predict().has_value());
  gap.observe(at(4.0, {51, 0, 0}, {61, 0, 0}));  // time going back starts anew too
  EXPECT_FALSE(gap.predict().has_value());
}
