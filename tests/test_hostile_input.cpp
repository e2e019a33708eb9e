// Hostile and broken input (each case found by a tester, issue "Hardening"):
// every one gets an error naming the file and the field, element or line,
// with the value, and nothing crashes, hangs or allocates without bound.
#include "test_support.hpp"

#include "init/length_map.hpp"
#include "loosehair/head_model.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

using namespace loosehair;

namespace {

namespace fs = std::filesystem;

fs::path scratchDir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("loosehair-hostile-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

std::string write(const std::string& name, const std::string& bytes) {
  const fs::path p = scratchDir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

// Runs f; expects an exception of type E whose message contains each part.
template <class E, class F>
void expectError(F&& f, std::initializer_list<const char*> parts) {
  try {
    f();
    ADD_FAILURE() << "accepted; expected an error with \"" << *parts.begin() << "\"";
  } catch (const E& e) {
    const std::string msg = e.what();
    for (const char* part : parts) EXPECT_NE(msg.find(part), std::string::npos) << msg;
    EXPECT_LT(msg.size(), 600u) << "the message quotes too much";
  }
}

const char* kSphere = R"({"head": {"type": "sphere", "radius": 0.1}, "hair": {"particles": 400}, )";

void expectSceneRejected(const std::string& json, std::initializer_list<const char*> parts) {
  expectError<SceneError>([&] { (void)buildSolver(parseScene(json, "bad.json")); }, parts);
}

}  // namespace

// ---- JSON ---------------------------------------------------------------------
TEST(HostileJson, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  expectError<SceneError>([&] { (void)parseScene(deep, "deep.json"); }, {"deep.json", "nested more than 64"});
  const std::string deep_object = "{\"a\":" + std::string(50000, '[') + std::string(50000, ']') + "}";
  expectError<SceneError>([&] { (void)parseScene(deep_object, "deep.json"); }, {"nested"});
}

TEST(HostileJson, LongValuesAreCutInMessages) {
  const std::string long_value = "{\"frames\": \"" + std::string(100000, 'y') + "\"}";
  expectError<SceneError>([&] { (void)parseScene(long_value, "long.json"); },
                          {"long.json", "frames", "100000 characters"});
  const std::string long_key = "{\"" + std::string(100000, 'k') + "\": 1}";
  expectError<SceneError>([&] { (void)parseScene(long_key, "long.json"); }, {"long.json"});
}

TEST(HostileJson, DuplicateKeysAreAnError) {
  expectError<SceneError>([] { (void)parseScene(R"({"hair": {"particles": 100, "particles": 200}})", "dup.json"); },
                          {"dup.json", "hair.particles", "twice"});
  expectError<SceneError>([] { (void)parseScene(R"({"frames": 1, "frames": 2})", "dup.json"); }, {"frames", "twice"});
}

TEST(HostileJson, IntegersWrittenWithAnExponentAreIntegers) {
  const std::string head = std::string(kSphere);
  EXPECT_EQ(parseScene(head + R"("frames": 1e5})", "e.json").frames, 100000);
  expectError<SceneError>([&] { (void)parseScene(head + R"("frames": 1.5})", "e.json"); },
                          {"frames", "whole number", "1.5"});
  expectError<SceneError>([&] { (void)parseScene(head + R"("seed": 1e300})", "e.json"); }, {"seed"});
  expectError<SceneError>([&] { (void)parseScene(head + R"("seed": 18446744073709551615})", "e.json"); }, {"seed"});
}

TEST(HostileJson, TruncatedJsonSaysWhere) {
  expectError<SceneError>([] { (void)parseScene(R"({"frames": 3)", "t.json"); },
                          {"t.json", "invalid JSON at line 1, column"});
}

// ---- files that are not regular files -------------------------------------------
TEST(HostileFiles, DirectoriesFifosAndDevicesAreRefusedWithoutHanging) {
  expectError<SceneError>([] { (void)loadScene(scratchDir().string()); }, {"is a directory"});
  const std::string fifo = (scratchDir() / "fifo.json").string();
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectError<SceneError>([&] { (void)loadScene(fifo); }, {"fifo.json", "FIFO"});
  expectError<MeshError>([&] { (void)loadMesh(fifo); }, {"FIFO"});
  expectError<SceneError>([] { (void)loadScene("/dev/zero"); }, {"/dev/zero", "character device"});
  expectError<std::exception>([] { (void)LengthMap("/dev/urandom"); }, {"/dev/urandom", "character device"});
  expectError<MeshError>([] { (void)loadMesh(scratchDir().string() + "/"); }, {"directory"});
  expectError<SceneError>([] { (void)loadScene((scratchDir() / "missing.json").string()); },
                          {"missing.json", "No such file"});
}

// ---- images ---------------------------------------------------------------------
TEST(HostileImages, PgmHeadersAndDataAreChecked) {
  expectError<std::exception>([] { (void)LengthMap(write("neg.pgm", "P5\n-4 4\n255\n" + std::string(64, 'x'))); },
                              {"neg.pgm", "width"});
  expectError<std::exception>([] { (void)LengthMap(write("trunc.pgm", "P5\n8 8\n255\n" + std::string(10, 'x'))); },
                              {"trunc.pgm", "truncated"});
  expectError<std::exception>([] { (void)LengthMap(write("huge.pgm", "P2\n65536 65536\n255\n0 0 0\n")); },
                              {"huge.pgm"});
  expectError<std::exception>([] { (void)LengthMap(write("short.pgm", "P2\n100 100\n255\n0 0 0\n")); },
                              {"short.pgm", "too short"});
  expectError<std::exception>([] { (void)LengthMap(write("over.pgm", "P2\n2 1\n10\n5 11\n")); },
                              {"over.pgm", "pixel 1"});
  const LengthMap plain(write("ok.pgm", "P2\n# a comment\n2 1\n10\n0 10\n"));
  EXPECT_FLOAT_EQ(plain.maximum(), 1.0f);
  const LengthMap binary(write("ok5.pgm", std::string("P5\n2 1\n255\n") + char(0) + char(255)));
  EXPECT_FLOAT_EQ(binary.maximum(), 1.0f);
  expectError<std::exception>([] { (void)LengthMap(write("junk.png", "not an image at all")); }, {"junk.png"});
}

// ---- meshes ---------------------------------------------------------------------
TEST(HostileMeshes, AbsurdCountsAreRefusedBeforeAllocating) {
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex ";
  const std::string ply_tail =
      "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n";
  expectError<MeshError>([&] { (void)loadMesh(write("big.ply", ply_head + "2000000000" + ply_tail)); },
                         {"big.ply", "2000000000 vertices"});
  expectError<MeshError>([&] { (void)loadMesh(write("neg.ply", ply_head + "-5" + ply_tail)); }, {"neg.ply", "-5"});
  expectError<MeshError>([&] { (void)loadMesh(write("big.off", "OFF\n100000000 1 0\n0 0 0\n")); },
                         {"big.off", "100000000 vertices"});
}

TEST(HostileMeshes, MeshesOfTooManyTrianglesAreRefusedUnlessAllowed) {
  // the bundled head (81920 triangles) against a lowered limit: what a
  // mesh of tens of millions of triangles meets at the default one
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
  scene.limits.mesh.max_triangles = 50000;
  expectError<SceneError>([&] { (void)HeadModel::build(scene, scene.source, scene.limits.mesh); },
                          {"hang.json", "head.mesh", "head.ply", "81920 faces", "limit of 50000", "--allow-expensive"});
  scene.limits.mesh.max_triangles = 81920;
  EXPECT_NO_THROW((void)HeadModel::build(scene, scene.source, scene.limits.mesh));

  // Refused from the count before the faces are read: each file below
  // claims more faces than it holds, which would be a different error if
  // its faces were read first.
  MeshLoadOptions limited;
  limited.max_faces = 2;
  const std::string ply = std::string("ply\nformat ascii 1.0\nelement vertex 3\n") +
                          "property float x\nproperty float y\nproperty float z\nelement face 3\n"
                          "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  expectError<MeshTooLargeError>([&] { (void)loadMesh(write("many.ply", ply), limited); },
                                 {"many.ply", "3 faces", "limit of 2"});
  expectError<MeshTooLargeError>(
      [&] { (void)loadMesh(write("many.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n"), limited); },
      {"many.off", "3 faces", "limit of 2"});
  std::string stl(84, '\0');
  const std::uint32_t claimed = 3;
  std::memcpy(stl.data() + 80, &claimed, 4);
  stl += std::string(3 * 50, '\0');  // three (degenerate) triangles: a binary STL by its size
  expectError<MeshTooLargeError>([&] { (void)loadMesh(write("many.stl", stl), limited); },
                                 {"many.stl", "3 faces", "limit of 2"});
  // ASCII STL has no count: its facets are counted before OpenMesh reads
  // them (these three, all of one point, would be refused as degenerate)
  std::string ascii = "solid x\n";
  for (int k = 0; k < 3; ++k)
    ascii += "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0 0\nvertex 0 0 0\nendloop\nendfacet\n";
  ascii += "endsolid x\n";
  expectError<MeshTooLargeError>([&] { (void)loadMesh(write("many-ascii.stl", ascii), limited); },
                                 {"many-ascii.stl", "3 faces", "limit of 2"});
  // OBJ has no count: refused at the face past the limit, before the next
  // (whose bad index would otherwise be the error)
  expectError<MeshTooLargeError>(
      [&] {
        (void)loadMesh(write("many.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 1 2 99\n"),
                       limited);
      },
      {"many.obj", "more than 2 faces", "limit of 2"});
  // polygons count as the triangles they become
  expectError<MeshTooLargeError>(
      [&] {
        (void)loadMesh(write("quads.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 5\n"),
                       limited);
      },
      {"quads.obj", "3 faces", "limit of 2"});
  // glTF: from the JSON's accessor counts, before any buffer is read (the
  // buffers below are missing, which the reader would name instead); a
  // strip of n corners is n - 2 triangles, a node's children count
  const std::string gltf =
      R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
          "nodes": [{"mesh": 0, "children": [1]}, {"mesh": 1}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]},
                     {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5}]}],
          "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3"},
                        {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}],
          "bufferViews": [{"buffer": 0, "byteLength": 72}, {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
          "buffers": [{"byteLength": 84, "uri": "missing.bin"}]})";
  expectError<MeshTooLargeError>([&] { (void)loadMesh(write("many.gltf", gltf), limited); },
                                 {"many.gltf", "3 faces", "limit of 2"});
  std::string json = gltf;
  while (json.size() % 4 != 0) json += ' ';
  std::string glb = "glTF";
  auto u32 = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2);
  u32(static_cast<std::uint32_t>(20 + json.size()));
  u32(static_cast<std::uint32_t>(json.size()));
  glb += "JSON" + json;
  expectError<MeshTooLargeError>([&] { (void)loadMesh(write("many.glb", glb), limited); },
                                 {"many.glb", "3 faces", "limit of 2"});
  limited.max_faces = 3;  // within the limit: the reader's own error
  expectError<MeshError>([&] { (void)loadMesh(write("fits.gltf", gltf), limited); }, {"fits.gltf", "missing.bin"});
}

