// Bad scenes and parameters are rejected with the field named; PLY dumps are
// complete and readable.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace loosehair;

namespace {

const char* kGood = R"({
  "name": "ok", "seed": 2, "frames": 3, "frame_rate": 30, "substeps": 20,
  "head": {"type": "sphere", "center": [0, 0, 0], "radius": 0.1},
  "scalp": {"type": "sphere-cap", "cap_angle_deg": 100},
  "hair": {"particles": 300, "length": 0.2, "mass": 0.03},
  "solver": {"h1": "auto", "youngs_modulus": 5e4},
  "motion": {"type": "still"}
})";

std::string replaced(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

void expectRejected(const std::string& text, const std::string& fragment) {
  try {
    const SceneDesc scene = parseScene(text, "bad.json");
    (void)buildSolver(scene);
    ADD_FAILURE() << "accepted a scene that should fail with: " << fragment;
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad.json: ", 0), 0u) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "message: " << msg;
  }
}

}  // namespace

TEST(SceneFiles, TheBundledScenesLoadAndBuild) {
  for (const char* name : {"/data/scenes/sphere-hang.json", "/tests/data/tiny.json"}) {
    const SceneDesc scene = loadScene(lhtest::sourceDir() + name);
    EXPECT_NO_THROW((void)buildSolver(scene)) << name;
  }
  const SceneDesc s = parseScene(kGood, "good.json");
  EXPECT_EQ(s.hair.particles, 300);
  EXPECT_TRUE(s.h1_auto);
  EXPECT_EQ(s.substeps, 20);
}

TEST(SceneFiles, BadScenesNameTheFieldAndTheProblem) {
  expectRejected("{ \"head\": ", "invalid JSON");
  expectRejected("[1, 2]", "must be a JSON object");
  expectRejected(replaced("\"length\": 0.2", "\"lenght\": 0.2"), "hair.lenght: unknown field");
  expectRejected(replaced("\"length\": 0.2", "\"length\": -0.2"),
                 "hair.length: must be a number in [0.01, 10], got -0.2");
  expectRejected(replaced("\"particles\": 300", "\"particles\": \"many\""),
                 "hair.particles: must be an integer, got \"many\"");
  expectRejected(replaced("\"particles\": 300", "\"particles\": 3"), "hair.particles: must be an integer in [10,");
  expectRejected(replaced("\"radius\": 0.1", "\"radius\": 0"), "head.radius: must be a number in (0, 10], got 0");
  expectRejected(replaced("\"type\": \"sphere\"", "\"type\": \"cube\""), "head.type");
  expectRejected(replaced("\"youngs_modulus\": 5e4", "\"youngs_modulus\": 1e999"), "number overflow parsing '1e999'");
  expectRejected(replaced("\"youngs_modulus\": 5e4", "\"youngs_modulus\": -5"),
                 "solver.youngs_modulus: must be a number in (0");
  expectRejected(replaced("\"h1\": \"auto\"", "\"h1\": \"big\""), "solver.h1: must be a number or \"auto\"");
  expectRejected(replaced("\"h1\": \"auto\"", "\"h1\": 0.01, \"h2\": 0.02"), "h2 = 0.02");
  expectRejected(replaced("\"youngs_modulus\": 5e4", "\"gravity\": [0, -9.8]"),
                 "solver.gravity: must be an array of three numbers");
  expectRejected(replaced("\"youngs_modulus\": 5e4", "\"collision_rate\": 1e5"), "collision_rate = 100000");
  expectRejected(replaced("\"substeps\": 20", "\"substeps\": \"lots\""),
                 "substeps: must be a positive integer or \"auto\"");
  expectRejected(replaced("\"substeps\": 20", "\"substeps\": 0"), "substeps: must be an integer in [1,");
  expectRejected(replaced("\"type\": \"still\"", "\"type\": \"wobble\""), "motion.type: must be");
  expectRejected(replaced("{\"type\": \"still\"}", R"({"type": "keyframes", "keys": [{"time": 1}, {"time": 0.5}]})"),
                 "motion.keys[1].time: keyframe times must increase");
  expectRejected(replaced("{\"type\": \"still\"}",
                          R"({"type": "keyframes", "keys": [{"time": 0}, {"time": 1, "euler": [1,2,3]}]})"),
                 "motion.keys[1].euler: unknown field");
}

