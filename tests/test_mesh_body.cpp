// Exact distances to a closed mesh (method.md §5 body collisions): MeshBody
// against brute force over every triangle, signed by the generalised winding
// number (an independent inside test), on meshes where a coarse grid is far
// off (a box's sharp edges, a bumpy sphere's creases); and a solver that
// keeps hair outside the real triangles although its grid is coarse.
#include "test_support.hpp"

#include "mesh/exact_distance.hpp"
#include "mesh/grid_value_bounds.hpp"
#include "util/random.hpp"
#include "mesh/triangle_cells.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

using namespace loosehair;

namespace {

// A sphere from a subdivided octahedron, its radius bumped by `bump`
// (relative) so that it has concave creases.
TriangleMesh bumpySphere(float radius, int levels, float bump) {
  TriangleMesh m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back(glm::normalize(m.vertices[a] + m.vertices[b]));
      return mid[key] = static_cast<std::uint32_t>(m.vertices.size() - 1);
    };
    std::vector<glm::u32vec3> next;
    for (const auto& t : m.triangles) {
      const std::uint32_t ab = middle(t.x, t.y), bc = middle(t.y, t.z), ca = middle(t.z, t.x);
      next.push_back({t.x, ab, ca});
      next.push_back({ab, t.y, bc});
      next.push_back({ca, bc, t.z});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  for (auto& v : m.vertices) {
    const float theta = std::acos(std::clamp(v.y, -1.0f, 1.0f)), phi = std::atan2(v.z, v.x);
    v *= radius * (1.0f + bump * std::sin(5.0f * theta) * std::sin(4.0f * phi));
  }
  return m;
}

// A box: 6 faces of 2 triangles, counter-clockwise from outside.
TriangleMesh box(glm::vec3 lo, glm::vec3 hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  // Inside the prism over the triangle: the plane's distance; else the edges'.
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const glm::dvec3 q = p - glm::dot(p - a, n) * n;
  const bool in = glm::dot(glm::cross(b - a, q - a), n) >= 0 && glm::dot(glm::cross(c - b, q - b), n) >= 0 &&
                  glm::dot(glm::cross(a - c, q - c), n) >= 0;
  if (in) return std::abs(glm::dot(p - a, n));
  auto segment = [&](const glm::dvec3& u, const glm::dvec3& v) {
    const double t = std::clamp(glm::dot(p - u, v - u) / glm::dot(v - u, v - u), 0.0, 1.0);
    return glm::length(p - (u + t * (v - u)));
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// Brute force: the unsigned distance to the nearest triangle, and the sign
// from the winding number (the solid angle the mesh subtends over 4 pi).
double exactSignedDistance(const TriangleMesh& m, glm::vec3 pf) {
  const glm::dvec3 p(pf);
  double d = INFINITY, omega = 0;
  for (const auto& t : m.triangles) {
    const glm::dvec3 a(m.vertices[t.x]), b(m.vertices[t.y]), c(m.vertices[t.z]);
    d = std::min(d, pointTriangleDistance(p, a, b, c));
    const glm::dvec3 x = a - p, y = b - p, z = c - p;
    const double lx = glm::length(x), ly = glm::length(y), lz = glm::length(z);
    omega += 2.0 * std::atan2(glm::dot(x, glm::cross(y, z)),
                              lx * ly * lz + glm::dot(x, y) * lz + glm::dot(x, z) * ly + glm::dot(y, z) * lx);
  }
  const bool inside = omega / (4.0 * std::numbers::pi) > 0.5;
  return inside ? -d : d;
}

// `m` checked (as a loaded mesh would be), baked on a grid of `voxel`, as
// a mesh body.
struct BakedBody {
  MeshReport report;
  std::shared_ptr<GridSdfBody> grid;
  std::shared_ptr<MeshBody> body;
};
BakedBody meshBody(TriangleMesh& m, float voxel, const char* name = "test mesh") {
  BakedBody t;
  t.report = checkMesh(m, name);
  SdfBakeOptions opt;
  opt.voxel_size = voxel;
  t.grid = GridSdfBody::bake(m, opt);
  t.body = std::make_shared<MeshBody>(m, t.grid);
  return t;
}

struct Comparison {
  double worst_exact = 0, worst_grid = 0;
  int sign_errors = 0, points = 0;
};

Comparison compare(const TriangleMesh& mesh, float voxel, float spread, std::uint32_t seed) {
  TriangleMesh m = mesh;
  const BakedBody t = meshBody(m, voxel);
  const auto& grid = t.grid;
  const MeshBody& body = *t.body;
  // points near the surface: vertices and face centres pushed along random
  // directions by up to `spread`
  std::vector<glm::vec3> p;
  std::uint32_t h = seed;
  auto uniform = [&] {
    h = h * 1664525u + 1013904223u;
    return static_cast<float>(h >> 8) / 16777216.0f;
  };
  for (std::size_t t = 0; p.size() < 3000; t = (t + 1) % m.triangles.size()) {
    const glm::vec3 c = (m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)) / 3.0f;
    for (const glm::vec3 base : {c, m.corner(t, 0)}) {
      const glm::vec3 dir = glm::normalize(glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f) + 1e-3f);
      p.push_back(base + spread * (2.0f * uniform() - 1.0f) * dir);
    }
  }
  std::vector<float> phi(p.size()), gphi(p.size());
  std::vector<glm::vec3> nrm(p.size()), gn(p.size());
  body.signedDistance(p.data(), p.size(), phi.data(), nrm.data());
  grid->signedDistance(p.data(), p.size(), gphi.data(), gn.data());
  Comparison c;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double e = exactSignedDistance(m, p[k]);
    ++c.points;
    c.worst_exact = std::max(c.worst_exact, std::abs(phi[k] - e));
    c.worst_grid = std::max(c.worst_grid, std::abs(gphi[k] - e));
    if (std::abs(e) > 1e-6 && (phi[k] < 0) != (e < 0)) ++c.sign_errors;
    // the normal points out of the body, away from the nearest point
    if (std::abs(e) > 1e-5) {
      const float len = glm::length(nrm[k]);
      EXPECT_NEAR(len, 1.0f, 1e-4f);
    }
  }
  return c;
}

}  // namespace