TEST(HostileMeshes, NonFiniteVerticesAndBadIndicesAreErrors) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  for (const char* bad : {"nan", "inf", "1e400", "-1e400"}) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv " + std::string(bad) + " 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
    expectError<MeshError>([&] { (void)loadMesh(write("nonfinite.obj", obj)); },
                           {"nonfinite.obj", "line 3", "not a finite number"});
  }
  expectError<MeshError>([&] { (void)loadMesh(write("range.obj", tri + "f 1 2 9\n")); },
                         {"range.obj", "line 5", "vertex 9"});
  expectError<MeshError>([&] { (void)loadMesh(write("zero.obj", tri + "f 0 1 2\n")); }, {"vertex 0"});
  expectError<MeshError>([&] { (void)loadMesh(write("neg.obj", tri + "f -1 -2 -7\n")); }, {"vertex -7"});
  // relative indices within range are fine
  EXPECT_NO_THROW((void)loadMesh(write("rel.obj", tri + "f -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n")));
}

TEST(HostileMeshes, GltfNodeCyclesAreRefused) {
  const std::string cyc =
      R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"children":[1]},{"children":[0]}]})";
  expectError<MeshError>([&] { (void)loadMesh(write("cycle.gltf", cyc)); }, {"cycle.gltf", "cycle"});
  const std::string self = R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"children":[0,0]}]})";
  expectError<MeshError>([&] { (void)loadMesh(write("self.gltf", self)); }, {"self.gltf", "reached twice"});
}