namespace {

// A mesh-head scene around the bundled assets, from the tests' own folder.
std::string meshScene(const std::string& head_extra, const std::string& rest = "") {
  const std::string data = lhtest::sourceDir() + "/data";
  return R"({"name": "m", "substeps": 5,
    "head": {"type": "mesh", "mesh": ")" +
         data + R"(/meshes/head.ply")" + head_extra + R"(},
    "hair": {"particles": 300, "length": 0.2, "mass": 0.03, "length_map": ")" +
         data + R"(/maps/hair_length.png"})" + rest + "}";
}

}  // namespace

TEST(SceneFiles, MeshScenesLoadAndBadMeshFieldsAreNamed) {
  // The bundled scenes on the head, with paths relative to the scene file.
  for (const char* name : {"hang", "back-hair-split", "head-shake", "head-nod", "wind"}) {
    SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/" + name + ".json");
    EXPECT_EQ(scene.head_kind, HeadKind::Mesh) << name;
    EXPECT_TRUE(scene.has_torso) << name;
    EXPECT_TRUE(std::filesystem::exists(scene.head_mesh.path)) << scene.head_mesh.path;
    EXPECT_TRUE(std::filesystem::exists(scene.hair.length_map)) << scene.hair.length_map;
  }
  EXPECT_NO_THROW((void)buildSolver(parseScene(meshScene(""), "ok.json")));
  expectRejected(meshScene(R"(, "up": "sideways")"), "head.up: must be one of");
  expectRejected(meshScene(R"(, "up": "+z", "front": "-z")"), "head.front: must be a different axis from up");
  expectRejected(meshScene(R"(, "scale": 0)"), "head.scale: must be a number in (0,");
  expectRejected(meshScene(R"(, "sdf_voxel": -1)"), "head.sdf_voxel");
  expectRejected(R"({"head": {"type": "mesh", "mesh": "nowhere/head.obj"}})",
                 "head.mesh: nowhere/head.obj: cannot open: No such file");
  expectRejected(R"({"head": {"type": "mesh"}})", "head.mesh: is required");
  expectRejected(meshScene("", R"(, "scalp": {"type": "sphere-cap"})"),
                 R"(scalp.type: "sphere-cap" needs a sphere head)");
  expectRejected(meshScene("", R"(, "scalp": {"type": "curves", "front": [[0,0,0],[1,1,1]]})"),
                 "scalp.right: is required");
  expectRejected(
      meshScene("", R"(, "scalp": {"type": "curves", "front": [[0,0]], "right": [], "back": [], "left": []})"),
      "scalp.front: must be an array of at least 2 points");
  // Curves far from each other's ends.
  expectRejected(meshScene("", R"(, "scalp": {"type": "curves",
      "front": [[-0.06,0.08,0.06],[0.06,0.08,0.06]], "right": [[0.07,0.0,0.0],[0.06,0.0,-0.08]],
      "back": [[0.06,0.0,-0.08],[-0.06,0.0,-0.08]], "left": [[-0.06,0.0,-0.08],[-0.06,0.08,0.06]]})"),
                 "consecutive curves must meet");
  expectRejected(replaced(R"("scalp": {"type": "sphere-cap", "cap_angle_deg": 100})", R"("scalp": {"type": "auto"})"),
                 "needs a mesh head");
  // A broken length map.
  std::string missing_map = meshScene("");
  missing_map.replace(missing_map.find("hair_length.png"), 15, "no_such_map.png");
  expectRejected(missing_map, "hair.length_map:");
  // Torso, obstacles and wind.
  expectRejected(meshScene("", R"(, "torso": {"mesh": "none.obj"})"),
                 "torso.mesh: none.obj: cannot open: No such file");
  expectRejected(meshScene("", R"(, "obstacles": [{"type": "cone"}])"), "obstacles[0].type: must be");
  expectRejected(meshScene("", R"(, "obstacles": [{"type": "capsule", "a": [0,0,0]}])"),
                 "obstacles[0].a: a capsule needs both");
  expectRejected(meshScene("", R"(, "obstacles": [{"radius": 0.1, "begin": 2, "end": 1}])"),
                 "obstacles[0].end: must be later");
  expectRejected(meshScene("", R"(, "wind": {"speed": -3})"), "wind.speed: must be a number in [0, 100]");
  expectRejected(meshScene("", R"(, "wind": {"direction": [0, 0, 0]})"), "wind.direction: must be a non-zero");
  expectRejected(meshScene("", R"(, "wind": {"profile": [[1, 1], [0.5, 1]]})"), "wind.profile[1]: times must increase");
  expectRejected(meshScene("", R"(, "wind": {"spacing": 0.0001})"), "more than 20 million grid cells");
  expectRejected(meshScene("", R"(, "wind": {"model": "particles", "spacing": 0.0001})"),
                 "more than 20 million air particles");
  expectRejected(meshScene("", R"(, "wind": {"gust": 1})"), "wind.gust: unknown field");
  expectRejected(meshScene("", R"(, "wind": {"model": "foam"})"),
                 "wind.model: must be \"grid\" or \"particles\", got \"foam\"");
  expectRejected(meshScene("", R"(, "wind": {"model": 3})"), "wind.model");
  expectRejected(meshScene("", R"(, "wind": {"projection_iterations": 99})"), "wind.projection_iterations");
  expectRejected(meshScene("", R"(, "wind": {"projection_iterations": 1.5})"), "wind.projection_iterations");
  expectRejected(meshScene("", R"(, "solver": {"implicit_iterations": 0})"), "solver.implicit_iterations");
  expectRejected(meshScene("", R"(, "solver": {"implicit_tolerance": -1})"), "solver.implicit_tolerance");
  expectRejected(meshScene("", R"(, "solver": {"implicit_springs": 2})"), "solver.implicit_springs");
}