TEST(MeshBody, ExactDistanceOnSharpEdgesAndCreases) {
  struct Case {
    const char* name;
    TriangleMesh mesh;
    float voxel, spread;
  };
  const Case cases[] = {
      {"box", box(glm::vec3(-0.1f, -0.08f, -0.06f), glm::vec3(0.1f, 0.08f, 0.06f)), 0.012f, 0.02f},
      {"bumpy sphere", bumpySphere(0.1f, 4, 0.12f), 0.01f, 0.015f},
  };
  for (const Case& c : cases) {
    const Comparison r = compare(c.mesh, c.voxel, c.spread, 7);
    std::printf("%s: %d points, worst error exact %.2e m, grid %.2e m, %d sign errors\n", c.name, r.points,
                r.worst_exact, r.worst_grid, r.sign_errors);
    EXPECT_LT(r.worst_exact, 2e-6) << c.name;
    EXPECT_EQ(r.sign_errors, 0) << c.name;
    // the grid alone is visibly off on these meshes: the test measures something
    EXPECT_GT(r.worst_grid, 50 * std::max(r.worst_exact, 1e-7)) << c.name;
  }
}

TEST(MeshBody, BelowALimitIsExactOrABound) {
  TriangleMesh m = bumpySphere(0.1f, 3, 0.1f);
  const BakedBody t = meshBody(m, 0.01f);
  const MeshBody& body = *t.body;
  std::vector<glm::vec3> p;
  for (int k = 0; k < 400; ++k) {
    const float a = 0.137f * static_cast<float>(k), b = 0.071f * static_cast<float>(k);
    const float r = 0.08f + 0.05f * static_cast<float>(k % 41) / 40.0f;
    p.emplace_back(r * std::cos(a) * std::sin(b + 0.3f), r * std::cos(b + 0.3f), r * std::sin(a) * std::sin(b + 0.3f));
  }
  for (float limit : {0.0f, 0.002f, 0.01f}) {
    std::vector<float> phi(p.size());
    std::vector<glm::vec3> nrm(p.size());
    body.signedDistanceBelow(p.data(), p.size(), limit, phi.data(), nrm.data());
    for (std::size_t k = 0; k < p.size(); ++k) {
      const double e = exactSignedDistance(m, p[k]);
      if (e < limit - 1e-6) {
        EXPECT_NEAR(phi[k], e, 2e-6) << "limit " << limit << " point " << k;
      } else {
        EXPECT_GE(phi[k], limit) << "limit " << limit << " point " << k;
        EXPECT_LE(phi[k], e + 2e-6) << "a lower bound, limit " << limit << " point " << k;
      }
    }
  }
}

