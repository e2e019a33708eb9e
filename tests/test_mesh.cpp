// Meshes (method.md §5, §6.1): every supported format loads the same surface,
// axis and scale options place it, bad meshes are rejected with the named
// problem, and signed-distance grids have the right sign and distance.
#include "util/random.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

using namespace loosehair;
namespace fs = std::filesystem;

namespace {

fs::path tempDir() {
  const fs::path d = fs::temp_directory_path() / ("loosehair-mesh-test-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// An octahedron-subdivided sphere: closed, outward, 8 * 4^levels triangles.
TriangleMesh sphereMesh(float radius, int levels, glm::vec3 centre = glm::vec3(0.0f)) {
  TriangleMesh m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto midpoint = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back(glm::normalize(m.vertices[a] + m.vertices[b]));
      return mid[key] = static_cast<unsigned>(m.vertices.size() - 1);
    };
    std::vector<glm::u32vec3> out;
    for (auto t : m.triangles) {
      const unsigned a = midpoint(t.x, t.y), b = midpoint(t.y, t.z), c = midpoint(t.z, t.x);
      out.insert(out.end(), {{t.x, a, c}, {t.y, b, a}, {t.z, c, b}, {a, b, c}});
    }
    m.triangles = out;
  }
  for (auto& v : m.vertices) v = centre + radius * v;
  return m;
}

void writeText(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// A unit cube [0,1]^3, outward triangles, in the given format.
const char* kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";

std::string cubeOff() {
  return "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
         "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n";
}

std::string cubePly() {
  return "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 6\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
         "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n";
}

std::string cubeStl() {
  const glm::vec3 v[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::string s = "solid cube\n";
  auto tri = [&](int a, int b, int c) {
    const glm::vec3 n = glm::normalize(glm::cross(v[b] - v[a], v[c] - v[a]));
    char buf[512];
    std::snprintf(
        buf, sizeof buf,
        "facet normal %g %g %g\nouter loop\nvertex %g %g %g\nvertex %g %g %g\nvertex %g %g %g\nendloop\nendfacet\n",
        n.x, n.y, n.z, v[a].x, v[a].y, v[a].z, v[b].x, v[b].y, v[b].z, v[c].x, v[c].y, v[c].z);
    s += buf;
  };
  for (const auto& f : q) {
    tri(f[0], f[1], f[2]);
    tri(f[0], f[2], f[3]);
  }
  return s + "endsolid cube\n";
}

// The cube as glTF (separate vertices per face, as exporters write them),
// under a node that scales it by 2.
void writeCubeGltf(const fs::path& path, bool binary) {
  const glm::vec3 v[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<float> pos;
  std::vector<std::uint16_t> idx;
  for (const auto& f : q) {
    const auto base = static_cast<std::uint16_t>(pos.size() / 3);
    for (int k = 0; k < 4; ++k) pos.insert(pos.end(), {v[f[k]].x, v[f[k]].y, v[f[k]].z});
    idx.insert(idx.end(), {base, static_cast<std::uint16_t>(base + 1), static_cast<std::uint16_t>(base + 2), base,
                           static_cast<std::uint16_t>(base + 2), static_cast<std::uint16_t>(base + 3)});
  }
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  buffer.data.resize(pos.size() * 4 + idx.size() * 2);
  std::memcpy(buffer.data.data(), pos.data(), pos.size() * 4);
  std::memcpy(buffer.data.data() + pos.size() * 4, idx.data(), idx.size() * 2);
  model.buffers.push_back(buffer);
  tinygltf::BufferView bp, bi;
  bp.buffer = 0;
  bp.byteOffset = 0;
  bp.byteLength = pos.size() * 4;
  bi.buffer = 0;
  bi.byteOffset = pos.size() * 4;
  bi.byteLength = idx.size() * 2;
  model.bufferViews = {bp, bi};
  tinygltf::Accessor ap, ai;
  ap.bufferView = 0;
  ap.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  ap.count = pos.size() / 3;
  ap.type = TINYGLTF_TYPE_VEC3;
  ap.minValues = {0, 0, 0};
  ap.maxValues = {1, 1, 1};
  ai.bufferView = 1;
  ai.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  ai.count = idx.size();
  ai.type = TINYGLTF_TYPE_SCALAR;
  model.accessors = {ap, ai};
  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = 0;
  prim.indices = 1;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.scale = {2, 2, 2};
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.asset.version = "2.0";
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, path.string(), true, true, true, binary));
}

struct MeshTest {
  // Every edge is shared by exactly two triangles that run it in opposite directions.
  static void expectClosed(const TriangleMesh& m) {
    std::map<std::pair<unsigned, unsigned>, int> count;
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) ++count[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, c] : count) {
      ASSERT_EQ(c, 1) << "edge " << e.first << "-" << e.second << " used twice in one direction";
      ASSERT_EQ(count.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is open";
    }
  }
};

void expectRejected(const fs::path& path, const std::string& problem, const MeshLoadOptions& opt = {}) {
  try {
    loadMesh(path.string(), opt);
    ADD_FAILURE() << path << " was accepted; expected: " << problem;
  } catch (const MeshError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find(problem), std::string::npos) << "expected '" << problem << "' in: " << what;
  }
}

}  // namespace