TEST(SceneFiles, MissingRequiredPartsAndFiles) {
  try {
    (void)parseScene(R"({"name": "x"})", "bad.json");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: head: is required"), std::string::npos) << e.what();
  }
  try {
    (void)loadScene("/no/such/dir/scene.json");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/dir/scene.json: cannot open"), std::string::npos);
  }
}

TEST(SimParamsValidation, EveryBadValueIsNamed) {
  EXPECT_TRUE(validate(SimParams{}).empty());
  const struct {
    void (*spoil)(SimParams&);
    const char* fragment;
  } cases[] = {
      {[](SimParams& q) { q.time_step = NAN; }, "time_step = nan is not a finite number"},
      {[](SimParams& q) { q.time_step = -1e-3; }, "time_step = -0.001 must be positive"},
      {[](SimParams& q) { q.h1 = 0; }, "h1 = 0 must be positive"},
      {[](SimParams& q) { q.h2 = q.h1; }, "must be smaller than h1"},
      {[](SimParams& q) { q.youngs_modulus = INFINITY; }, "youngs_modulus = inf"},
      {[](SimParams& q) { q.alignment_threshold = 1.5f; }, "alignment_threshold = 1.5 must lie in [0, 1]"},
      {[](SimParams& q) { q.stiffness_clamp = 0.5f; }, "stiffness_clamp = 0.5"},
      {[](SimParams& q) { q.gravity.y = NAN; }, "gravity.y"},
      {[](SimParams& q) { q.air_drag = 1000.0f; }, "air_drag = 1000"},
      {[](SimParams& q) { q.target_connections = 0; }, "target_connections = 0"},
      {[](SimParams& q) { q.threads = -2; }, "threads = -2"},
  };
  for (const auto& c : cases) {
    SimParams q;
    c.spoil(q);
    const auto problems = validate(q);
    ASSERT_FALSE(problems.empty()) << c.fragment;
    bool found = false;
    for (const auto& pr : problems) found = found || pr.find(c.fragment) != std::string::npos;
    EXPECT_TRUE(found) << "no problem mentions '" << c.fragment << "', first: " << problems[0];
  }
}