// A coarse grid (1 cm voxels on a head-sized bumpy sphere) cuts corners by
// millimetres; the hair must still end every step outside the triangles.
TEST(MeshBody, HairStaysOutsideTheExactSurface) {
  TriangleMesh m = bumpySphere(0.1f, 3, 0.06f);
  const BakedBody baked = meshBody(m, 0.01f);
  const auto& grid = baked.grid;
  const auto& body = baked.body;
  SceneDesc scene = lhtest::sphereScene(800);
  Solver solver = buildSolver(scene);
  // the same hair on the bumpy head: roots projected onto its surface
  Particles hair = solver.particles();
  std::vector<float> phi(hair.size());
  std::vector<glm::vec3> nrm(hair.size());
  Solver bumpy(solver.params(), hair, body);
  double deepest = 1;
  for (int s = 0; s < 100; ++s) {
    bumpy.step();
    const auto& p = bumpy.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.is_root[i]) continue;
      ASSERT_TRUE(std::isfinite(p.position[i].x));
      // brute force on the particles near the surface only (the rest are
      // certainly outside by more than the grid's error)
      float g;
      glm::vec3 gn;
      grid->signedDistance(&p.position[i], 1, &g, &gn);
      if (g > 3.0f * grid->voxelSize()) continue;
      deepest = std::min(deepest, exactSignedDistance(m, p.position[i]));
    }
  }
  std::printf("deepest particle against the exact surface: %.2e m\n", deepest);
  EXPECT_GE(deepest, -2e-6) << "a particle ended a step inside the real triangles";
}

// Body::roughError: what the solver may subtract from a rough answer to get
// a lower bound of the exact distance. Analytic bodies are exact; a mesh
// body's grid is off by up to its error, and its rough answers must keep
// within it; a bare grid (trilinear, up to sqrt 3-Lipschitz) and a union
// with one have no such bound.
TEST(MeshBody, RoughErrorBoundsTheRoughAnswers) {
  TriangleMesh m = bumpySphere(0.1f, 3, 0.06f);
  const BakedBody baked = meshBody(m, 0.01f);
  const auto& grid = baked.grid;
  const auto& body = baked.body;
  EXPECT_FLOAT_EQ(body->roughError(), body->gridError());
  EXPECT_EQ(SphereBody(glm::vec3(0.0f), 0.1f).roughError(), 0.0f);
  EXPECT_LT(grid->roughError(), 0.0f);
  UnionBody analytic;
  analytic.add(std::make_shared<SphereBody>(glm::vec3(0.0f), 0.1f));
  analytic.add(std::make_shared<CapsuleBody>(glm::vec3(0.0f), glm::vec3(0.1f, 0.0f, 0.0f), 0.02f));
  EXPECT_EQ(analytic.roughError(), 0.0f);
  UnionBody with_mesh = analytic;
  with_mesh.add(body);
  EXPECT_FLOAT_EQ(with_mesh.roughError(), body->gridError());
  with_mesh.add(grid);
  EXPECT_LT(with_mesh.roughError(), 0.0f);
  // the rough answers lie at most the error above the exact distance
  Random rng(7);
  auto r = [&] { return static_cast<float>(rng.uniform(-0.14, 0.14)); };
  double worst = -1;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 p(r(), r(), r());
    float rough;
    glm::vec3 n;
    body->roughDistanceBelow(&p, 1, INFINITY, &rough, &n);
    worst = std::max(worst, static_cast<double>(rough) - exactSignedDistance(m, p));
  }
  std::printf("rough minus exact: at most %.2e m (error %.2e m)\n", worst, static_cast<double>(body->roughError()));
  EXPECT_LE(worst, static_cast<double>(body->roughError()));
}

