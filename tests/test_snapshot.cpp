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

SceneDesc tiny(const char* file = "tiny.json") { return loadScene(lhtest::sourceDir() + "/tests/data/" + file); }

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

// ---- crafted snapshots: every field checked against what the scene allows ----
namespace {

// A snapshot taken apart as snapshot.cpp lays it out (version 2), to be
// changed field by field and put together with a new checksum: what a
// hostile file with a recomputed checksum holds.
struct Crafted {
  std::string header;  // magic, version, fingerprint (the length is recomputed)
  double time = 0, dt = 0;
  std::uint64_t steps = 0;
  std::string hair;  // positions .. the spring solve's last change, as bytes
  std::uint8_t air_kind = 0;
  std::vector<std::vector<float>> grid;  // u, v, w, pressure
  double pending = 0;
  std::vector<glm::vec3> air_x, air_v;
  std::vector<float> air_density;
  double advance = 0;
  std::uint64_t layers = 0, emitted = 0, removed = 0;
};

template <class T>
T take(const std::string& b, std::size_t& at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  at += sizeof v;
  return v;
}
template <class T>
std::vector<T> takeArray(const std::string& b, std::size_t& at) {
  const auto n = take<std::uint64_t>(b, at);
  std::vector<T> v(n);
  if (n) std::memcpy(v.data(), b.data() + at, n * sizeof(T));
  at += n * sizeof(T);
  return v;
}
template <class T>
void put(std::string& b, const T& v) {
  b.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
void putArray(std::string& b, const std::vector<T>& v) {
  put<std::uint64_t>(b, v.size());
  b.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
std::uint64_t fnv(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

Crafted takeApart(const std::string& bytes, std::size_t n) {
  Crafted c;
  c.header = bytes.substr(0, 32);
  std::size_t at = 40;
  c.time = take<double>(bytes, at);
  c.steps = take<std::uint64_t>(bytes, at);
  c.dt = take<double>(bytes, at);
  const std::size_t hair_begin = at;
  for (int k = 0; k < 3; ++k) (void)takeArray<glm::vec3>(bytes, at);
  (void)take<std::uint8_t>(bytes, at);
  if (take<std::uint8_t>(bytes, at)) {
    (void)takeArray<float>(bytes, at);
    (void)takeArray<float>(bytes, at);
    (void)take<std::uint64_t>(bytes, at);
  }
  (void)takeArray<glm::vec3>(bytes, at);
  c.hair = bytes.substr(hair_begin, at - hair_begin);
  (void)n;
  c.air_kind = take<std::uint8_t>(bytes, at);
  if (c.air_kind == 2) {
    for (int k = 0; k < 4; ++k) c.grid.push_back(takeArray<float>(bytes, at));
    c.pending = take<double>(bytes, at);
  } else if (c.air_kind == 1) {
    c.air_x = takeArray<glm::vec3>(bytes, at);
    c.air_v = takeArray<glm::vec3>(bytes, at);
    c.air_density = takeArray<float>(bytes, at);
    c.advance = take<double>(bytes, at);
    c.layers = take<std::uint64_t>(bytes, at);
    c.emitted = take<std::uint64_t>(bytes, at);
    c.removed = take<std::uint64_t>(bytes, at);
  }
  return c;
}

std::string putTogether(const Crafted& c) {
  std::string payload;
  put(payload, c.time);
  put(payload, c.steps);
  put(payload, c.dt);
  payload += c.hair;
  put(payload, c.air_kind);
  if (c.air_kind == 2) {
    for (const auto& a : c.grid) putArray(payload, a);
    put(payload, c.pending);
  } else if (c.air_kind == 1) {
    putArray(payload, c.air_x);
    putArray(payload, c.air_v);
    putArray(payload, c.air_density);
    put(payload, c.advance);
    put(payload, c.layers);
    put(payload, c.emitted);
    put(payload, c.removed);
  }
  std::string out = c.header;
  put<std::uint64_t>(out, payload.size());
  out += payload;
  put(out, fnv(out));
  return out;
}

// The hair's positions in the crafted bytes (the first array of `hair`).
glm::vec3* positions(Crafted& c) { return reinterpret_cast<glm::vec3*>(c.hair.data() + 8); }

void expectRefused(Solver& target, const std::string& bytes, const char* says) {
  const std::uint64_t before = target.stateHash();
  try {
    decodeSnapshot(target, bytes, "crafted.state");
    ADD_FAILURE() << "accepted a crafted snapshot: " << says;
  } catch (const SnapshotError& e) {
    EXPECT_NE(std::strstr(e.what(), "crafted.state"), nullptr) << e.what();
    EXPECT_NE(std::strstr(e.what(), says), nullptr) << e.what();
  }
  EXPECT_EQ(target.stateHash(), before);
}

}  // namespace

TEST(Snapshot, CraftedHairFieldsAreCheckedAgainstTheScene) {
  const SceneDesc scene = tiny();
  Solver source = buildSolver(scene);
  source.advance(3);
  const std::string good = encodeSnapshot(source);
  const std::size_t n = source.particles().size();
  ASSERT_EQ(putTogether(takeApart(good, n)), good) << "the test's reading of the layout is off";
  Solver target = buildSolver(scene);
  {
    Crafted c = takeApart(good, n);
    c.steps = std::uint64_t{1} << 63;
    expectRefused(target, putTogether(c), "step count");
    c.steps = 6442450944ULL * 1000;
    expectRefused(target, putTogether(c), "step count");
  }
  {
    Crafted c = takeApart(good, n);
    c.time = -1e9;
    expectRefused(target, putTogether(c), "the time is -1e+09");
  }
  {
    Crafted c = takeApart(good, n);
    for (std::size_t i = 0; i < n; ++i) positions(c)[i] += glm::vec3(1e6f, 0.0f, 0.0f);
    expectRefused(target, putTogether(c), "a hair particle lies");
  }
  {
    Crafted c = takeApart(good, n);
    glm::vec3* velocity = reinterpret_cast<glm::vec3*>(c.hair.data() + 8 + n * 12 + 8);
    velocity[n / 2] = glm::vec3(3e38f, 0.0f, 0.0f);
    expectRefused(target, putTogether(c), "speed of 3e+38");
  }
  decodeSnapshot(target, good, "crafted.state");
  EXPECT_EQ(target.stateHash(), source.stateHash());
}

TEST(Snapshot, CraftedAirIsCheckedAgainstTheScene) {
  // the grid air: velocities far beyond any wind
  SceneDesc windy = tiny("tiny-wind.json");
  Solver grid_source = buildSolver(windy);
  grid_source.advance(4);
  const std::string grid_good = encodeSnapshot(grid_source);
  const std::size_t n = grid_source.particles().size();
  ASSERT_EQ(putTogether(takeApart(grid_good, n)), grid_good);
  Solver grid_target = buildSolver(windy);
  {
    Crafted c = takeApart(grid_good, n);
    ASSERT_EQ(c.air_kind, 2);
    for (float& u : c.grid[0]) u = 3e38f;
    expectRefused(grid_target, putTogether(c), "speed of 3e+38");
  }
  // the particle air: a run of 1e300, and 200,000 air particles at a point
  SceneDesc particles = windy;
  particles.wind.model = AirModel::Particles;
  Solver air_source = buildSolver(particles);
  air_source.advance(4);
  const std::string air_good = encodeSnapshot(air_source);
  Solver air_target = buildSolver(particles);
  {
    Crafted c = takeApart(air_good, n);
    ASSERT_EQ(c.air_kind, 1);
    c.advance = 1e300;
    expectRefused(air_target, putTogether(c), "the wind run is 1e+300");
  }
  {
    Crafted c = takeApart(air_good, n);
    c.air_x.assign(200000, glm::vec3(0.01f, 0.02f, 0.03f));
    c.air_v.assign(200000, glm::vec3(0.0f));
    c.air_density.clear();
    expectRefused(air_target, putTogether(c), "air particles");
  }
  {
    Crafted c = takeApart(air_good, n);
    c.air_x.assign(2000, glm::vec3(0.01f, 0.02f, 0.03f));
    c.air_v.assign(2000, glm::vec3(0.0f));
    c.air_density.clear();
    expectRefused(air_target, putTogether(c), "crowd into one cell");
  }
  decodeSnapshot(air_target, air_good, "crafted.state");
  EXPECT_EQ(air_target.stateHash(), air_source.stateHash());
}
