// Heads the bundled scenes do not cover (SPEC §5, §6.1): the bundled head
// turned on its side or upside down, or in other units, is named in a
// warning that says which setting to change; the bundled scenes themselves
// build clean (no warning, every particle reaches a root).
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace loosehair;

namespace {

struct Built {
  std::vector<std::string> warnings;
  std::string error;
};

// The bundled head written through `turn` (file coordinates from ours) to
// an OBJ, loaded by a scene with the given head options.
Built buildTurnedHead(glm::vec3 (*turn)(glm::vec3), const std::string& head_options) {
  const std::string dir = ::testing::TempDir() + "loosehair-turned-head";
  std::filesystem::create_directories(dir);
  TriangleMesh h = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  for (auto& p : h.vertices) p = turn(p);
  writeObj(h, dir + "/head.obj");
  const std::string text = R"({"name": "turned", "substeps": 4,
    "head": {"type": "mesh", "mesh": "head.obj")" + head_options + R"(},
    "hair": {"particles": 600, "length": 0.2}})";
  std::ofstream(dir + "/scene.json") << text;
  Built b;
  try {
    BuildReport report;
    (void)buildSolver(loadScene(dir + "/scene.json"), &report);
    b.warnings = report.warnings;
  } catch (const std::exception& e) {
    b.error = e.what();
  }
  std::filesystem::remove_all(dir);
  return b;
}

bool mentions(const Built& b, const std::string& what) {
  if (b.error.find(what) != std::string::npos) return true;
  for (const auto& w : b.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(HeadMeshes, BundledScenesBuildClean) {
  for (const char* name : {"hang", "head-shake", "head-nod", "back-hair-split", "wind", "sphere-hang"}) {
    BuildReport report;
    Solver solver = buildSolver(loadScene(lhtest::sourceDir() + "/data/scenes/" + name + ".json"), &report);
    EXPECT_TRUE(report.warnings.empty()) << name << ": " << (report.warnings.empty() ? "" : report.warnings[0]);
    EXPECT_EQ(solver.initReport().unanchored, 0u) << name << ": no particle hangs on its tether alone";
  }
}

TEST(HeadMeshes, AHeadLyingOnItsSideIsNamed) {
  // A Z-up file read as Y-up: the warning (or the error it explains) names head.up.
  const Built b = buildTurnedHead([](glm::vec3 p) { return glm::vec3(p.x, -p.z, p.y); }, "");
  EXPECT_TRUE(mentions(b, "head.up")) << b.error;
  EXPECT_TRUE(mentions(b, "on its side")) << b.error;
  // told its axes, the same file is clean
  const Built ok = buildTurnedHead([](glm::vec3 p) { return glm::vec3(p.x, -p.z, p.y); },
                                   R"(, "up": "+z", "front": "-y")");
  EXPECT_TRUE(ok.error.empty()) << ok.error;
  EXPECT_TRUE(ok.warnings.empty()) << ok.warnings[0];
}

TEST(HeadMeshes, AnUpsideDownHeadIsNamed) {
  const Built b = buildTurnedHead([](glm::vec3 p) { return glm::vec3(p.x, -p.y, -p.z); }, "");
  EXPECT_TRUE(mentions(b, "upside down")) << b.error;
  EXPECT_TRUE(mentions(b, "head.up")) << b.error;
  const Built ok = buildTurnedHead([](glm::vec3 p) { return glm::vec3(p.x, -p.y, -p.z); },
                                   R"(, "up": "-y", "front": "-z")");
  EXPECT_TRUE(ok.error.empty()) << ok.error;
  EXPECT_TRUE(ok.warnings.empty()) << ok.warnings[0];
}

TEST(HeadMeshes, AHeadInCentimetresWithoutScaleIsNamed) {
  const Built b = buildTurnedHead([](glm::vec3 p) { return 100.0f * p; }, "");
  EXPECT_TRUE(mentions(b, "head.scale")) << b.error;
  EXPECT_TRUE(mentions(b, "0.01 for centimetres")) << b.error;
}