TEST(Mesh, EveryFormatLoadsTheSameClosedCube) {
  const fs::path d = tempDir();
  writeText(d / "cube.obj", kCubeObj);
  writeText(d / "cube.off", cubeOff());
  writeText(d / "cube.ply", cubePly());
  writeText(d / "cube.stl", cubeStl());
  writeCubeGltf(d / "cube.gltf", false);
  writeCubeGltf(d / "cube.glb", true);
  for (const char* name : {"cube.obj", "cube.off", "cube.ply", "cube.stl", "cube.gltf", "cube.glb"}) {
    SCOPED_TRACE(name);
    MeshReport r;
    const TriangleMesh m = loadMesh((d / name).string(), {}, &r);
    const bool gltf = std::string(name).find("gl") != std::string::npos;
    const float side = gltf ? 2.0f : 1.0f;  // the glTF node scales by 2
    EXPECT_EQ(m.vertices.size(), 8u) << "vertices at equal positions are welded";
    EXPECT_EQ(m.triangles.size(), 12u) << "quads become two triangles";
    EXPECT_TRUE(r.closed());
    EXPECT_EQ(r.components, 1u);
    EXPECT_NEAR(r.volume, side * side * side, 1e-5);
    EXPECT_FALSE(r.flipped);
    EXPECT_NEAR(r.upper.x - r.lower.x, side, 1e-6);
  }
  fs::remove_all(d);
}

TEST(Mesh, ScaleUpAndFrontAxesPlaceTheMesh) {
  const fs::path d = tempDir();
  // A box 1 x 2 x 3 (x, y, z) in a file whose up is +z and face is -y, in cm.
  writeText(d / "box.obj",
            "v 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 0\nv 0 0 3\nv 1 0 3\nv 1 2 3\nv 0 2 3\n"
            "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n");
  MeshLoadOptions opt;
  opt.scale = 0.01f;
  opt.up = parseAxis("+z");
  opt.front = parseAxis("-y");
  opt.offset = glm::vec3(0.0f, 1.0f, 0.0f);
  MeshReport r;
  loadMesh((d / "box.obj").string(), opt, &r);
  // file z (3 cm) becomes height, file y (2 cm) becomes depth, x stays width
  EXPECT_NEAR(r.upper.y - r.lower.y, 0.03f, 1e-6);
  EXPECT_NEAR(r.upper.z - r.lower.z, 0.02f, 1e-6);
  EXPECT_NEAR(r.upper.x - r.lower.x, 0.01f, 1e-6);
  EXPECT_NEAR(r.lower.y, 1.0f, 1e-6) << "offset applied after scaling";
  EXPECT_NEAR(r.upper.z, 0.0f, 1e-6) << "file -y (the face) becomes +z";
  EXPECT_FALSE(r.flipped) << "a proper rotation keeps the winding";
  EXPECT_THROW(parseAxis("up"), std::invalid_argument);
  fs::remove_all(d);
}