// A world body that moves between a step's start and its end: a bumpy
// ball swept along the hanging back hair at 3 m/s (33 mm a step). The
// projection skips the particles integrate() proved clear of every body at
// the step's start; that proof has to count the body's move, or the hair
// the ball reached in the step is left inside it.
TEST(MeshBody, HairStaysOutOfAWorldBodyMovingThroughIt) {
  TriangleMesh m = bumpySphere(0.05f, 3, 0.06f);
  const auto ball = meshBody(m, 0.008f, "test ball").body;
  Solver solver = buildSolver(lhtest::sphereScene(800));
  const HeadTrajectory sweep = HeadTrajectory::keyframes(
      {{1.0, glm::dvec3(0.0), glm::dvec3(-0.3, -0.17, -0.09)}, {1.2, glm::dvec3(0.0), glm::dvec3(0.3, -0.17, -0.09)}});
  solver.addWorldBody(ball, sweep, 0.0, 10.0);
  double deepest = 1;
  int reached = 0;                // particles the ball pushed (within 1 mm of it)
  while (solver.time() < 1.25) {  // the hair hangs first; the sweep is 1.0-1.2 s
    solver.step();
    const HeadPose pose = sweep.pose(solver.time());
    const auto& p = solver.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.is_root[i]) continue;
      ASSERT_TRUE(std::isfinite(p.position[i].x));
      const glm::vec3 local(glm::transpose(pose.rotation) * (glm::dvec3(p.position[i]) - pose.center));
      if (glm::length(local) > 0.07f) continue;  // the bumps reach 0.053 m
      const double d = exactSignedDistance(m, local);
      deepest = std::min(deepest, d);
      if (d < 1e-3) ++reached;
    }
  }
  std::printf("deepest particle against the moving ball: %.2e m; %d particle-steps in contact\n", deepest, reached);
  ASSERT_GT(reached, 30) << "the ball should sweep through the hair";
  EXPECT_GE(deepest, -2e-6) << "a particle ended a step inside the moving ball";
}

// A closed eyeball set half into a closed head (two overlapping parts): the
// body is their union. Every point near either surface gets the sign of the
// generalised winding number of the whole mesh (inside if >= 1/2), which the
// pseudo-normal of the nearest triangle alone would get wrong inside one
// part near the other's surface.
TEST(MeshBody, OverlappingClosedPartsActAsTheirUnion) {
  TriangleMesh m = bumpySphere(0.1f, 3, 0.0f);
  const TriangleMesh eye = bumpySphere(0.025f, 2, 0.0f);
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  const glm::vec3 centre(0.0f, 0.0f, 0.1f);
  for (const auto& v : eye.vertices) m.vertices.push_back(v + centre);
  for (const auto& t : eye.triangles) m.triangles.push_back(t + glm::u32vec3(base));
  const BakedBody t = meshBody(m, 0.01f, "head with an eye");
  ASSERT_EQ(t.report.components, 2u);
  const MeshBody& body = *t.body;
  int wrong = 0, points = 0;
  for (int k = 0; k < 2000; ++k) {
    // around the eye's rim, where the two surfaces meet, and over it
    const float a = 0.0031f * static_cast<float>(k * 97 % 2000), b = 0.0057f * static_cast<float>(k * 31 % 1100);
    const float r = 0.015f + 0.02f * static_cast<float>(k % 37) / 36.0f;
    const glm::vec3 p = centre + r * glm::vec3(std::cos(a) * std::sin(b), std::cos(b), std::sin(a) * std::sin(b));
    float phi;
    glm::vec3 n;
    body.signedDistance(&p, 1, &phi, &n);
    const double e = exactSignedDistance(m, p);  // winding number sign
    if (std::abs(e) < 1e-5) continue;
    ++points;
    if ((phi < 0) != (e < 0)) ++wrong;
  }
  std::printf("%d points near an eyeball set into a head, %d with the wrong side\n", points, wrong);
  EXPECT_GT(points, 1500);
  EXPECT_EQ(wrong, 0);
}

