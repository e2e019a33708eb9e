// Scalp and initial hair state (method.md §6.1): the harmonic map of a trimmed
// scalp, f^-1, Poisson-disc sampling in (u, v, s), cantilever strands and
// hair-length maps.
#include "init/cantilever.hpp"
#include "init/length_map.hpp"
#include "init/mesh_scalp.hpp"
#include "init/poisson_pillar.hpp"
#include "mesh/nearest_triangle.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <filesystem>
#include <fstream>
#include <numbers>

using namespace loosehair;
namespace fs = std::filesystem;

namespace {

// A flat box ("pillbox"): a fine grid on top (y = height) over [-a, a]^2,
// the same underneath and a strip of tall quads around the rim.
TriangleMesh pillbox(float a, float height, int n) {
  TriangleMesh m;
  auto index = [n](int layer, int i, int j) {
    return static_cast<unsigned>(layer * (n + 1) * (n + 1) + j * (n + 1) + i);
  };
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        m.vertices.emplace_back(-a + 2 * a * i / n, layer == 0 ? height : 0.0f, -a + 2 * a * j / n);
  const glm::vec3 centre(0, 0.5f * height, 0);
  auto add = [&](unsigned p, unsigned q, unsigned r) {
    const glm::vec3 nrm = glm::cross(m.vertices[q] - m.vertices[p], m.vertices[r] - m.vertices[p]);
    const glm::vec3 mid = (m.vertices[p] + m.vertices[q] + m.vertices[r]) / 3.0f;
    if (glm::dot(nrm, mid - centre) > 0)
      m.triangles.emplace_back(p, q, r);
    else
      m.triangles.emplace_back(p, r, q);
  };
  for (int layer = 0; layer < 2; ++layer)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        add(index(layer, i, j), index(layer, i, j + 1), index(layer, i + 1, j));
        add(index(layer, i + 1, j), index(layer, i, j + 1), index(layer, i + 1, j + 1));
      }
  std::vector<std::pair<int, int>> rim;
  for (int i = 0; i < n; ++i) rim.emplace_back(i, 0);
  for (int j = 0; j < n; ++j) rim.emplace_back(n, j);
  for (int i = n; i > 0; --i) rim.emplace_back(i, n);
  for (int j = n; j > 0; --j) rim.emplace_back(0, j);
  for (std::size_t k = 0; k < rim.size(); ++k) {
    const auto [i0, j0] = rim[k];
    const auto [i1, j1] = rim[(k + 1) % rim.size()];
    add(index(0, i0, j0), index(1, i0, j0), index(1, i1, j1));
    add(index(0, i0, j0), index(1, i1, j1), index(0, i1, j1));
  }
  return m;
}

struct BundledHead {
  TriangleMesh mesh;
  std::shared_ptr<GridSdfBody> sdf;
  BundledHead() {
    mesh = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
    SdfBakeOptions opt;
    opt.cache_dir = GridSdfBody::defaultCacheDir();
    sdf = GridSdfBody::bake(mesh, opt);
  }
};

const BundledHead& bundledHead() {
  static const BundledHead head;
  return head;
}

void checkMapIsAnEmbedding(const MeshScalp& scalp) {
  const auto& uv = scalp.uvs();
  for (const auto& t : scalp.triangles()) {
    const glm::vec2 a = uv[t.x], b = uv[t.y], c = uv[t.z];
    ASSERT_GT((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x), 0.0f) << "a triangle flips";
  }
  for (const auto& p : uv) {
    ASSERT_GE(p.x, -1e-6f);
    ASSERT_LE(p.x, 1.0f + 1e-6f);
    ASSERT_GE(p.y, -1e-6f);
    ASSERT_LE(p.y, 1.0f + 1e-6f);
  }
  int corners = 0;
  for (std::uint32_t b : scalp.boundary()) {
    const glm::vec2 p = uv[b];
    const float to_side = std::min({p.x, 1 - p.x, p.y, 1 - p.y});
    EXPECT_NEAR(to_side, 0.0f, 1e-5f) << "boundary vertex inside the square";
    corners += (std::min(p.x, 1 - p.x) < 1e-6f && std::min(p.y, 1 - p.y) < 1e-6f) ? 1 : 0;
  }
  EXPECT_EQ(corners, 4);
}

}  // namespace

