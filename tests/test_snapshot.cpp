// Snapshots (loosehair/snapshot.hpp): a run saved and resumed gives the
// same bits as the uninterrupted run, on every bundled scene (wind
// included), and a truncated, damaged, foreign, other-version or
// other-scene snapshot is refused with a clear error and leaves the solver
// as it was.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

using namespace loosehair;

namespace {

SceneDesc tiny(const char* file = "tiny.json") {
  return loadScene(lhtest::sourceDir() + "/tests/data/" + file);
}

// Runs `first` steps, snapshots, resumes the snapshot on a fresh solver
// built from the same scene, and compares with the uninterrupted run after
// `first + second` steps.
void expectResumeIsIdentical(const SceneDesc& scene, int first, int second) {
  Solver whole = buildSolver(scene);
  whole.advance(first);
  const std::string bytes = encodeSnapshot(whole);
  whole.advance(second);

  Solver resumed = buildSolver(scene);
  decodeSnapshot(resumed, bytes, "snapshot");
  EXPECT_EQ(resumed.stepCount(), static_cast<std::uint64_t>(first));
  resumed.advance(second);
  EXPECT_EQ(resumed.stateHash(), whole.stateHash()) << scene.name;
  EXPECT_EQ(resumed.time(), whole.time());
  EXPECT_EQ(resumed.particles().position, whole.particles().position);
}

std::string withByte(std::string s, std::size_t at, char delta) {
  s[at] = static_cast<char>(s[at] + delta);
  return s;
}

}  // namespace

TEST(Snapshot, ResumeGivesTheUninterruptedBits) {
  expectResumeIsIdentical(tiny(), 40, 60);
  expectResumeIsIdentical(tiny("tiny-wind.json"), 30, 30);  // the air on a grid
  SceneDesc particles = tiny("tiny-wind.json");
  particles.wind.model = AirModel::Particles;
  expectResumeIsIdentical(particles, 30, 30);
}

TEST(Snapshot, AirOfTheOtherModelIsRefused) {
  SceneDesc particles = tiny("tiny-wind.json");
  particles.wind.model = AirModel::Particles;
  Solver grid_run = buildSolver(tiny("tiny-wind.json"));
  Solver particle_run = buildSolver(particles);
  const std::string grid_bytes = encodeSnapshot(grid_run);
  try {
    decodeSnapshot(particle_run, grid_bytes, "grid.state");
    FAIL() << "a grid air snapshot resumed on particle air";
  } catch (const SnapshotError& e) {
    EXPECT_NE(std::string(e.what()).find("grid.state"), std::string::npos) << e.what();
  }
}

TEST(Snapshot, ResumeAfterAResetAndAChangedTimeStep) {
  const SceneDesc scene = tiny();
  Solver whole = buildSolver(scene);
  whole.advance(10);
  // a reset (as the viewer's restart does) and a new time step: the step
  // after a reset absorbs its corrections, and the snapshot keeps both
  const Particles p = whole.particles();
  whole.setKinematicState(p.position, p.velocity, p.direction);
  whole.setTimeStep(scene.sim.time_step * 0.5);
  const std::string bytes = encodeSnapshot(whole);
  whole.advance(20);
  Solver resumed = buildSolver(scene);
  decodeSnapshot(resumed, bytes, "snapshot");
  EXPECT_EQ(resumed.params().time_step, scene.sim.time_step * 0.5);
  resumed.advance(20);
  EXPECT_EQ(resumed.stateHash(), whole.stateHash());
}

TEST(Snapshot, TheThreadCountDoesNotMatter) {
  SceneDesc one = tiny(), two = tiny();
  one.sim.threads = 1;
  two.sim.threads = 2;
  Solver a = buildSolver(one);
  a.advance(25);
  Solver b = buildSolver(two);
  decodeSnapshot(b, encodeSnapshot(a), "snapshot");
  a.advance(25);
  b.advance(25);
  EXPECT_EQ(a.stateHash(), b.stateHash());
}

