// method.md §5: head trajectories and the kinematics behind the inertial forces.
#include "loosehair/head_motion.hpp"
#include "loosehair/loosehair.hpp"

#include <glm/trigonometric.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace loosehair;

TEST(HeadMotion, ShakeAngularVelocityMatchesTheYawRate) {
  const auto h = HeadTrajectory::shake(0.5, 1.0, 3.0, 0.2);
  for (double t : {0.5, 1.1, 1.7, 2.3}) {
    const auto k = h.kinematics(t);
    // yaw(t) numerically: angle of the rotated +Z axis about +Y
    auto yaw = [&](double tt) {
      const glm::dvec3 z = h.pose(tt).rotation * glm::dvec3(0, 0, 1);
      return std::atan2(z.x, z.z);
    };
    const double d = 1e-5;
    const double rate = (yaw(t + d) - yaw(t - d)) / (2 * d);
    const double accel = (yaw(t + d) - 2 * yaw(t) + yaw(t - d)) / (d * d);
    EXPECT_NEAR(k.angular_velocity.y, rate, 1e-5 * (1 + std::abs(rate)));
    EXPECT_NEAR(k.angular_velocity.x, 0.0, 1e-9);
    EXPECT_NEAR(k.angular_acceleration.y, accel, 1e-3 * (1 + std::abs(accel)));
  }
  // at rest before the start and after the end
  EXPECT_EQ(h.kinematics(0.1).angular_velocity, glm::dvec3(0.0));
  EXPECT_NEAR(glm::length(h.kinematics(3.3).angular_velocity), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(h.endTime(), 3.2);
}

TEST(HeadMotion, NodTurnsAboutTheSideAxis) {
  const auto h = HeadTrajectory::nod(0.4, 1.0, 2.0);
  const auto k = h.kinematics(0.6);
  EXPECT_NEAR(k.angular_velocity.y, 0.0, 1e-9);
  EXPECT_GT(std::abs(k.angular_velocity.x), 0.1);
}

TEST(HeadMotion, KeyframesPassThroughTheirKeysAndHoldAtTheEnds) {
  std::vector<HeadKeyframe> keys(3);
  keys[0] = {0.0, {0, 0, 0}, {0, 0, 0}};
  keys[1] = {1.0, {30, 0, 0}, {0.1, 0, 0}};
  keys[2] = {2.0, {0, 10, 0}, {0, 0.05, 0}};
  const auto h = HeadTrajectory::keyframes(keys);
  const auto p1 = h.pose(1.0);
  EXPECT_NEAR(p1.center.x, 0.1, 1e-12);
  const glm::dmat3 r1 = rotationFromEuler(glm::radians(glm::dvec3(30, 0, 0)));
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(p1.rotation[c][r], r1[c][r], 1e-12);
  EXPECT_EQ(h.pose(5.0).center, glm::dvec3(0, 0.05, 0));
  // translation velocity by finite differences of the pose
  const auto k = h.kinematics(0.5);
  EXPECT_GT(k.velocity.x, 0.0);
  EXPECT_THROW(HeadTrajectory::keyframes({keys[0]}), std::invalid_argument);
  std::vector<HeadKeyframe> bad = keys;
  bad[2].time = 0.5;
  EXPECT_THROW(HeadTrajectory::keyframes(bad), std::invalid_argument);
}

TEST(HeadMotion, AHeadFarFromItsPivotIsWarnedOf) {
  // the head turns about its frame's origin: a head placed a metre away
  // swings on a long arm (a mesh whose origin is at the feet, say)
  auto warnings = [](const std::string& center, const std::string& motion) {
    const std::string json = R"({"head": {"type": "sphere", "radius": 0.1, "center": )" + center +
                             R"(}, "hair": {"particles": 300}, "motion": )" + motion + "}";
    loosehair::BuildReport report;
    (void)loosehair::buildSolver(loosehair::parseScene(json, "pivot.json"), &report);
    std::string all;
    for (const std::string& w : report.warnings) all += w + "\n";
    return all;
  };
  const std::string shake = R"({"type": "shake", "amplitude_deg": 30, "frequency_hz": 1, "cycles": 1})";
  const std::string far = warnings("[0, 1, 0]", shake);
  EXPECT_NE(far.find("motion: the head turns about its frame's origin, 0.90 m"), std::string::npos) << far;
  EXPECT_NE(far.find("head.center"), std::string::npos) << far;
  // near the pivot, or far but still: nothing to say
  EXPECT_EQ(warnings("[0, 0.02, 0]", shake).find("motion:"), std::string::npos);
  EXPECT_EQ(warnings("[0, 1, 0]", R"({"type": "still"})").find("motion:"), std::string::npos);
}
