// Stages of the step alone, on hand-made particles (no scene, no solver):
// density, the springs, a hair-hair pair, the external forces, integrate
// against a hand-made body, the strain limit, the tethers and the
// direction pass (each in its file under sim/src/solver/).
#include "solver/connection_builder.hpp"
#include "solver/kernel.hpp"
#include "solver/neighbor_grid.hpp"
#include "solver/body_contacts.hpp"
#include "solver/body_query.hpp"
#include "solver/connection_passes.hpp"
#include "solver/density.hpp"
#include "solver/directions.hpp"
#include "solver/external_forces.hpp"
#include "solver/hair_chain.hpp"
#include "solver/hair_chain_stage.hpp"
#include "solver/integrate.hpp"
#include "solver/pair_forces.hpp"
#include "solver/spring_forces.hpp"
#include "solver/spring_scratch.hpp"
#include "solver/step_context.hpp"
#include "solver/strain_limit.hpp"
#include "solver/tethers.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

using namespace loosehair;

namespace {

// A hair hanging straight down from a root at the origin: n particles l
// apart, the first a root, all pointing down.
struct Hair {
  std::vector<glm::vec3> x, t;
  std::vector<float> s, mass;
  std::vector<std::uint8_t> root;
  ConnectionSet c;
  SlicedConnections sliced;
  Hair(int n, float l, float h1) {
    for (int i = 0; i < n; ++i) {
      x.push_back({0.0f, -l * static_cast<float>(i), 0.0f});
      t.push_back({0.0f, -1.0f, 0.0f});
      s.push_back(l * static_cast<float>(i));
      mass.push_back(1e-4f);
      root.push_back(i == 0 ? 1 : 0);
    }
    ConnectionOptions o;
    o.h1 = h1;
    c = buildConnections(x, t, s, root, o);
    sliced = sliceForPasses(c);
  }
  // (x, 1/m) records of positions p, as integrate makes them
  std::vector<glm::vec4> records(const std::vector<glm::vec3>& p) const {
    std::vector<glm::vec4> r;
    for (std::size_t i = 0; i < p.size(); ++i) r.emplace_back(p[i], root[i] ? 0.0f : 1.0f / mass[i]);
    return r;
  }
  std::size_t limit(std::vector<glm::vec3>& p, int rounds, int threads = 1) const {
    std::vector<glm::vec4> rec[2] = {records(p), {}};
    std::vector<glm::vec3> scratch;
    return limitStrain({0.012f, 0.01f, rounds}, sliced, root, p, rec, scratch, threads);
  }
};

}  // namespace

TEST(StrainLimitStage, PullsAnOverStretchedHairBackAndNeverMovesTheRoot) {
  const Hair h(2, 0.01f, 0.012f);
  ASSERT_EQ(h.c.pairCount(), 1u);
  std::vector<glm::vec3> p = h.x;
  p[1].y = -0.015f;  // 50 % over its rest length, within the support 2 h1
  EXPECT_EQ(h.limit(p, 1), 1u);
  EXPECT_EQ(p[0], h.x[0]) << "a root does not move";
  // one round moves it back by the excess over (1 + 1 %) l, scaled by how
  // loose the spring is there (W(r) / W(l) < 1): part of the way
  const float after_one = glm::length(p[1] - p[0]);
  EXPECT_LT(after_one, 0.015f);
  EXPECT_GT(after_one, 0.0101f);
  EXPECT_FLOAT_EQ(p[1].x, 0.0f);
  EXPECT_FLOAT_EQ(p[1].z, 0.0f);
  // more rounds come nearer the limit, never past it
  std::vector<glm::vec3> q = h.x;
  q[1].y = -0.015f;
  h.limit(q, 20);
  const float after_many = glm::length(q[1] - q[0]);
  EXPECT_LT(after_many, after_one);
  EXPECT_GE(after_many, 0.0101f * (1.0f - 1e-5f));
}

TEST(StrainLimitStage, LeavesSlackAndReleasedConnectionsAlone) {
  const Hair h(2, 0.01f, 0.012f);
  std::vector<glm::vec3> slack = h.x;
  slack[1].y = -0.008f;  // shorter than rest
  EXPECT_EQ(h.limit(slack, 4), 0u);
  EXPECT_EQ(slack[1], glm::vec3(0.0f, -0.008f, 0.0f));
  std::vector<glm::vec3> gone = h.x;
  gone[1].y = -0.03f;  // beyond the support 2 h1: the hair let go here
  EXPECT_EQ(h.limit(gone, 4), 0u);
  EXPECT_EQ(gone[1], glm::vec3(0.0f, -0.03f, 0.0f));
}