TEST(Scalp, FlatSquarePatchMapsToItselfUpToScale) {
  const float a = 0.05f, h = 0.02f;
  const TriangleMesh box = pillbox(a, h, 24);
  SdfBakeOptions opt;
  opt.voxel_size = 0.001f;
  const auto sdf = GridSdfBody::bake(box, opt);
  ScalpCurves c;
  const glm::vec3 fl(-a, h, a), fr(a, h, a), br(a, h, -a), bl(-a, h, -a);
  c.control[0] = {fl, 0.5f * (fl + fr), fr};
  c.control[1] = {fr, 0.5f * (fr + br), br};
  c.control[2] = {br, 0.5f * (br + bl), bl};
  c.control[3] = {bl, 0.5f * (bl + fl), fl};
  const MeshScalp scalp(box, *sdf, c, "pillbox");
  checkMapIsAnEmbedding(scalp);
  EXPECT_NEAR(scalp.area(), 4 * a * a, 1e-6);
  float worst = 0;
  for (std::size_t k = 0; k < scalp.positions().size(); ++k) {
    const glm::vec3 p = scalp.positions()[k];
    EXPECT_NEAR(p.y, h, 1e-6f) << "only the top face is scalp";
    const glm::vec2 expected((p.x + a) / (2 * a), (a - p.z) / (2 * a));
    worst = std::max(worst, glm::length(scalp.uvs()[k] - expected));
  }
  EXPECT_LT(worst, 1e-4f) << "the harmonic map of a flat square is the identity up to scale";
  // f^-1 is its inverse
  for (float u = 0.05f; u < 1; u += 0.1f)
    for (float v = 0.05f; v < 1; v += 0.13f) {
      const glm::vec3 p = scalp.point({u, v});
      EXPECT_NEAR(p.x, -a + 2 * a * u, 1e-5f);
      EXPECT_NEAR(p.z, a - 2 * a * v, 1e-5f);
      EXPECT_GT(scalp.normal({u, v}).y, 0.999f);
    }
}

TEST(Scalp, BundledHeadAutomaticScalp) {
  const auto& head = bundledHead();
  const MeshScalp scalp(head.mesh, *head.sdf, automaticScalpCurves(head.mesh, *head.sdf), "head");
  EXPECT_EQ(scalp.report().flipped, 0u);
  EXPECT_FALSE(scalp.report().mean_value_weights) << "cotangent weights suffice on the bundled head";
  checkMapIsAnEmbedding(scalp);
  EXPECT_GT(scalp.area(), 0.03);
  EXPECT_LT(scalp.area(), 0.08);
  // f^-1 reproduces the vertices and lands on the head.
  for (std::size_t k = 0; k < scalp.positions().size(); k += 97)
    EXPECT_LT(glm::length(scalp.point(scalp.uvs()[k]) - scalp.positions()[k]), 1e-4f);
  for (float u = 0.02f; u < 1; u += 0.12f)
    for (float v = 0.03f; v < 1; v += 0.12f) {
      const glm::vec3 p = scalp.point({u, v});
      float phi;
      glm::vec3 n;
      head.sdf->signedDistance(&p, 1, &phi, &n);
      EXPECT_LT(std::abs(phi), 1e-3f) << u << " " << v;
      EXPECT_GT(glm::dot(scalp.normal({u, v}), n), 0.8f) << "scalp normals point out of the head";
    }
  // Orientation of the square: v from the forehead to the nape, u from the
  // left temple to the right; the crown in the middle points up.
  EXPECT_GT(scalp.point({0.5f, 0.0f}).z, 0.04f);
  EXPECT_LT(scalp.point({0.5f, 1.0f}).z, -0.05f);
  EXPECT_LT(scalp.point({0.5f, 1.0f}).y, scalp.point({0.5f, 0.0f}).y) << "the nape is below the hairline";
  EXPECT_LT(scalp.point({0.0f, 0.5f}).x, -0.05f);
  EXPECT_GT(scalp.point({1.0f, 0.5f}).x, 0.05f);
  EXPECT_GT(scalp.normal({0.5f, 0.4f}).y, 0.7f);
  // The hairline stays above the eyes (y ~ 0.016) at the front.
  EXPECT_GT(scalp.point({0.5f, 0.0f}).y, 0.06f);
}