TEST(Mesh, BadMeshesAreRejectedWithTheProblem) {
  const fs::path d = tempDir();
  expectRejected(d / "missing.obj", "No such file");
  writeText(d / "cube.xyz", kCubeObj);
  expectRejected(d / "cube.xyz", "unknown mesh format");
  writeText(d / "empty.obj", "# nothing\n");
  expectRejected(d / "empty.obj", "no triangles");
  writeText(d / "flat.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 1 3 2\nf 1 4 3\n");
  expectRejected(d / "flat.obj", "flat");
  // A sphere with a C-shaped band cut out of it: one opening, which a fan
  // from its centroid would fold over itself, on more than 2% of the edges.
  {
    TriangleMesh s = sphereMesh(1.0f, 3);
    std::erase_if(s.triangles, [&](const glm::u32vec3& t) {
      const glm::vec3 c = (s.vertices[t.x] + s.vertices[t.y] + s.vertices[t.z]) / 3.0f;
      return std::abs(c.y) < 0.25f && std::abs(std::atan2(c.z, c.x)) < 2.6f;
    });
    writeObj(s, (d / "open.obj").string());
    expectRejected(d / "open.obj", "not closed: 1 hole(s), 1 of them not flat enough");
  }
  // Every triangle of a closed mesh reversed but one: inconsistent.
  {
    TriangleMesh s = sphereMesh(1.0f, 2);
    for (std::size_t t = 1; t < s.triangles.size(); t += 2) std::swap(s.triangles[t].y, s.triangles[t].z);
    writeObj(s, (d / "mixed.obj").string());
    expectRejected(d / "mixed.obj", "not consistently oriented");
  }
  // Mostly degenerate triangles.
  {
    TriangleMesh s = sphereMesh(1.0f, 1);
    const std::size_t good = s.triangles.size();
    for (std::size_t k = 0; k < good; ++k) {  // zero-area slivers: three points on a line
      const auto base = static_cast<unsigned>(s.vertices.size());
      const glm::vec3 o(2.0f + static_cast<float>(k), 0.0f, 0.0f);
      s.vertices.insert(s.vertices.end(), {o, o + glm::vec3(0.1f, 0, 0), o + glm::vec3(0.2f, 0, 0)});
      s.triangles.emplace_back(base, base + 1, base + 2);
    }
    const std::string path = (d / "degenerate.obj").string();
    std::ofstream out(path);
    for (auto v : s.vertices) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    for (auto t : s.triangles) out << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
    out.close();
    expectRejected(d / "degenerate.obj", "degenerate");
  }
  // The scale must be positive.
  MeshLoadOptions bad;
  bad.scale = -1.0f;
  writeText(d / "cube.obj", kCubeObj);
  expectRejected(d / "cube.obj", "scale", bad);
  fs::remove_all(d);
}

TEST(Mesh, NonFiniteVerticesAreRejected) {
  TriangleMesh s = sphereMesh(1.0f, 1);
  s.vertices[3].y = std::numeric_limits<float>::quiet_NaN();
  try {
    checkMesh(s, "nan-mesh");
    ADD_FAILURE() << "accepted a NaN vertex";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("nan-mesh: vertex 3 is not finite"), std::string::npos) << e.what();
  }
}

TEST(Mesh, NonManifoldMeshesAreRejected) {
  // Checked on the in-memory mesh: OpenMesh itself drops faces that would
  // make an edge non-manifold while reading, which shows up as holes.
  TriangleMesh s = sphereMesh(1.0f, 2);
  const std::size_t n = s.triangles.size();
  for (std::size_t t = 0; t < n; t += 4) {  // a fin on every fourth triangle's first edge
    s.vertices.push_back(1.5f * (s.vertices[s.triangles[t].x] + s.vertices[s.triangles[t].y]));
    s.triangles.emplace_back(s.triangles[t].x, s.triangles[t].y, static_cast<unsigned>(s.vertices.size() - 1));
  }
  try {
    checkMesh(s, "fins");
    ADD_FAILURE() << "accepted a mesh with fins";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("three or more triangles"), std::string::npos) << e.what();
  }
}