// Two closed boxes, one reaching 2 cm into the other (a neck pushed into a
// bust), as their union of one body each (what a head mesh of separate
// parts becomes, head_model.cpp): inside the overlap, next to the faces of
// one box that lie inside the other, the distance is the union's, and one
// push along the normal brings a point out; hinted queries give the same
// bits as plain ones.
TEST(MeshBody, SeparatePartsAsAUnionPushOutOfTheWhole) {
  TriangleMesh a = box({-0.1f, -0.1f, -0.1f}, {0.1f, 0.0f, 0.1f});
  TriangleMesh b = box({-0.04f, -0.02f, -0.04f}, {0.04f, 0.2f, 0.04f});
  const BakedBody ba = meshBody(a, 0.005f, "chest"), bb = meshBody(b, 0.005f, "neck");
  UnionBody both;
  both.add(ba.body);
  both.add(bb.body);
  // the union's exact distance inside: to the nearest outer face
  auto inside = [](glm::vec3 p) {
    const bool in_a = p.y < 0.0f && std::abs(p.x) < 0.1f && std::abs(p.z) < 0.1f && p.y > -0.1f;
    const bool in_b = std::abs(p.x) < 0.04f && std::abs(p.z) < 0.04f && p.y > -0.02f && p.y < 0.2f;
    return in_a || in_b;
  };
  int points = 0, still_in = 0;
  std::vector<glm::vec3> q;
  for (int k = 0; k < 400; ++k) {
    // where hair meets them: 1-4 mm inside the neck's sides, within 4 mm
    // of the chest's top (inside the neck) above and below it
    const float along = -0.035f + 0.07f * static_cast<float>(k % 20) / 19.0f;
    const float depth = 0.001f + 0.003f * static_cast<float>(k / 20 % 4) / 3.0f;
    const float y = -0.004f + 0.008f * static_cast<float>(k / 80) / 4.0f;
    const float side = 0.04f - depth;
    const glm::vec3 around[4] = {{side, y, along}, {-side, y, along}, {along, y, side}, {along, y, -side}};
    q.push_back(around[k % 4]);
  }
  std::vector<float> phi(q.size()), phi_h(q.size());
  std::vector<glm::vec3> n(q.size()), n_h(q.size());
  both.signedDistanceBelow(q.data(), q.size(), 1.0f, phi.data(), n.data());  // exact below 1 m
  std::vector<std::int32_t> hint(q.size(), -1);
  for (int pass = 0; pass < 2; ++pass)  // the second pass with the first's hints
    both.signedDistanceBelowHinted(q.data(), q.size(), 1.0f, phi_h.data(), n_h.data(), hint.data());
  for (std::size_t k = 0; k < q.size(); ++k) {
    ASSERT_TRUE(inside(q[k]));
    ++points;
    // as deep as in the deeper box (not the ~0 of the chest's top it is next to)
    const glm::vec3 p = q[k];
    const float depth_a = std::min({0.1f - std::abs(p.x), 0.1f - std::abs(p.z), -p.y, p.y + 0.1f});
    const float depth_b = std::min({0.04f - std::abs(p.x), 0.04f - std::abs(p.z), p.y + 0.02f, 0.2f - p.y});
    EXPECT_NEAR(phi[k], -std::max(depth_a, depth_b), 2e-4f) << "at " << p.x << " " << p.y << " " << p.z;
    // pushed out of the deepest part, then out of the one that leaves it
    // in (the solver's rounds do as much)
    glm::vec3 out = q[k];
    for (int round = 0; round < 3; ++round) {
      float d;
      glm::vec3 dn;
      both.signedDistanceBelow(&out, 1, 1.0f, &d, &dn);
      if (d >= 0.0f) break;
      out -= (d - 1e-5f) * dn;
    }
    still_in += inside(out) ? 1 : 0;
    EXPECT_EQ(phi[k], phi_h[k]);
    EXPECT_EQ(n[k], n_h[k]);
  }
  std::printf("%d points where a neck enters a chest: %d still inside after the pushes\n", points, still_in);
  EXPECT_EQ(still_in, 0);
}