TEST(StrainLimitStage, MovesTwoEqualParticlesEquallyAndKeepsTheirCentre) {
  const Hair h(3, 0.01f, 0.012f);
  std::vector<glm::vec3> p = h.x;
  // root, then 1 and 2 pulled apart symmetrically about their centre
  p[1].y = -0.010f;
  p[2].y = -0.024f;
  const glm::vec3 centre = 0.5f * (p[1] + p[2]);
  // only the 1-2 connection is over-stretched if 1 stays at rest from the root
  h.limit(p, 1);
  EXPECT_LT(glm::length(p[2] - p[1]), 0.014f);
  // 1 is pulled by the root's connection too (it is at rest: no pull), and
  // by 2; 2 by 1 only: equal inverse masses share the excess equally
  EXPECT_NEAR(0.5f * (p[1].y + p[2].y), centre.y, 1e-7f);
}

TEST(StrainLimitStage, GivesTheSameBitsOnAnyThreadCount) {
  // a long hair, jittered and stretched
  const Hair h(2000, 0.004f, 0.0048f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.001f, 0.001f);
  std::vector<glm::vec3> p = h.x;
  for (std::size_t i = 1; i < p.size(); ++i) p[i] = 1.01f * p[i] + glm::vec3(jitter(rng), jitter(rng), jitter(rng));
  std::vector<glm::vec3> one = p, two = p;
  const std::size_t a = h.limit(one, 4, 1), b = h.limit(two, 4, 2);
  EXPECT_GT(a, 100u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)), 0);
}

TEST(TetherStage, HoldsEachParticleWithinReachOfItsRootAndTie) {
  const std::vector<std::uint8_t> root = {1, 0, 0, 0};
  const std::vector<glm::vec3> rp(4, glm::vec3(0.0f));
  const std::vector<float> s = {0.0f, 0.1f, 0.2f, 0.2f};
  std::vector<glm::vec3> x = {{0.0f, 0.3f, 0.0f}, {0.0f, -0.05f, 0.0f}, {0.3f, -0.4f, 0.0f}, {0.0f, -0.2f, 0.0f}};
  applyTethers(0.01f, root, rp, s, {}, {}, x, 2);
  EXPECT_EQ(x[0], glm::vec3(0.0f, 0.3f, 0.0f)) << "a root is not tethered";
  EXPECT_EQ(x[1], glm::vec3(0.0f, -0.05f, 0.0f)) << "within reach: not moved";
  EXPECT_NEAR(glm::length(x[2]), 1.01f * 0.2f, 1e-6f) << "beyond reach: onto it";
  EXPECT_NEAR(x[2].x / x[2].y, 0.3f / -0.4f, 1e-6f) << "along the line to the root";
  EXPECT_EQ(x[3], glm::vec3(0.0f, -0.2f, 0.0f));
  // a tie 5 cm to the side with a reach of 1 cm pulls particle 3 to it
  const std::vector<glm::vec3> tie(4, glm::vec3(0.05f, -0.2f, 0.0f));
  const std::vector<float> reach = {-1.0f, -1.0f, -1.0f, 0.01f};
  applyTethers(0.0f, root, rp, s, tie, reach, x, 1);
  EXPECT_NEAR(glm::length(x[3] - tie[3]), 0.01f, 1e-6f) << "the tie comes last: it holds";
  EXPECT_NEAR(x[3].y, -0.2f, 1e-7f);
}