TEST(Mesh, HolesAreClosedSoTheBodyHasAnInside) {
  // The bundled head cut open below the neck, as many head models are.
  TriangleMesh head = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  TriangleMesh open;
  open.vertices = head.vertices;
  for (const auto& t : head.triangles)
    if (!(head.vertices[t.x].y < -0.20f && head.vertices[t.y].y < -0.20f && head.vertices[t.z].y < -0.20f))
      open.triangles.push_back(t);
  const MeshReport r = checkMesh(open, "open-neck");
  EXPECT_GT(r.boundary_edges, 20u);
  EXPECT_EQ(r.holes_filled, 1u);
  MeshTest::expectClosed(open);
  const auto body = GridSdfBody::bake(open, {});
  const glm::vec3 inside[] = {{0, 0.03f, 0}, {0, -0.17f, -0.014f}};
  for (const auto& p : inside) {
    float phi;
    glm::vec3 n;
    body->signedDistance(&p, 1, &phi, &n);
    EXPECT_LT(phi, -0.01f) << "the inside of an open head is inside";
  }
}

TEST(Mesh, AFewFlatOpeningsAreClosedWhateverTheirSize) {
  // A bust cut flat under the chest: the opening is 2.3% of the edges, and
  // closes with a flat fan.
  TriangleMesh bust = loadMesh(lhtest::sourceDir() + "/data/meshes/torso.ply");
  std::erase_if(bust.triangles, [&](const glm::u32vec3& t) {
    return bust.vertices[t.x].y < -0.30f || bust.vertices[t.y].y < -0.30f || bust.vertices[t.z].y < -0.30f;
  });
  const std::size_t open_triangles = bust.triangles.size();
  const MeshReport r = checkMesh(bust, "bust");
  EXPECT_EQ(r.holes_filled, 1u);
  const std::size_t edges = (3 * open_triangles + r.boundary_edges) / 2;
  EXPECT_GT(r.boundary_edges * 50, edges) << "more than 2% of the edges";
  MeshTest::expectClosed(bust);
  // A cube with two opposite faces missing is closed to the cube.
  TriangleMesh cube;
  cube.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  cube.triangles = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4}, {2, 3, 7}, {2, 7, 6}};
  const MeshReport c = checkMesh(cube, "open-cube");
  EXPECT_EQ(c.holes_filled, 2u);
  EXPECT_NEAR(c.volume, 1.0, 1e-6);
  // Five openings are too many to guess an inside for, at more than 2% of the edges.
  TriangleMesh holes = sphereMesh(1.0f, 2);
  std::vector<glm::u32vec3> kept;
  for (std::size_t t = 0; t < holes.triangles.size(); ++t)
    if (t % 25 != 0 || t > 100) kept.push_back(holes.triangles[t]);
  holes.triangles = kept;
  try {
    checkMesh(holes, "five-holes");
    ADD_FAILURE() << "closed five holes on 8% of the edges";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("5 hole(s)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at most 4 openings"), std::string::npos) << e.what();
  }
}

TEST(Mesh, DecimationForDrawingKeepsTheShapeClosed) {
  const TriangleMesh head = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  TriangleMesh small = decimate(head, 8000);
  EXPECT_LE(small.triangles.size(), 8000u);
  EXPECT_GT(small.triangles.size(), 7000u);
  MeshTest::expectClosed(small);
  MeshReport before, after;
  TriangleMesh copy = head;
  before = checkMesh(copy, "full");
  after = checkMesh(small, "decimated");
  EXPECT_FALSE(after.flipped);
  EXPECT_NEAR(after.volume / before.volume, 1.0, 0.02);
  EXPECT_NEAR(after.upper.y, before.upper.y, 0.002) << "the crown stays where it was";
  EXPECT_EQ(decimate(small, 100000).triangles.size(), small.triangles.size()) << "small meshes are left alone";
}

TEST(Mesh, InsideOutMeshesAreTurnedRightWayOut) {
  TriangleMesh s = sphereMesh(0.5f, 2);
  for (auto& t : s.triangles) std::swap(t.y, t.z);
  const MeshReport r = checkMesh(s, "inside-out");
  EXPECT_TRUE(r.flipped);
  EXPECT_GT(r.volume, 0.0);
  const auto a = s.vertices[s.triangles[0].x], b = s.vertices[s.triangles[0].y], c = s.vertices[s.triangles[0].z];
  EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f), 0.0f) << "normals point outwards again";
}