// The cells list every triangle whose (grown) box meets a query box within
// their reach: brute force over random triangles of mixed sizes, queries
// inside, at the edges of and outside the grid.
TEST(TriangleCells, ListEveryTriangleWhoseBoxMeetsTheQuery) {
  Random rng(11);
  std::vector<glm::vec3> corners;
  auto r = [&](double lo, double hi) { return static_cast<float>(rng.uniform(lo, hi)); };
  for (int t = 0; t < 600; ++t) {
    const glm::vec3 c(r(-0.1, 0.1), r(-0.05, 0.15), r(0.0, 0.08));
    const float size = t % 10 == 0 ? 0.03f : 0.004f;
    for (int k = 0; k < 3; ++k) corners.push_back(c + size * glm::vec3(r(-1, 1), r(-1, 1), r(-1, 1)));
  }
  const float margin = 1e-6f;
  TriangleCells cells;
  cells.build(corners, margin, 5000);
  ASSERT_GT(cells.reach(), 0.0f);
  std::vector<int> seen(600);
  for (int q = 0; q < 3000; ++q) {
    const glm::vec3 p(r(-0.15, 0.15), r(-0.1, 0.2), r(-0.05, 0.13));
    const float radius = cells.reach() * r(0.0, 1.0);
    std::fill(seen.begin(), seen.end(), 0);
    cells.forEachNear(p, radius, [&](std::uint32_t k) { ++seen[k]; });
    for (std::size_t t = 0; t < 600; ++t) {
      const glm::vec3 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
      const glm::vec3 lo = glm::min(a, glm::min(b, c)) - margin, hi = glm::max(a, glm::max(b, c)) + margin;
      const bool meets = glm::all(glm::lessThanEqual(lo, p + radius)) && glm::all(glm::lessThanEqual(p - radius, hi));
      if (meets) {
        ASSERT_GT(seen[t], 0) << "query " << q << " missed triangle " << t;
      }
    }
  }
}

// The exact distance answers a small ball from the cells and a large one
// from the hierarchy: the same triangle and the same bits either way. A
// seed at the true nearest triangle or beside it (a particle that slid
// onto the next triangle) makes the ball small (the cells); no seed leaves
// it infinite (the hierarchy alone).
TEST(MeshBody, CellsAndHierarchyGiveTheSameNearestTriangle) {
  TriangleMesh m = bumpySphere(0.1f, 4, 0.12f);
  checkMesh(m, "test mesh");
  const ExactDistance exact(m);
  Random rng(5);
  int compared = 0;
  for (int k = 0; k < 4000; ++k) {
    const std::size_t t = static_cast<std::size_t>(rng.next() % m.triangles.size());
    // on the surface, a hair's breadth to a few millimetres in or out, and
    // at vertices and edges, where neighbours tie
    const double u = rng.uniform(), v = rng.uniform() * (1.0 - u);
    const glm::vec3 a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    glm::vec3 p = k % 4 == 0 ? a
                             : (k % 4 == 1 ? 0.5f * (a + b)
                                           : a + static_cast<float>(u) * (b - a) + static_cast<float>(v) * (c - a));
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    p += static_cast<float>(rng.uniform(-1.0, 1.0) * (k % 3 == 0 ? 1e-6 : 3e-3)) * n;
    ExactDistance::Nearest whole{}, seeded{}, beside{};
    ASSERT_TRUE(exact.nearest(p, INFINITY, nullptr, 0, whole));
    const auto seed = static_cast<std::int32_t>(whole.triangle);
    const std::int32_t seeds[3] = {seed, static_cast<std::int32_t>((t + 97) % m.triangles.size()), seed};
    ASSERT_TRUE(exact.nearest(p, INFINITY, seeds, 3, seeded));
    // seeded with a neighbour of the nearest
    std::int32_t neighbour = -1;
    for (std::size_t u = 0; u < m.triangles.size() && neighbour < 0; ++u)
      for (int i = 0; i < 3 && u != whole.triangle; ++i)
        for (int j = 0; j < 3; ++j)
          if (m.triangles[u][i] == m.triangles[whole.triangle][j]) neighbour = static_cast<std::int32_t>(u);
    ASSERT_TRUE(exact.nearest(p, INFINITY, &neighbour, 1, beside));
    ++compared;
    ASSERT_EQ(seeded.triangle, whole.triangle) << "point " << k;
    ASSERT_EQ(seeded.signed_distance, whole.signed_distance) << "point " << k;
    ASSERT_EQ(seeded.normal, whole.normal) << "point " << k;
    ASSERT_EQ(beside.triangle, whole.triangle) << "point " << k;
    ASSERT_EQ(beside.signed_distance, whole.signed_distance) << "point " << k;
    ASSERT_EQ(beside.normal, whole.normal) << "point " << k;
    // and against brute force
    ASSERT_NEAR(seeded.signed_distance, exactSignedDistance(m, p), 2e-6) << "point " << k;
  }
  EXPECT_EQ(compared, 4000);
}

