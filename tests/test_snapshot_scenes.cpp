// Snapshots on every bundled scene (data/scenes): saved after some frames
// and resumed on a solver built afresh from the scene file, a run goes on
// bit-identically (the state hash after N + M steps equals the
// uninterrupted run's). Wind, a moving head and the torso included.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace loosehair;

TEST(SnapshotScenes, EveryBundledSceneResumesBitIdentically) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(lhtest::sourceDir() + "/data/scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const SceneDesc scene = loadScene(entry.path().string());
    BuildReport report;
    Solver whole = buildSolver(scene, &report);
    // into the motion: past the first frames, where the head starts moving
    const int first = 3 * report.substeps, second = 2 * report.substeps;
    whole.advance(first);
    const std::string bytes = encodeSnapshot(whole);
    whole.advance(second);
    Solver resumed = buildSolver(scene);
    decodeSnapshot(resumed, bytes, entry.path().string());
    resumed.advance(second);
    EXPECT_EQ(resumed.stateHash(), whole.stateHash());
    ++scenes;
  }
  EXPECT_GE(scenes, 6);
}