TEST(Mesh, BundledHeadAndTorsoAreClosedHumanSized) {
  MeshReport h, t;
  const TriangleMesh head = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply", {}, &h);
  loadMesh(lhtest::sourceDir() + "/data/meshes/torso.ply", {}, &t);
  for (const MeshReport* r : {&h, &t}) {
    EXPECT_TRUE(r->closed());
    EXPECT_EQ(r->misoriented_edges, 0u);
    EXPECT_EQ(r->components, 1u);
    EXPECT_FALSE(r->flipped) << "the generator writes outward triangles";
  }
  // Head: crown to chin about 0.23 m (the neck hangs below the chin), a
  // head's width and depth, face towards +Z.
  const float width = h.upper.x - h.lower.x, depth = h.upper.z - h.lower.z;
  EXPECT_GT(width, 0.14f);
  EXPECT_LT(width, 0.20f);
  EXPECT_GT(depth, 0.18f);
  EXPECT_LT(depth, 0.26f);
  float chin = 1;  // lowest point in front of the neck
  for (const auto& v : head.vertices)
    if (v.z > 0.05f) chin = std::min(chin, v.y);
  EXPECT_NEAR(h.upper.y - chin, 0.23f, 0.02f);
  float nose = -1;
  for (const auto& v : head.vertices) nose = std::max(nose, v.z);
  EXPECT_GT(nose, -h.lower.z * 0.9f) << "the nose (front, +Z) sticks out further than the back of the head";
  // Torso: shoulders about 0.4 m wide, below the head.
  EXPECT_NEAR(t.upper.x - t.lower.x, 0.42f, 0.06f);
  EXPECT_LT(t.upper.y, chin);
}

TEST(Sdf, SphereMeshDistanceAndNormal) {
  const float radius = 0.1f;
  const TriangleMesh s = sphereMesh(radius, 5, glm::vec3(0.02f, -0.01f, 0.0f));
  SdfBakeOptions opt;
  opt.voxel_size = 0.003f;
  const auto body = GridSdfBody::bake(s, opt);
  const glm::vec3 centre(0.02f, -0.01f, 0.0f);
  const glm::vec3 pts[] = {centre,
                           centre + glm::vec3(0.05f, 0, 0),
                           centre + glm::vec3(0, 0.099f, 0),
                           centre + glm::vec3(0, 0, 0.12f),
                           centre + glm::vec3(0.1f, 0.1f, 0.0f),
                           centre + glm::vec3(0.5f, 0, 0)};
  for (const auto& p : pts) {
    float phi;
    glm::vec3 n;
    body->signedDistance(&p, 1, &phi, &n);
    const float exact = glm::length(p - centre) - radius;
    // Near the surface: within the polygon's sagitta and a voxel's
    // interpolation; deep inside the bake is only approximate.
    const float tolerance = std::abs(exact) < 0.03f ? 0.0015f : 0.05f * std::abs(exact);
    EXPECT_NEAR(phi, exact, tolerance) << p.x << " " << p.y << " " << p.z;
    EXPECT_EQ(phi < 0.0f, exact < 0.0f);
    if (glm::length(p - centre) > 0.03f) {
      EXPECT_GT(glm::dot(n, glm::normalize(p - centre)), 0.98f);
    }
  }
}