// The cell corners' bound (GridSdfBody::cell, which proves contacts clear
// in MeshBody) and the grid's value less its error (the solver's proof that
// a particle is clear, Body::roughError) are lower bounds of the exact
// distance. The conversion's values beyond the bake's exact band can exceed
// the distance (by up to 1 mm on this bumpy sphere's 4 mm voxels): a corner
// bound taken from one of them overstated the distance as much.
TEST(MeshBody, ClearanceProofsAreLowerBounds) {
  for (const float bump : {0.06f, 0.12f}) {
    TriangleMesh m = bumpySphere(0.1f, 4, bump);
    const BakedBody t = meshBody(m, 0.004f);
    Random rng(7);
    int violations = 0, proven = 0;
    double worst = 0.0;
    for (int k = 0; k < 20000; ++k) {
      const glm::vec3 dir = glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
      const auto r = static_cast<float>(rng.uniform(0.07, 0.14));
      const glm::vec3 p = r * dir;
      const GridSdfBody::Cell cell = t.grid->cell(p);
      float g = 0.0f;
      glm::vec3 gn;
      t.grid->signedDistance(&p, 1, &g, &gn);
      // the rough answer less its error: the solver's other proof of clearance
      const float rough = g - t.body->roughError();
      if (!(cell.lower > 0.0f && cell.lower < 0.02f) && !(rough > 0.0f && rough < 0.02f)) continue;
      ++proven;
      const double e = exactSignedDistance(m, p);
      const double bound = std::max(cell.lower, rough);
      if (bound > e + 1e-5) {
        ++violations;
        worst = std::max(worst, bound - e);
      }
    }
    EXPECT_GT(proven, 1000);
    EXPECT_EQ(violations, 0) << "bump " << bump << ": worst excess " << worst * 1e3 << " mm";
  }
}

// Seeds only make a search faster, also where the surface nearest the seed
// is not the nearest surface: inside a plate 2.5 mm thick made of 3 mm
// triangles, a point nearer the bottom sheet, seeded with the top sheet's
// triangle above it, still finds the bottom one. (A shortcut that settled a
// search among the seed's neighbours without a sound bound on the other
// triangles failed here.)
TEST(MeshBody, ASeedOnTheFarSheetOfAThinPlateStillFindsTheNearOne) {
  TriangleMesh m = bumpySphere(0.05f, 5, 0.0f);
  for (auto& v : m.vertices) v.z *= 0.025f;
  checkMesh(m, "plate");
  const ExactDistance exact(m);
  Random rng(3);
  int bottom_found = 0;
  for (int k = 0; k < 400; ++k) {
    const float x = static_cast<float>(rng.uniform(-0.01, 0.01)), y = static_cast<float>(rng.uniform(-0.01, 0.01));
    ExactDistance::Nearest above{}, whole{}, seeded{};
    ASSERT_TRUE(exact.nearest(glm::vec3(x, y, 0.005f), INFINITY, nullptr, 0, above));
    const glm::vec3 p(x, y, static_cast<float>(rng.uniform(-0.0012, 0.0012)));
    ASSERT_TRUE(exact.nearest(p, INFINITY, nullptr, 0, whole));
    const auto seed = static_cast<std::int32_t>(above.triangle);
    ASSERT_TRUE(exact.nearest(p, INFINITY, &seed, 1, seeded));
    ASSERT_EQ(seeded.triangle, whole.triangle) << "point " << k;
    ASSERT_EQ(seeded.signed_distance, whole.signed_distance) << "point " << k;
    ASSERT_LT(whole.signed_distance, 0.0f) << "point " << k;
    ASSERT_NEAR(whole.signed_distance, exactSignedDistance(m, p), 2e-6) << "point " << k;
    if (p.z < -0.0002f) bottom_found += whole.triangle != above.triangle ? 1 : 0;
  }
  EXPECT_GT(bottom_found, 100);
}