TEST(Snapshot, BadSnapshotsAreRefusedAndChangeNothing) {
  const SceneDesc scene = tiny();
  Solver source = buildSolver(scene);
  source.advance(5);
  const std::string good = encodeSnapshot(source);
  Solver target = buildSolver(scene);
  const std::uint64_t before = target.stateHash();

  auto refused = [&](const std::string& bytes, const char* says) {
    try {
      decodeSnapshot(target, bytes, "x.state");
      ADD_FAILURE() << "accepted a snapshot that " << says;
    } catch (const SnapshotError& e) {
      EXPECT_NE(std::strstr(e.what(), "x.state"), nullptr) << e.what();
      EXPECT_NE(std::strstr(e.what(), says), nullptr) << e.what();
    }
    EXPECT_EQ(target.stateHash(), before);
    EXPECT_EQ(target.stepCount(), 0u);
  };
  refused("", "not a loosehair snapshot");
  refused("ply\nformat binary_little_endian 1.0\n", "not a loosehair snapshot");
  refused(good.substr(0, 30), "truncated");
  refused(good.substr(0, good.size() - 1), "truncated");
  refused(good + "x", "truncated");
  refused(withByte(good, good.size() / 2, 1), "checksum");
  refused(withByte(good, 16, 1), "version");
  // another seed: another scene as far as the state goes
  SceneDesc other = scene;
  other.seed += 1;
  Solver elsewhere = buildSolver(other);
  refused(encodeSnapshot(elsewhere), "another scene");
  // the same particles, another physical parameter
  SceneDesc stiffer = scene;
  stiffer.sim.youngs_modulus *= 2;
  refused(encodeSnapshot(buildSolver(stiffer)), "another scene");
  // another wind whose air starts the same (a grid air is still at t = 0
  // when the gusts start from 0): the drag, the direction, the gusts
  {
    SceneDesc windy = tiny("tiny-wind.json");
    windy.wind.profile = {{0.0, 0.0f}, {1.0, 1.0f}};
    const std::string saved = encodeSnapshot(buildSolver(windy));
    for (int change = 0; change < 3; ++change) {
      SceneDesc other_wind = windy;
      if (change == 0) other_wind.wind.drag_rate *= 2.0f;
      if (change == 1) other_wind.wind.direction = {0.0f, 0.0f, 1.0f};
      if (change == 2) other_wind.wind.profile = {{0.0, 0.0f}, {2.0, 1.0f}};
      Solver elsewhere_wind = buildSolver(other_wind);
      EXPECT_THROW(decodeSnapshot(elsewhere_wind, saved, "x.state"), SnapshotError) << "wind change " << change;
    }
    Solver same_wind = buildSolver(windy);
    EXPECT_NO_THROW(decodeSnapshot(same_wind, saved, "x.state"));
  }
  // a snapshot with wind on a scene without
  refused(encodeSnapshot(buildSolver(tiny("tiny-wind.json"))), "another scene");
  // and the good one is accepted
  decodeSnapshot(target, good, "x.state");
  EXPECT_EQ(target.stateHash(), source.stateHash());
}

TEST(Snapshot, FilesAreWrittenWholeAndReadBack) {
  const auto dir = std::filesystem::temp_directory_path() / "loosehair-snapshot-test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const SceneDesc scene = tiny();
  Solver solver = buildSolver(scene);
  solver.advance(3);
  const std::string path = (dir / "run.state").string();
  saveSnapshot(solver, path);
  solver.advance(3);
  saveSnapshot(solver, path);  // replaces the first, atomically
  Solver resumed = buildSolver(scene);
  loadSnapshot(resumed, path);
  EXPECT_EQ(resumed.stateHash(), solver.stateHash());
  // nothing but the snapshot is left in the directory
  int entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++entries;
  }
  EXPECT_EQ(entries, 1);
  // a directory, a missing file and a FIFO are refused, naming the file
  EXPECT_THROW(loadSnapshot(resumed, dir.string()), SnapshotError);
  EXPECT_THROW(loadSnapshot(resumed, (dir / "missing.state").string()), SnapshotError);
  EXPECT_THROW(saveSnapshot(solver, (dir / "no-such-dir" / "x.state").string()), SnapshotError);
  std::filesystem::remove_all(dir);
}
