// A head moved by hand (LiveHead, the viewer's drag): the simulation driven
// live gives the same bits as the recorded keyframes replayed from a scene
// file, and the hair lags the dragged head.
#include "loosehair/file_io.hpp"
#include "loosehair/live_head.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace loosehair;

namespace {

// A drag: the head turned 35 degrees about the neck over half a second,
// held, and brought back.
HeadKeyframe dragAt(std::int64_t frame) {
  const double t = static_cast<double>(frame) / 30.0;
  const double yaw = t < 0.2   ? 0.0
                     : t < 0.7 ? 70.0 * (t - 0.2)
                     : t < 1.0 ? 35.0
                     : t < 1.5 ? 35.0 - 70.0 * (t - 1.0)
                               : 0.0;
  return turnAbout(glm::dvec3(0, -0.12, 0), glm::dvec3(yaw, 0, 0), glm::dvec3(0.0));
}

}  // namespace

TEST(LiveHead, ADragReplayedFromItsKeyframesGivesTheSameBits) {
  const SceneDesc scene = lhtest::sphereScene(800, "{}", R"({"type": "still"})", 6);
  Solver live = buildSolver(scene);
  LiveHead head(scene.frame_rate);
  const int frames = 54;  // 1.8 s
  double max_yaw = 0, max_lag = 0;
  std::vector<glm::vec3> start;
  live.worldPositions(start);
  for (int f = 0; f < frames; ++f) {
    head.beginFrame(f, dragAt(f));
    live.setTrajectory(head.trajectory());
    live.advance(scene.substeps);
    const double yaw = lhtest::headYaw(live);
    max_yaw = std::max(max_yaw, std::abs(yaw));
    // the hair's own turn: less than the head's while it turns (it lags)
    max_lag = std::max(max_lag, std::abs(yaw - lhtest::hairYaw(live, start, 0.1f)));
  }
  EXPECT_GT(max_yaw, glm::radians(30.0)) << "the head turned";
  EXPECT_GT(max_lag, glm::radians(3.0)) << "the hair lagged behind the turning head";
  // the recorded keys, written as a head motion file (as the viewer saves
  // a drag) and read back for a replay (simulate --motion)
  const std::string path = ::testing::TempDir() + "live-head-motion.json";
  writeFileAtomically(path, {keyframesJson(head.keys())});
  SceneDesc replay_scene = lhtest::sphereScene(800, "{}", R"({"type": "still"})", 6);
  replay_scene.motion = loadMotion(path);
  Solver replay = buildSolver(replay_scene);
  replay.advance(frames * scene.substeps);
  EXPECT_EQ(replay.stateHash(), live.stateHash());
  std::printf("drag: head turned %.1f deg, hair up to %.1f deg behind or ahead; state-hash %016llx live and replayed\n",
              glm::degrees(max_yaw), glm::degrees(max_lag), static_cast<unsigned long long>(live.stateHash()));
}

TEST(LiveHead, ABadMotionFileNamesTheFileAndTheField) {
  const std::string dir = ::testing::TempDir();
  auto refused = [&](const std::string& name, const std::string& text, const std::string& says) {
    writeFileAtomically(dir + name, {text});
    try {
      (void)loadMotion(dir + name);
      ADD_FAILURE() << name << " was read";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused("motion-none.json", R"({"keys": []})", "motion");
  refused("motion-one-key.json", R"({"motion": {"type": "keyframes", "keys": [{"time": 0}]}})", "keys");
  refused("motion-nan.json", R"({"motion": {"type": "shake", "amplitude_deg": "x"}})", "amplitude_deg");
  refused("motion-cut.json", R"({"motion": {"type": )", "JSON");
  EXPECT_THROW(loadMotion(dir + "motion-missing.json"), SceneError);
}

TEST(LiveHead, FramesMustComeInOrder) {
  LiveHead head(30.0);
  head.beginFrame(0, {});
  EXPECT_THROW(head.beginFrame(2, {}), std::logic_error);
  EXPECT_THROW(LiveHead(0.0), std::invalid_argument);
  EXPECT_THROW(LiveHead(std::nan("")), std::invalid_argument);
  EXPECT_DOUBLE_EQ(head.keys().back().time, 3.0 / 30.0);
}

TEST(LiveHead, TurningAboutThePivotKeepsThePivotInPlace) {
  const glm::dvec3 pivot(0.01, -0.12, 0.02);
  const HeadKeyframe k = turnAbout(pivot, glm::dvec3(30, -10, 5), glm::dvec3(0.0));
  const glm::dvec3 moved = rotationFromEuler(glm::radians(k.euler_deg)) * pivot + k.translation;
  EXPECT_LT(glm::length(moved - pivot), 1e-12);
}