TEST(HostileMeshes, NamesWithoutAKnownExtensionSaySo) {
  expectError<MeshError>([&] { (void)loadMesh(write("noext", "v 0 0 0\n")); }, {"noext", "no extension"});
  expectError<MeshError>([&] { (void)loadMesh(write("x.xyz", "v 0 0 0\n")); }, {"x.xyz", "unknown mesh format"});
}

// ---- scenes whose hair hangs on nothing ------------------------------------------
TEST(HostileScenes, HairOnNothingIsRefused) {
  expectSceneRejected(R"({"head": {"type": "sphere", "radius": 1e-9}, "hair": {"particles": 400}})",
                      {"bad.json", "head.radius", "1e-09"});
  expectSceneRejected(std::string(kSphere) + R"("scalp": {"cap_angle_deg": 1e-6}})",
                      {"bad.json", "cannot reach a root"});
  expectSceneRejected(std::string(kSphere) + R"("solver": {"h1": 0.0001}})", {"bad.json", "h1"});
}

TEST(HostileScenes, TinyValuesNameTheirField) {
  expectSceneRejected(R"({"head": {"type": "sphere", "radius": 0.1}, "hair": {"mass": 1e-300}})",
                      {"hair.mass", "1e-300"});
  expectSceneRejected(std::string(kSphere) + R"("solver": {"material_density": 1e-3}})", {"solver.material_density"});
}