// The direction pass (solver/directions.hpp) on the same straight hair.
TEST(DirectionStage, TurnsAStrayDirectionBackAlongTheHairAndMeasuresTheNextSprings) {
  const Hair h(5, 0.01f, 0.012f);
  const std::size_t n = h.x.size();
  std::vector<glm::vec3> dir = h.t;
  dir[2] = glm::normalize(glm::vec3(1.0f, -0.2f, 0.0f));  // knocked sideways
  dir[0] = glm::vec3(1.0f, 0.0f, 0.0f);                   // a root keeps whatever it has
  const std::vector<glm::vec3> v(n, glm::vec3(0.0f));
  std::vector<float> weight(h.sliced.layout.entryCount(), 1.0f);
  std::vector<float> sum_root(n, -1.0f), sum_tip(n, -1.0f);
  const DirectionPassResult r = updateDirections(0.012f, h.sliced, weight, h.root, h.x, v, dir, sum_root, sum_tip, 2);
  EXPECT_EQ(r.broken, 0u);
  EXPECT_EQ(r.active_entries, 2 * h.c.pairCount());
  EXPECT_NEAR(dir[2].x, 0.0f, 1e-6f);
  EXPECT_NEAR(dir[2].y, -1.0f, 1e-6f);
  EXPECT_EQ(dir[0], glm::vec3(1.0f, 0.0f, 0.0f));
  // the side sums of l_ij k_ij at these (rest) positions: what the factor
  // pass of the next step divides E A by
  for (std::size_t i = 0; i < n; ++i) {
    double root_side = 0, tip_side = 0;
    const CubicKernel k1(0.012f);
    for (std::uint32_t e = h.c.begin(i); e < h.c.end(i); ++e) {
      const float l = h.c.rest_length[e];
      (h.c.tip_side[e] ? tip_side : root_side) += static_cast<double>(l) * h.c.strength[e] * k1.W(l);
    }
    EXPECT_NEAR(sum_root[i], root_side, 1e-6 * root_side + 1e-12) << i;
    EXPECT_NEAR(sum_tip[i], tip_side, 1e-6 * tip_side + 1e-12) << i;
  }
  // no active connection (all weights 0): a particle keeps its direction
  std::vector<float> none(weight.size(), 0.0f);
  std::vector<glm::vec3> kept = dir;
  kept[3] = glm::vec3(0.0f, 0.0f, 1.0f);
  updateDirections(0.012f, h.sliced, none, h.root, h.x, v, kept, sum_root, sum_tip, 1);
  EXPECT_EQ(kept[3], glm::vec3(0.0f, 0.0f, 1.0f));
  // a state that is not finite is counted, never passed on silently
  std::vector<glm::vec3> bad_v = v;
  bad_v[4].y = NAN;
  EXPECT_EQ(updateDirections(0.012f, h.sliced, weight, h.root, h.x, bad_v, dir, sum_root, sum_tip, 1).broken, 1u);
}

// Density (solver/density.hpp): m W(0) for a lone particle, plus m_j W(r)
// for each neighbour within 2 h2; the pressure terms from them.
TEST(DensityStage, SumsTheKernelOverNeighboursAndGivesThePressureTerm) {
  const float h2 = 0.01f, m = 2e-4f;
  const std::vector<glm::vec3> x = {{0.0f, 0.0f, 0.0f}, {0.012f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}};
  const std::vector<float> mass(3, m);
  NeighborGrid grid;
  grid.build(x, 2.0f * h2, 2, NeighborGrid::ListIndex::SearchOrder);
  PairRecords records;
  std::vector<float> rho(3), p(3), term(3);
  computeDensity({h2, 10.0f, 1.0f}, grid, x, mass, records, rho, p, term, 2);
  const CubicKernel k(h2);
  EXPECT_FLOAT_EQ(rho[0], m * k.W(0.0f) + m * k.W(0.012f));
  EXPECT_FLOAT_EQ(rho[1], rho[0]);
  EXPECT_FLOAT_EQ(rho[2], m * k.W(0.0f)) << "beyond the support: alone";
  for (int i = 0; i < 3; ++i) {
    EXPECT_FLOAT_EQ(p[i], 10.0f * (rho[i] - 1.0f));
    EXPECT_FLOAT_EQ(term[i], p[i] / (rho[i] * rho[i]));
  }
  ASSERT_EQ(records.xm.size(), 3u) << "the (x, m) records handed to the hair-hair pass";
  for (std::size_t k2 = 0; k2 < 3; ++k2) {
    const std::uint32_t i = grid.searchOrder()[k2];
    EXPECT_EQ(records.xm[k2], glm::vec4(x[i], m));
  }
}