TEST(Scalp, AutomaticScalpOnOtherHeads) {
  const fs::path dir = fs::temp_directory_path() / ("loosehair-scalp-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // The bundled head written as another tool would: Z up, facing -Y, in cm.
  {
    const TriangleMesh& h = bundledHead().mesh;
    TriangleMesh t = h;
    for (auto& v : t.vertices) v = 100.0f * glm::vec3(v.x, -v.z, v.y) * 1.15f;
    writeObj(t, (dir / "zup.obj").string());
  }
  MeshLoadOptions opt;
  opt.scale = 0.01f;
  opt.up = Axis::PosZ;
  opt.front = Axis::NegY;
  const TriangleMesh zup = loadMesh((dir / "zup.obj").string(), opt);
  // And a bald egg without a neck.
  TriangleMesh egg = loadMesh(lhtest::sourceDir() + "/data/meshes/head.ply");
  for (auto& v : egg.vertices) {
    const float r = glm::length(v);
    v = glm::vec3(0.08f, 0.1f, 0.095f) * (v / std::max(r, 1e-6f));
  }
  for (const TriangleMesh* m : std::initializer_list<const TriangleMesh*>{&zup, &egg}) {
    SdfBakeOptions so;
    so.voxel_size = 0.003f;
    const auto sdf = GridSdfBody::bake(*m, so);
    const MeshScalp scalp(*m, *sdf, automaticScalpCurves(*m, *sdf), "other head");
    checkMapIsAnEmbedding(scalp);
    EXPECT_GT(scalp.area(), 0.02);
    EXPECT_GT(scalp.normal({0.5f, 0.4f}).y, 0.6f) << "the scalp is on top";
    EXPECT_GT(scalp.point({0.5f, 0.0f}).z, scalp.point({0.5f, 1.0f}).z) << "front before back";
  }
  fs::remove_all(dir);
}

TEST(Scalp, CurvesThatDoNotMeetAreRejected) {
  const auto& head = bundledHead();
  ScalpCurves c = automaticScalpCurves(head.mesh, *head.sdf);
  c.control[1].front() += glm::vec3(0, 0.1f, 0);  // right curve starts far from where front ends
  try {
    MeshScalp scalp(head.mesh, *head.sdf, c, "head.obj");
    ADD_FAILURE() << "accepted curves that do not meet";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("must meet"), std::string::npos) << e.what();
  }
}

TEST(Poisson, SamplesKeepTheRadiusInTheWorldMetricAndHitTheCount) {
  const auto& head = bundledHead();
  const MeshScalp scalp(head.mesh, *head.sdf, automaticScalpCurves(head.mesh, *head.sdf), "head");
  const LengthMap map(lhtest::sourceDir() + "/data/maps/hair_length.png");
  auto length = [&](glm::vec2 uv) { return 0.3f * std::max(map(uv), 0.02f); };
  for (int target : {2000, 6000}) {
    PillarOptions opt;
    opt.target_count = target;
    opt.seed = 11;
    const PillarResult r = samplePillar(scalp, length, 0.3f * map.maximum(), opt);
    const auto n = static_cast<double>(r.samples.size());
    EXPECT_NEAR(n / target, 1.0, 0.05) << "count within 5% of " << target;
    float closest = INFINITY;
    for (std::size_t i = 0; i < r.samples.size(); ++i) {
      const auto& a = r.samples[i];
      EXPECT_LE(a.s, length(a.uv) + 1e-6f) << "no sample beyond its hair's length";
      EXPECT_GE(a.s, -r.root_depth - 1e-6f);
      EXPECT_LT(glm::length(scalp.point(a.uv) - a.point), 1e-5f);
      for (std::size_t j = i + 1; j < r.samples.size(); ++j) {
        const auto& b = r.samples[j];
        const glm::vec3 d = a.point - b.point;
        const float ds = a.s - b.s;
        closest = std::min(closest, std::sqrt(glm::dot(d, d) + ds * ds));
      }
    }
    EXPECT_GE(closest, r.radius * (1 - 1e-5f)) << "two samples closer than the Poisson radius";
    // Deterministic for a seed.
    const PillarResult again = samplePillar(scalp, length, 0.3f * map.maximum(), opt);
    ASSERT_EQ(again.samples.size(), r.samples.size());
    for (std::size_t i = 0; i < r.samples.size(); i += 101) EXPECT_EQ(again.samples[i].s, r.samples[i].s);
  }
}