// Too few substeps for a damping rate: the error names the rate, the step
// and where the step comes from (the scene's substeps, not a solver field).
TEST(HostileScenes, TooFewSubstepsNameTheSubsteps) {
  expectSceneRejected(
      std::string(kSphere) + R"("substeps": 1})",
      {"bad.json", "solver.collision_rate", "time_step = 0.0333333", "1 / (30 x 1)", "\"substeps\": \"auto\""});
}

TEST(HostileScenes, ExpensiveSettingsAreRefusedUnlessAllowed) {
  // explicit springs: a stiffness that needs millions of steps a frame
  expectSceneRejected(std::string(kSphere) + R"("solver": {"youngs_modulus": 1e12, "implicit_springs": false}})",
                      {"bad.json", "steps", "limit", "youngs_modulus", "--allow-expensive"});
  {  // implicit springs: the same stiffness at the steps accuracy asks for
    BuildReport report;
    (void)buildSolver(
        parseScene(std::string(kSphere) + R"("solver": {"youngs_modulus": 1e12, "implicit_springs": true}})",
                   "stiff.json"),
        &report);
    EXPECT_LE(report.substeps, 4);
  }
  expectSceneRejected(std::string(kSphere) + R"("wind": {"spacing": 0.002}})",
                      {"bad.json", "wind.spacing", "grid cells"});
  // a long frame: the message names what bounds the step and the frame, not
  // the stiffness (which does not bound the implicit springs)
  expectSceneRejected(
      std::string(kSphere) + R"("frame_rate": 0.01})",
      {"bad.json", "implicit springs' accuracy", "1/0.01 s", "9000 steps", "frame_rate", "--allow-expensive"});
  expectSceneRejected(std::string(kSphere) + R"("frame_rate": 0.1, "solver": {"collision_rate": 100}})",
                      {"bad.json", "solver.collision_rate = 100", "4000 steps", "lower solver.collision_rate"});
  {  // a high damping rate with "auto" takes the steps it needs (it was
     // refused by a check against a 1 ms step)
    BuildReport report;
    (void)buildSolver(parseScene(std::string(kSphere) + R"("solver": {"collision_rate": 400}})", "rate.json"), &report);
    EXPECT_EQ(report.substeps, 54);  // ceil(1/30 s / (0.25 / 400 1/s))
    EXPECT_LE(400.0 * report.time_step, 0.25 + 1e-6);
  }
  {  // so does a strong hold (100 Hz, the field's top) on a styled scene
    SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
    scene.hair.style = lhtest::sourceDir() + "/data/styles/bob.json";
    scene.sim.shape_keeping = 100.0f;
    scene.shape_keeping_auto = false;
    BuildReport report;
    (void)buildSolver(scene, &report);
    EXPECT_GE(report.substeps, 42);  // 2 pi 100 Hz dt <= 0.5
    EXPECT_LE(2.0 * 3.14159265 * 100.0 * report.time_step, kMaxHoldPhasePerStep + 1e-6);
  }
  // twenty million particles would need some 70 GB
  expectSceneRejected(R"({"head": {"type": "sphere", "radius": 0.1}, "hair": {"particles": 20000000}})",
                      {"bad.json", "hair.particles: 20000000", "limit of 2000000", "--allow-expensive"});
  // steps given by hand are held to the same limit
  expectSceneRejected(std::string(kSphere) + R"("substeps": 100000})",
                      {"bad.json", "substeps: 100000", "limit of 2000", "--allow-expensive"});
  // with the limit raised the same scene is built
  SceneDesc scene =
      parseScene(std::string(kSphere) + R"("solver": {"youngs_modulus": 1e12, "implicit_springs": false}})", "ok.json");
  scene.limits.max_substeps = 1 << 30;
  BuildReport report;
  EXPECT_NO_THROW((void)buildSolver(scene, &report));
  EXPECT_GT(report.substeps, 2000);
}