TEST(SolverInput, BadParticlesAreRejected) {
  Particles p;
  p.resize(2);
  for (std::size_t i = 0; i < 2; ++i) {
    p.position[i] = glm::vec3(0, -0.01f * float(i), 0);
    p.direction[i] = glm::vec3(0, -1, 0);
    p.mass[i] = 1e-5f;
    p.arc_length[i] = i == 0 ? -0.01f : 0.01f;
    p.is_root[i] = i == 0;
  }
  auto body = std::make_shared<SphereBody>(glm::vec3(0, 1, 0), 0.1f);
  EXPECT_NO_THROW(Solver(SimParams{}, p, body));
  Particles bad = p;
  bad.position[1].x = NAN;
  EXPECT_THROW(Solver(SimParams{}, bad, body), std::invalid_argument);
  bad = p;
  bad.mass[1] = 0;
  EXPECT_THROW(Solver(SimParams{}, bad, body), std::invalid_argument);
  bad = p;
  bad.is_root[0] = 0;  // s < 0 (under the scalp) but not held
  EXPECT_THROW(Solver(SimParams{}, bad, body), std::invalid_argument);
  bad = p;
  bad.is_root[1] = 1;  // held further along, as a hair tie holds hair: allowed
  EXPECT_NO_THROW(Solver(SimParams{}, bad, body));
  SimParams params;
  params.h2 = 1.0f;
  try {
    Solver s(params, p, body);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("h2 = 1 must be smaller than h1"), std::string::npos);
  }
  EXPECT_THROW(Solver(SimParams{}, p, nullptr), std::invalid_argument);
}

TEST(PlyDump, WritesACompleteReadableFile) {
  const SceneDesc scene = parseScene(kGood, "good.json");
  Solver solver = buildSolver(scene);
  solver.advance(10);
  const auto dir = std::filesystem::temp_directory_path() / "loosehair-ply-test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "frame_00001.ply").string();
  writeParticlePly(path, solver);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  std::ifstream in(path, std::ios::binary);
  std::string line, header;
  std::size_t count = 0;
  while (std::getline(in, line)) {
    header += line + "\n";
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
    if (line == "end_header") break;
  }
  ASSERT_EQ(count, solver.particles().size());
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  std::vector<char> body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  constexpr std::size_t kRecord = 15 * 4 + 1 + 4;
  ASSERT_EQ(body.size(), count * kRecord);
  std::vector<glm::vec3> world;
  solver.worldPositions(world);
  for (std::size_t i : {std::size_t{0}, count / 2, count - 1}) {
    float xyz[3], s, density;
    std::memcpy(xyz, body.data() + i * kRecord, sizeof xyz);
    std::memcpy(&s, body.data() + i * kRecord + 11 * 4, 4);
    std::memcpy(&density, body.data() + i * kRecord + 15 * 4 + 1, 4);
    EXPECT_EQ(xyz[0], world[i].x);
    EXPECT_EQ(xyz[2], world[i].z);
    EXPECT_EQ(s, solver.particles().arc_length[i]);
    EXPECT_EQ(static_cast<unsigned char>(body[i * kRecord + 15 * 4]), solver.particles().is_root[i]);
    EXPECT_EQ(density, solver.density()[i]);
  }
  // an unwritable place: an error naming the file, and nothing left behind
  const std::string bad = (dir / "missing-dir" / "frame.ply").string();
  try {
    writeParticlePly(bad, solver);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(bad));
  EXPECT_FALSE(std::filesystem::exists(bad + ".tmp"));
  std::filesystem::remove_all(dir);
}