// MeshBody proves a particle clear with the grid's answer less sqrt(3)
// voxels, which holds only while no baked value exceeds its voxel's exact
// distance by more than sqrt(3/4) voxel. The conversion's values beyond the
// exact band exceeded it by up to a whole voxel on the bundled head and
// torso (6 and 14 voxels over 0.8 voxel, where its band stopped short); the
// bake now gives every such voxel its exact distance.
TEST(MeshBody, BakedValuesExceedTheDistanceByLessThanTheProofsAllow) {
  for (const char* name : {"head.ply", "torso.ply"}) {
    TriangleMesh mesh = loadMesh(lhtest::sourceDir() + "/data/meshes/" + name);
    const auto grid = GridSdfBody::bake(mesh, SdfBakeOptions{});
    const MeshBody body(mesh, grid);
    const ExactDistance exact(mesh);
    const float voxel = grid->voxelSize(), bound = GridSdfBody::kFarAllowance * voxel;
    EXPECT_GE(body.roughError(), 0.8660254f * voxel + bound) << name;
    const glm::ivec3 n = grid->dims();
    int checked = 0, over = 0;
    float worst = 0.0f;
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const float v = grid->voxelValue(i, j, k);
          if (!(v > bound)) continue;  // inside, the values are never above the distance
          ++checked;
          const glm::vec3 c = grid->lower() + voxel * glm::vec3(i, j, k);
          ExactDistance::Nearest near{};
          if (!exact.nearest(c, v - bound, nullptr, 0, near)) continue;
          const float excess = v - near.signed_distance;
          if (excess > bound * 1.0001f + 1e-7f) {
            ++over;
            worst = std::max(worst, excess);
          }
        }
    EXPECT_GT(checked, 100000) << name;
    EXPECT_EQ(over, 0) << name << ": worst excess " << worst / voxel << " voxel";
  }
}

// The bound itself, on a grid of exact values with some raised by hand: a
// value more than the allowance above the distance (also one outside where
// the voxel is inside) comes down to the exact signed distance, one within
// the allowance stays, and so do the values inside; whatever the thread
// count.
TEST(MeshBody, FarValuesAboveTheAllowanceComeDownToTheDistance) {
  TriangleMesh m = bumpySphere(0.05f, 3, 0.1f);
  checkMesh(m, "bumpy ball");
  const ExactDistance exact(m);
  const float voxel = 0.01f;
  const glm::ivec3 dims(16, 15, 14);
  const glm::vec3 lower(-0.075f, -0.07f, -0.065f);
  const std::size_t count = static_cast<std::size_t>(dims.x) * dims.y * dims.z;
  std::vector<float> truth(count);
  const std::vector<std::int32_t> nearest(count, -1);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const std::size_t at = (static_cast<std::size_t>(k) * dims.y + j) * dims.x + i;
        truth[at] = static_cast<float>(exactSignedDistance(m, lower + voxel * glm::vec3(i, j, k)));
      }
  const float exact_from = 0.025f, allowance = 0.8f * voxel;
  std::vector<float> raised = truth;
  std::vector<std::size_t> fixed, kept;
  Random rng(11);
  for (std::size_t at = 0; at < count; ++at) {
    if (rng.uniform(0, 1) > 0.1) continue;
    if (truth[at] >= exact_from - 0.5f * voxel) {
      // outside: raised by a whole voxel (comes down) or by half (stays)
      const bool whole = rng.uniform(0, 1) < 0.5;
      raised[at] = std::max(truth[at], exact_from) + (whole ? voxel : 0.5f * voxel);
      (raised[at] - truth[at] > allowance * 1.01f ? fixed : kept).push_back(at);
    } else if (truth[at] < -0.5f * voxel && truth[at] > -(exact_from + 0.5f * voxel)) {
      // inside, not deep: the wrong sign, a voxel farther out than it is in
      raised[at] = std::max(-truth[at], exact_from) + voxel;
      fixed.push_back(at);
    }
  }
  ASSERT_GT(fixed.size(), 40u);
  ASSERT_GT(kept.size(), 20u);
  std::vector<float> one_thread;
  for (const int threads : {1, 2}) {
    std::vector<float> value = raised;
    std::vector<std::int32_t> tri = nearest;
    const GridValues grid{lower, voxel, dims, value, tri};
    EXPECT_EQ(boundFarValues(exact, grid, exact_from, allowance, threads), fixed.size());
    for (const std::size_t at : fixed) {
      EXPECT_NEAR(value[at], truth[at], 2e-6f) << "voxel " << at << " raised to " << raised[at];
      EXPECT_GE(tri[at], 0);
    }
    for (const std::size_t at : kept) EXPECT_EQ(value[at], raised[at]) << "voxel " << at;
    for (std::size_t at = 0; at < count; ++at) {
      if (raised[at] < exact_from) {
        EXPECT_EQ(value[at], raised[at]) << "voxel " << at;
      }
    }
    if (threads == 1) {
      one_thread = value;
    } else {
      EXPECT_EQ(value, one_thread);
    }
  }
}