TEST(Cantilever, LongerOrSofterHairHangsLower) {
  const glm::vec3 root(0, 0, 0), out(1, 0, 0), down(0, -1, 0);
  auto tipY = [&](float length, float stiffness) {
    const CantileverStrand s(root, out, down, length, stiffness, nullptr, 0, 0, 64);
    return s.position(length).y;
  };
  EXPECT_LT(tipY(0.30f, 5e-4f), tipY(0.15f, 5e-4f)) << "longer hangs lower";
  EXPECT_LT(tipY(0.20f, 1e-4f), tipY(0.20f, 1e-3f)) << "softer hangs lower";
  EXPECT_LT(tipY(0.20f, 1e-4f) / 0.20f, tipY(0.20f, 1e-3f) / 0.20f);
  // The strand is one smooth curve parameterised by arc length: positions
  // at nearby s are |ds| apart, the tangent is the derivative and turns by
  // small angles only.
  const float length = 0.25f;
  const CantileverStrand s(root, glm::normalize(glm::vec3(1, 0.3f, 0.2f)), down, length, 2e-3f, nullptr, 0, 0, 200);
  glm::vec3 prev_t = s.tangent(0);
  for (float a = 0.002f; a < length - 0.004f; a += 0.0025f) {
    const float ds = 0.001f;
    const glm::vec3 d = s.position(a + ds) - s.position(a);
    EXPECT_NEAR(glm::length(d), ds, 1e-5f);
    const glm::vec3 t = s.tangent(a + 0.5f * ds);
    EXPECT_GT(glm::dot(glm::normalize(d), t), 0.998f);
    EXPECT_GT(glm::dot(prev_t, t), std::cos(0.1f)) << "the tangent jumps at s = " << a;
    prev_t = t;
  }
  EXPECT_LT(s.tangent(length).y, -0.5f) << "the tip points down";
}

TEST(Cantilever, StrandsStayOutOfTheBody) {
  const SphereBody head(glm::vec3(0), 0.1f);
  // Rooted on top, leaving sideways: the strand must wrap around the sphere.
  const CantileverStrand s(glm::vec3(0, 0.1f, 0), glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), 0.3f, 2e-4f, &head, 0.002f,
                           0.0f, 120);
  for (float a = 0.005f; a <= 0.3f; a += 0.005f) EXPECT_GE(glm::length(s.position(a)), 0.1f + 0.0015f) << a;
}

// The initial shape is a curve of the hair, not of how finely it is cut: a
// strand leaving the crown of a sphere upwards-sideways ends where it ends
// with 128 pieces or 2048, and none of it stands up. (With the clearance
// demanded from the first piece, pieces shorter than it were pushed out
// along the normal: 1024 pieces stood straight up, 0.27 m off a 0.1 m
// sphere; the standing crowns of the 50k-100k particle heads.)
TEST(Cantilever, TheShapeDoesNotDependOnThePieces) {
  const SphereBody head(glm::vec3(0), 0.1f);
  const glm::vec3 root(0, 0.1f, 0), dir = glm::normalize(glm::vec3(0.18f, 0.6f, 0.78f)), down(0, -1, 0);
  const float length = 0.17f;
  auto strand = [&](int pieces) {
    return CantileverStrand(root, dir, down, length, 5e-4f, &head, 0.002f, 0.2f, pieces);
  };
  const CantileverStrand coarse = strand(128), fine = strand(2048);
  EXPECT_LT(glm::length(coarse.position(length) - fine.position(length)), 0.01f);
  for (const CantileverStrand* s : {&coarse, &fine}) {
    float top = -1;
    for (float a = 0; a <= length; a += 0.001f) top = std::max(top, s->position(a).y);
    EXPECT_LT(top, 0.13f) << "the strand stands up off the crown";
    for (float a = 0.01f; a <= length; a += 0.005f)
      EXPECT_GE(glm::length(s->position(a)), 0.1f + 0.0015f) << "inside the sphere at s = " << a;
  }
}

// A particle's strand is grown only as far as the particle (the scene's
// initial state; growCantilever): the pieces before s do not depend on the
// ones after, so the point and tangent there are the whole strand's, bit
// for bit, wherever s falls among the pieces, and fewer pieces are grown.
TEST(Cantilever, AStrandGrownToAParticleAgreesWithTheWholeStrand) {
  const SphereBody head(glm::vec3(0), 0.1f);
  const glm::vec3 root(0, 0.1f, 0), dir = glm::normalize(glm::vec3(0.18f, 0.6f, 0.78f)), down(0, -1, 0);
  const float length = 0.17f;
  const int pieces = 97;
  const CantileverStrand whole(root, dir, down, length, 5e-4f, &head, 0.002f, 0.2f, pieces);
  ASSERT_EQ(whole.points().size(), static_cast<std::size_t>(pieces) + 1);
  const float ds = length / pieces;
  for (float s : {0.0f, 0.5f * ds, ds, 1.5f * ds, 0.0423f, 40 * ds, 0.1f, length - 2.5f * ds, length - ds,
                  length - 0.1f * ds, length}) {
    const CantileverStrand part(root, dir, down, length, 5e-4f, &head, 0.002f, 0.2f, pieces, s);
    EXPECT_LE(part.points().size(), whole.points().size());
    if (s < length - 4 * ds) {
      EXPECT_LT(part.points().size(), whole.points().size()) << s;
    }
    const glm::vec3 a = part.position(s), b = whole.position(s), ta = part.tangent(s), tb = whole.tangent(s);
    EXPECT_EQ(a.x, b.x) << s;
    EXPECT_EQ(a.y, b.y) << s;
    EXPECT_EQ(a.z, b.z) << s;
    EXPECT_EQ(ta.x, tb.x) << s;
    EXPECT_EQ(ta.y, tb.y) << s;
    EXPECT_EQ(ta.z, tb.z) << s;
  }
}