// One hair-hair pair (solver/pair_forces.hpp): the force on j is exactly
// the negative of the force on i, nothing acts beyond the support, and a
// receding pair feels no collision or friction.
TEST(HairHairPairStage, ActsOppositelyOnTheTwoAndOnlyOnApproach) {
  const float h = 0.01f;
  const CubicKernel k(h);
  const HairHairPairTerms terms{1.0f / h, k.W(0.0f) / 4.0f, -k.dWdr(h) / 3.0f, 3.0f, 2.0f};
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto unit = [&] { return glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.0f, 0.01f)); };
  for (int trial = 0; trial < 200; ++trial) {
    const glm::vec3 d = 0.012f * glm::vec3(u(rng), u(rng), u(rng)), v(u(rng), u(rng), u(rng));
    glm::vec3 ti = unit(), tj = trial % 4 == 0 ? ti : unit();  // parallel hairs too
    const float mm = 1e-8f, pp = trial % 2 ? 5.0f : 0.0f;
    const PairForce a =
        hairHairPairForce(terms, d.x, d.y, d.z, v.x, v.y, v.z, ti.x, ti.y, ti.z, tj.x, tj.y, tj.z, mm, pp);
    const PairForce b =
        hairHairPairForce(terms, -d.x, -d.y, -d.z, -v.x, -v.y, -v.z, tj.x, tj.y, tj.z, ti.x, ti.y, ti.z, mm, pp);
    ASSERT_TRUE(std::isfinite(a.x + a.y + a.z)) << trial;
    EXPECT_EQ(a.x, -b.x) << trial;
    EXPECT_EQ(a.y, -b.y) << trial;
    EXPECT_EQ(a.z, -b.z) << trial;
  }
  const glm::vec3 ti(1.0f, 0.0f, 0.0f), tj(0.0f, 0.0f, 1.0f);  // crossing: n = t_i x t_j = -y
  auto force = [&](glm::vec3 d, glm::vec3 v, float pp) {
    const PairForce f =
        hairHairPairForce(terms, d.x, d.y, d.z, v.x, v.y, v.z, ti.x, ti.y, ti.z, tj.x, tj.y, tj.z, 1e-8f, pp);
    return glm::vec3(f.x, f.y, f.z);
  };
  EXPECT_EQ(force({0.0f, 0.021f, 0.0f}, {0.0f, -1.0f, 0.0f}, 5.0f), glm::vec3(0.0f)) << "beyond 2 h";
  EXPECT_EQ(force({0.0f, 0.01f, 0.0f}, {0.3f, 1.0f, 0.0f}, 0.0f), glm::vec3(0.0f)) << "receding";
  const glm::vec3 f = force({0.0f, 0.01f, 0.0f}, {0.3f, -1.0f, 0.0f}, 0.0f);  // j comes down onto i
  EXPECT_LT(f.y, 0.0f) << "the collision takes i along with j";
  EXPECT_GT(f.x, 0.0f) << "friction drags i along j's slide";
}

namespace {

// Two free particles l apart along -y joined by one connection.
struct Pair {
  std::vector<glm::vec3> x, t, v;
  std::vector<float> s, mass, area, rest_root, rest_tip;
  std::vector<std::uint8_t> root;
  ConnectionSet c;
  SlicedConnections sliced;
  explicit Pair(float l) {
    x = {{0.0f, 0.0f, 0.0f}, {0.0f, -l, 0.0f}};
    t.assign(2, glm::vec3(0.0f, -1.0f, 0.0f));
    v.assign(2, glm::vec3(0.0f));
    s = {0.0f, l};
    mass.assign(2, 1e-4f);
    area.assign(2, 4e-6f);
    rest_root.assign(2, 1e30f);  // no clamp
    rest_tip.assign(2, 1e30f);
    root.assign(2, 0);
    ConnectionOptions o;
    o.h1 = 1.2f * l;
    c = buildConnections(x, t, s, root, o);
    sliced = sliceForPasses(c);
  }
};

}  // namespace

// The springs (solver/spring_forces.hpp): none at rest; stretched, equal
// and opposite, of E A times the strain (the tensile modulus kept whatever
// the kernel's weight, method.md §3.2).
TEST(SpringStage, PullsAStretchedPairBackWithTheTensileModulus) {
  const float l = 0.01f;
  Pair p(l);
  ASSERT_EQ(p.c.pairCount(), 1u);
  const SpringSettings settings{1.2f * l, 2e6, 4.0f, 0.0f};
  auto forces = [&] {
    SpringScratch s;
    resizeSpringScratch(s, 2, p.c, p.sliced, false);
    computeSpringFactors(settings, p.c, {p.x, p.v, p.root, p.area, p.rest_root, p.rest_tip}, s, 2);
    std::vector<glm::vec3> f(2, glm::vec3(7.0f));  // replaced, not added to
    accumulateSpringForces(settings, p.sliced, 2, s, f, 2);
    return f;
  };
  std::vector<glm::vec3> f = forces();
  EXPECT_EQ(f[0], glm::vec3(0.0f));
  EXPECT_EQ(f[1], glm::vec3(0.0f));
  for (float strain : {0.01f, 0.3f}) {  // a stretched pair: the kernel weight k_ij drops, E A stays
    p.x[1].y = -l * (1.0f + strain);
    f = forces();
    EXPECT_NEAR(f[0].y, -2e6f * 4e-6f * strain, 1e-4f * 2e6f * 4e-6f * strain) << strain;
    EXPECT_EQ(f[0].x, 0.0f);
    EXPECT_EQ(f[1].y, -f[0].y) << "equal and opposite";
  }
}

