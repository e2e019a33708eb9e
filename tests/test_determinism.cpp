// method.md §5 Determinism: the same scene and seed give the same bits on any
// thread count and in every run, and a committed golden sequence of state
// hashes guards the physics against unintended change.
//
// Renewing the golden file on purpose (after a deliberate physics change):
//   LOOSEHAIR_UPDATE_GOLDEN=1 build/release/tests/loosehair_sim_tests --gtest_filter='Golden.*'
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace loosehair;

namespace {

SceneDesc tinyScene(int threads) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/tests/data/tiny.json");
  scene.sim.threads = threads;
  return scene;
}

std::string hex(std::uint64_t h) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
  return buf;
}

}  // namespace

TEST(Determinism, SameHashForOneAndTwoThreadsAndAcrossRuns) {
  Solver one = buildSolver(tinyScene(1));
  Solver two = buildSolver(tinyScene(2));
  Solver again = buildSolver(tinyScene(2));
  // more threads than cores: blocks go to threads in a different order every run
  Solver three = buildSolver(tinyScene(3));
  ASSERT_EQ(one.stateHash(), two.stateHash());
  for (int k = 0; k < 300; ++k) {
    one.step();
    two.step();
    again.step();
    three.step();
  }
  EXPECT_EQ(one.stateHash(), two.stateHash());
  EXPECT_EQ(one.stateHash(), three.stateHash());
  EXPECT_EQ(two.stateHash(), again.stateHash());
  EXPECT_EQ(one.particles().position, two.particles().position);
}

TEST(Determinism, TheHashSeesTheState) {
  SceneDesc a = tinyScene(2), b = tinyScene(2);
  b.seed = a.seed + 1;
  EXPECT_NE(buildSolver(a).stateHash(), buildSolver(b).stateHash());
  Solver s = buildSolver(a);
  const auto before = s.stateHash();
  s.step();
  EXPECT_NE(before, s.stateHash());
}

TEST(Golden, FirstHundredStepsOfTheTinyScene) {
  const std::string path = std::string(LOOSEHAIR_GOLDEN_DIR) + "/tiny_steps.txt";
  Solver solver = buildSolver(tinyScene(2));
  std::vector<std::string> got;
  got.push_back(hex(solver.stateHash()));
  for (int k = 0; k < 100; ++k) {
    solver.step();
    got.push_back(hex(solver.stateHash()));
  }
  const char* update = std::getenv("LOOSEHAIR_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") {
    std::ofstream out(path);
    out << "# state hashes of tests/data/tiny.json: initial state, then after each of 100 steps\n";
    for (const auto& h : got) out << h << "\n";
    GTEST_SKIP() << "golden file renewed: " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << "missing " << path << " (create it with LOOSEHAIR_UPDATE_GOLDEN=1, see this file's header)";
  std::vector<std::string> want;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') want.push_back(line);
  ASSERT_EQ(want.size(), got.size());
  for (std::size_t k = 0; k < got.size(); ++k)
    ASSERT_EQ(got[k], want[k]) << "state differs from the golden run after step " << k;
}