TEST(Sdf, BundledHeadInsideAndOutside) {
  const TriangleMesh head = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  const auto body = GridSdfBody::bake(head, {});
  const glm::vec3 inside[] = {{0, 0.03f, 0}, {0, -0.2f, -0.006f}, {0.05f, 0.05f, -0.02f}, {0, -0.05f, 0.06f}};
  const glm::vec3 outside[] = {{0, 0.2f, 0}, {0.15f, 0, 0}, {0, 0, 0.2f}, {0, -0.15f, 0.1f}, {0, 0, -0.15f}};
  for (const auto& p : inside) {
    float phi;
    glm::vec3 n;
    body->signedDistance(&p, 1, &phi, &n);
    EXPECT_LT(phi, -0.01f) << "inside " << p.x << " " << p.y << " " << p.z;
  }
  for (const auto& p : outside) {
    float phi;
    glm::vec3 n;
    body->signedDistance(&p, 1, &phi, &n);
    EXPECT_GT(phi, 0.01f) << "outside " << p.x << " " << p.y << " " << p.z;
  }
  // The crown (top vertex) is on the surface, with the normal pointing up.
  glm::vec3 top(0, -1, 0);
  for (const auto& v : head.vertices)
    if (v.y > top.y) top = v;
  float phi;
  glm::vec3 n;
  body->signedDistance(&top, 1, &phi, &n);
  EXPECT_NEAR(phi, 0.0f, 0.5f * body->voxelSize());
  EXPECT_GT(n.y, 0.95f);
}

// The solver's contact queries skip the exact distance far from the surface
// (signedDistanceBelow): below the limit the answer must be the exact one,
// bit for bit, and above it never below the limit; on a fresh bake and on
// one read back from the cache.
TEST(Sdf, BelowTheLimitTheQueryIsExactAndAboveItABound) {
  const fs::path d = tempDir() / "cache-below";
  fs::remove_all(d);
  SdfBakeOptions opt;
  opt.voxel_size = 0.003f;
  opt.cache_dir = d.string();
  const TriangleMesh s = sphereMesh(0.1f, 4);
  for (int pass = 0; pass < 2; ++pass) {
    bool cached = false;
    const auto body = GridSdfBody::bake(s, opt, &cached);
    EXPECT_EQ(cached, pass == 1);
    // points from the centre to well outside the grid's box
    std::vector<glm::vec3> p;
    Random rng(12345);
    for (int k = 0; k < 100000; ++k)
      p.emplace_back(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
    std::vector<float> exact(p.size()), below(p.size());
    std::vector<glm::vec3> exact_n(p.size()), below_n(p.size());
    body->signedDistance(p.data(), p.size(), exact.data(), exact_n.data());
    for (float limit : {-0.01f, 0.0f, 0.002f, 0.02f, 0.1f}) {
      body->signedDistanceBelow(p.data(), p.size(), limit, below.data(), below_n.data());
      std::size_t skipped = 0;
      for (std::size_t k = 0; k < p.size(); ++k) {
        if (exact[k] < limit) {
          ASSERT_EQ(below[k], exact[k]) << "limit " << limit << ", point " << k;
          ASSERT_EQ(below_n[k], exact_n[k]) << "limit " << limit << ", point " << k;
        } else {
          ASSERT_GE(below[k], limit) << "limit " << limit << ", point " << k;
        }
        skipped += below[k] != exact[k] ? 1 : 0;
      }
      // and it does skip far from the surface (most of this box)
      if (limit <= 0.02f) {
        EXPECT_GT(skipped, p.size() / 2) << "limit " << limit;
      }
    }
  }
  fs::remove_all(d.parent_path());
}

TEST(Sdf, CachedBakeIsReusedAndIdentical) {
  const fs::path d = tempDir() / "cache";
  fs::remove_all(d);
  const TriangleMesh s = sphereMesh(0.1f, 3);
  SdfBakeOptions opt;
  opt.voxel_size = 0.005f;
  opt.cache_dir = d.string();
  bool cached = true;
  const auto a = GridSdfBody::bake(s, opt, &cached);
  EXPECT_FALSE(cached);
  const auto b = GridSdfBody::bake(s, opt, &cached);
  EXPECT_TRUE(cached);
  for (float x = -0.15f; x < 0.15f; x += 0.0137f) {
    const glm::vec3 p(x, 0.3f * x, 0.01f);
    float pa, pb;
    glm::vec3 na, nb;
    a->signedDistance(&p, 1, &pa, &na);
    b->signedDistance(&p, 1, &pb, &nb);
    EXPECT_EQ(pa, pb);
  }
  // A different mesh does not hit the same cache entry.
  const auto c = GridSdfBody::bake(sphereMesh(0.11f, 3), opt, &cached);
  EXPECT_FALSE(cached);
  fs::remove_all(d.parent_path());
}