// External forces (solver/external_forces.hpp): gravity on a still head,
// the centrifugal force in a turning head's frame; roots take none.
TEST(ExternalForcesStage, AddsGravityAndTheHeadFramesInertia) {
  const std::vector<glm::vec3> x = {{0.0f, 0.0f, 0.0f}, {0.1f, 0.0f, 0.0f}}, v(2, glm::vec3(0.0f));
  const std::vector<float> m = {1.0f, 2.0f};
  const std::vector<std::uint8_t> root = {1, 0};
  std::vector<glm::vec3> f(2, glm::vec3(1.0f, 0.0f, 0.0f));
  HeadKinematics still;
  addExternalForces({{0.0f, -10.0f, 0.0f}, 0.0f}, still, {x, v, m, root}, nullptr, f, 2);
  EXPECT_EQ(f[0], glm::vec3(1.0f, 0.0f, 0.0f)) << "a root";
  EXPECT_EQ(f[1], glm::vec3(1.0f, -20.0f, 0.0f)) << "added to what was there";
  HeadKinematics turning;
  turning.angular_velocity = {0.0, 3.0, 0.0};
  std::vector<glm::vec3> g(2, glm::vec3(0.0f));
  addExternalForces({{0.0f, 0.0f, 0.0f}, 0.0f}, turning, {x, v, m, root}, nullptr, g, 1);
  EXPECT_NEAR(g[1].x, 2.0f * 9.0f * 0.1f, 1e-5f) << "m w^2 r outward";
  EXPECT_NEAR(g[1].y, 0.0f, 1e-6f);
}

namespace {

// The ground y = 0, still: the body integrate asks.
struct Ground final : BodyQuery {
  void nearest(const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal, glm::vec3* surface_velocity, float,
               bool) const override {
    for (std::size_t i = 0; i < n; ++i) {
      phi[i] = x[i].y;
      normal[i] = {0.0f, 1.0f, 0.0f};
      surface_velocity[i] = glm::vec3(0.0f);
    }
  }
  float roughError() const override { return 0.0f; }
};

}  // namespace

// Integrate (solver/integrate.hpp): symplectic Euler in free space; on the
// ground the approach is removed and the slide slowed by Coulomb friction;
// a root does not move; what it hands on is in the context.
TEST(IntegrateStage, StepsFreeParticlesAndStopsThemAtABody) {
  std::vector<glm::vec3> x = {{0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0005f, 0.0f}};
  std::vector<glm::vec3> v = {{5.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, {1.0f, -1.0f, 0.0f}};
  const std::vector<float> m = {1.0f, 2.0f, 1.0f}, inv_m = {0.0f, 0.5f, 1.0f};
  const std::vector<std::uint8_t> root = {1, 0, 0};
  StepContext ctx;
  ctx.resize(3);
  ctx.dt = 0.01f;
  ctx.force = {{0.0f, 0.0f, 0.0f}, {0.0f, -4.0f, 0.0f}, {0.0f, 0.0f, 0.0f}};
  const std::size_t contacts = integrate({0.001f, 0.5f}, Ground(), {x, v, m, inv_m, root}, {}, ctx, 2);
  EXPECT_EQ(x[0], glm::vec3(0.0f, 1.0f, 0.0f)) << "a root stays";
  EXPECT_EQ(v[1], glm::vec3(0.0f, -0.02f, 1.0f)) << "v += dt f / m";
  EXPECT_EQ(x[1], glm::vec3(0.0f, 1.0f, 0.0f) + 0.01f * v[1]) << "x += dt v (the new v)";
  EXPECT_EQ(contacts, 1u);
  EXPECT_EQ(v[2].y, 0.0f) << "inelastic: the approach removed";
  EXPECT_FLOAT_EQ(v[2].x, 0.5f) << "Coulomb: the slide slowed by mu |v_n|";
  EXPECT_EQ(ctx.integrated_position[1], x[1]);
  EXPECT_EQ(ctx.strain_records[0][1], glm::vec4(x[1], 0.5f));
  EXPECT_LE(ctx.body_clearance[1], x[1].y) << "a lower bound of the distance";
  // with the implicit solve's velocity change instead of the forces
  const std::vector<glm::vec3> dv = {{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 0.0f, 0.0f}};
  integrate({0.001f, 0.5f}, Ground(), {x, v, m, inv_m, root}, dv, ctx, 1);
  EXPECT_EQ(v[1], glm::vec3(0.0f, -0.02f, 0.0f));
}

// The hair chain (solver/hair_chain_stage.hpp): a particle flung beyond the
// springs' reach of the hair nearer its root is drawn back within it, and
// only it moves.
TEST(HairChainStage, DrawsAFlungParticleBackWithinReachOfItsHair) {
  const Hair h(5, 0.01f, 0.012f);
  const HairChain chain(h.c, h.root, h.s, h.x, 0.012f);
  std::vector<glm::vec3> x = h.x;
  x[4] = glm::vec3(0.03f, -0.025f, 0.0f);  // within its tether (s = 0.04), 3 cm from the hair
  std::vector<std::uint8_t> moved;
  holdHairChains(chain, 0.0f, h.x, h.s, {}, {}, x, moved);
  ASSERT_EQ(moved.size(), 5u);
  EXPECT_EQ(moved[4], 1);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(moved[i], 0) << i;
    EXPECT_EQ(x[i], h.x[i]) << i;
  }
  float nearest = INFINITY;
  for (int i = 0; i < 4; ++i) nearest = std::min(nearest, glm::length(x[4] - x[i]));
  EXPECT_LE(nearest, HairChain::kSupportFraction * 2.0f * 0.012f + 1e-6f);
  EXPECT_LE(glm::length(x[4] - h.x[0]), 0.04f + 1e-6f) << "and within its tether";
}