TEST(LengthMap, PngAndPgmGiveTheSameLengths) {
  const fs::path dir = fs::temp_directory_path() / ("loosehair-map-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // 4 x 2 ramp: row 0 (v = 0, the front) dark, row 1 light.
  const unsigned char px[8] = {0, 85, 170, 255, 255, 255, 255, 255};
  ASSERT_TRUE(stbi_write_png((dir / "m.png").c_str(), 4, 2, 1, px, 4));
  {
    std::ofstream p5(dir / "m.pgm", std::ios::binary);
    p5 << "P5\n4 2\n255\n";
    p5.write(reinterpret_cast<const char*>(px), 8);
    std::ofstream p2(dir / "m2.pgm");
    p2 << "P2\n# plain\n4 2\n255\n0 85 170 255\n255 255 255 255\n";
  }
  for (const char* name : {"m.png", "m.pgm", "m2.pgm"}) {
    const LengthMap m((dir / name).string());
    EXPECT_EQ(m.width(), 4);
    EXPECT_EQ(m.height(), 2);
    EXPECT_NEAR(m({0.125f, 0.25f}), 0.0f, 1e-6f) << name;  // pixel centres
    EXPECT_NEAR(m({0.375f, 0.25f}), 1.0f / 3.0f, 1e-6f) << name;
    EXPECT_NEAR(m({0.25f, 0.25f}), 1.0f / 6.0f, 1e-6f) << name << ": bilinear between pixels";
    EXPECT_NEAR(m({0.125f, 0.75f}), 1.0f, 1e-6f) << name;
    EXPECT_NEAR(m.maximum(), 1.0f, 1e-6f);
  }
  EXPECT_THROW(LengthMap((dir / "none.png").string()), std::runtime_error);
  std::ofstream(dir / "bad.pgm") << "P2\n4 2\n255\n0 1 2\n";
  EXPECT_THROW(LengthMap((dir / "bad.pgm").string()), std::runtime_error);
  fs::remove_all(dir);
}

// The nearest-triangle search (nearestScalpUv, groom import) answers what
// trying every triangle answers, bit for bit, near the surface and far from
// it, with repeated triangles (ties) in the soup.
TEST(NearestTriangle, AgreesWithTryingEveryTriangle) {
  std::vector<glm::vec3> pos;
  std::vector<glm::u32vec3> tris;
  std::uint64_t state = 12345;
  auto uniform = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<float>(state >> 40) / static_cast<float>(1u << 24);
  };
  const int g = 40;  // a wavy sheet, 20 cm square, jittered
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j) {
      const float x = 0.2f * static_cast<float>(j) / g + 0.002f * uniform();
      const float z = 0.2f * static_cast<float>(i) / g + 0.002f * uniform();
      pos.emplace_back(x, 0.02f * std::sin(30.0f * x) * std::cos(20.0f * z), z);
    }
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const auto a = static_cast<std::uint32_t>(i * (g + 1) + j);
      tris.emplace_back(a, a + 1, a + g + 2);
      tris.emplace_back(a, a + g + 2, a + g + 1);
    }
  tris.push_back(tris[100]);  // a repeat: the lower id must win
  const NearestTriangle search(pos, tris);
  for (int q = 0; q < 3000; ++q) {
    const float spread = q % 3 == 0 ? 2.0f : 0.25f;  // far and near
    const glm::vec3 p(spread * (uniform() - 0.4f), spread * (uniform() - 0.5f), spread * (uniform() - 0.4f));
    NearestTriangle::Hit brute;
    for (std::uint32_t k = 0; k < tris.size(); ++k) {
      const glm::vec3 a = pos[tris[k].x], b = pos[tris[k].y], c = pos[tris[k].z];
      const glm::vec3 l = closestBarycentric(p, a, b, c);
      const float d = glm::length(l.x * a + l.y * b + l.z * c - p);
      if (d < brute.distance) brute = {k, l, d};
    }
    const NearestTriangle::Hit hit = search.nearest(p);
    ASSERT_EQ(hit.triangle, brute.triangle) << "query " << q;
    ASSERT_EQ(hit.distance, brute.distance) << "query " << q;
  }
  EXPECT_FALSE(std::isfinite(NearestTriangle({}, {}).nearest(glm::vec3(0.0f)).distance));
}