namespace {

// The ground y = 0 at the step's end, for the body contacts.
struct GroundAtEnd final : ContactBodies {
  void nearest(const glm::vec3* x, std::size_t n, const std::uint32_t*, bool, float* phi, glm::vec3* normal,
               glm::vec3* surface_velocity) const override {
    for (std::size_t i = 0; i < n; ++i) {
      phi[i] = x[i].y;
      normal[i] = {0.0f, 1.0f, 0.0f};
      surface_velocity[i] = glm::vec3(0.0f);
    }
  }
  void clearance(std::size_t, std::size_t count, float* lower) const override {
    std::fill(lower, lower + count, -INFINITY);
  }
  int rounds() const override { return 2; }
  bool hasObstacles() const override { return false; }
};

}  // namespace

// The body contacts (solver/body_contacts.hpp): a particle inside the
// ground is put on its surface and keeps no speed into or out of it; one
// outside that the corrections did not move keeps its state; a root stays.
TEST(BodyContactStage, PutsAParticleInsideOnTheSurfaceWithoutThrowingIt) {
  std::vector<glm::vec3> x = {{0.0f, 0.1f, 0.0f}, {0.0f, -0.01f, 0.0f}, {0.05f, 0.05f, 0.0f}};
  std::vector<glm::vec3> v = {{0.0f, 0.0f, 0.0f}, {0.5f, -1.0f, 0.0f}, {0.0f, -0.2f, 0.0f}};
  const std::vector<std::uint8_t> root = {1, 0, 0};
  const std::vector<glm::vec3> rp(3, glm::vec3(0.0f, 0.1f, 0.0f));
  const std::vector<float> s = {0.0f, 0.2f, 0.2f};
  StepContext ctx;
  ctx.resize(3);
  ctx.dt = 0.01f;
  ctx.integrated_position = x;
  std::vector<std::uint8_t> trapped;
  const bool any = projectOutOfBodies({false, 0.0f, 0.0f}, GroundAtEnd(), {x, v, root, rp, s}, ctx, trapped, 2);
  EXPECT_FALSE(any);
  EXPECT_EQ(x[0], glm::vec3(0.0f, 0.1f, 0.0f));
  EXPECT_GE(x[1].y, 0.0f) << "on the surface";
  EXPECT_LT(x[1].y, 1e-4f);
  EXPECT_EQ(x[1].x, 0.0f);
  EXPECT_EQ(v[1].y, 0.0f) << "the push out is not a velocity, the approach is gone";
  EXPECT_EQ(v[1].x, 0.5f) << "the slide along the surface kept";
  EXPECT_EQ(x[2], glm::vec3(0.05f, 0.05f, 0.0f));
  EXPECT_EQ(v[2], glm::vec3(0.0f, -0.2f, 0.0f));
}
