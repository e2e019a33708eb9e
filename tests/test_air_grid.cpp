// Wind on a grid (air_grid.hpp): a steady wind crosses an empty box
// unchanged, the air flows around a body without divergence and never into
// it, a moving body carries the air beside it, the hair-air drag is equal and
// opposite, dense hair slows the air behind it, and the results are the same
// bits for any thread count.
#include "wind/air_grid.hpp"
#include "util/random.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace loosehair;

namespace {

WindParams box(float speed) {
  WindParams w;
  w.model = AirModel::Grid;
  w.direction = glm::vec3(1, 0, 0);
  w.speed = speed;
  w.box_center = glm::vec3(0);
  w.box_size = glm::vec3(0.6f, 0.36f, 0.36f);
  w.spacing = 0.03f;
  return w;
}

// A ball of radius r at c moving at velocity v (world).
AirGrid::BodySampler ball(glm::vec3 c, float r, glm::vec3 v = glm::vec3(0)) {
  return [c, r, v](const glm::vec3* x, std::size_t n, float* phi, glm::vec3* vel) {
    for (std::size_t k = 0; k < n; ++k) {
      phi[k] = glm::length(x[k] - c) - r;
      vel[k] = v;
    }
  };
}

struct Hair {
  std::vector<glm::vec3> x, v, f;
  std::vector<float> m;
  std::vector<std::uint8_t> root;
};

// A block of hair particles at rest in [lo, hi].
Hair block(glm::vec3 lo, glm::vec3 hi, std::size_t n, float mass, std::uint64_t seed) {
  Hair h;
  Random rng(seed);
  for (std::size_t i = 0; i < n; ++i) {
    h.x.emplace_back(rng.uniform(lo.x, hi.x), rng.uniform(lo.y, hi.y), rng.uniform(lo.z, hi.z));
    h.v.emplace_back(0.0f);
  }
  h.f.assign(n, glm::vec3(0));
  h.m.assign(n, mass);
  h.root.assign(n, 0);
  return h;
}

// One air step of dt ending at t, whether or not the air's own pace would
// take one now (the tests' steps are short).
void stepAir(AirGrid& air, float dt, double t, const AirGrid::BodySampler& bodies, int threads = 2) {
  (void)air.due(dt);
  air.advance(t, bodies, threads);
}

}  // namespace

TEST(AirGrid, SteadyWindCrossesAnEmptyBoxUnchanged) {
  AirGrid air(box(3.0f));
  air.fill(0.0, {});
  for (int s = 0; s < 30; ++s) stepAir(air, 0.01f, (s + 1) * 0.01, {});
  std::vector<glm::vec3> x, v;
  air.openCells(x, v);
  ASSERT_EQ(x.size(), air.cellCount());
  float worst = 0;
  for (const auto& u : v) worst = std::max(worst, glm::length(u - glm::vec3(3, 0, 0)));
  EXPECT_LT(worst, 1e-4f) << "uniform wind through an open box stays uniform";
  EXPECT_LT(air.maxDivergence(), 1e-3f);
}

TEST(AirGrid, ASideGustIsCarriedDownwindAtTheWindSpeed) {
  // A slab of air moving up (divergence-free: the same up velocity across
  // the slab) in a 1 m/s wind: the advection carries it downwind.
  WindParams w = box(1.0f);
  AirGrid air(w);
  air.fill(0.0, {});
  AirGrid::State s = air.state();
  const glm::ivec3 n = air.cells();
  const float h = air.cellSize();
  auto slabCentre = [&](const AirGrid& a) {  // up-velocity-weighted mean position along the wind
    double sum = 0, weight = 0;
    for (int i = 0; i < n.x; ++i) {
      const glm::vec3 p = glm::vec3(-0.5f * n.x * h + (i + 0.5f) * h, 0, 0);
      const double up = std::max(0.0f, a.velocityAt(p).y);
      sum += up * p.x;
      weight += up;
    }
    return weight > 0 ? sum / weight : 1e9;
  };
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j <= n.y; ++j)
      for (int i = 4; i < 7; ++i)  // x in [-0.18, -0.09]
        s.u[1][static_cast<std::size_t>(i + n.x * (j + (n.y + 1) * k))] = 0.5f;
  air.restore(s);
  const double before = slabCentre(air);
  // hair steps of 10 ms; the air takes its own (3 cells at 1 m/s: 0.09 s)
  int air_steps = 0;
  for (int step = 0; step < 18; ++step)
    if (air.due(0.01f)) {
      air.advance((step + 1) * 0.01, {}, 2);
      ++air_steps;
    }
  EXPECT_EQ(air_steps, 2);
  const double after = slabCentre(air);
  std::printf("up-moving slab from %.3f m to %.3f m along the wind in 0.18 s\n", before, after);
  EXPECT_NEAR(after - before, 0.18, 0.04) << "carried at the wind's 1 m/s";
}

TEST(AirGrid, AirFlowsAroundABodyWithoutDivergenceAndNeverIntoIt) {
  const glm::vec3 c(-0.05f, 0, 0);
  const float r = 0.08f;
  WindParams w = box(3.0f);
  AirGrid air(w);
  const auto body = ball(c, r);
  air.fill(0.0, body);
  for (int s = 0; s < 40; ++s) stepAir(air, 0.01f, (s + 1) * 0.01, body);
  // Nearly divergence-free: what is left is the solve's tolerance, a
  // thousandth of the wind through a face.
  EXPECT_LT(air.maxDivergence(), 2e-3f * w.speed / w.spacing);
  // No air enters the ball: every face touching it moves with it (here: is
  // still), so the air sampled anywhere inside is still.
  Random rng(3);
  float inside = 0;
  for (int k = 0; k < 400; ++k) {
    const glm::vec3 d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (glm::length(d) > 1.0f) continue;
    inside = std::max(inside, glm::length(air.velocityAt(c + (r - 1.5f * w.spacing) * d)));
  }
  EXPECT_EQ(inside, 0.0f);
  // It goes around: deflected up in front of the ball's upper half, fast
  // beside it, slow in its lee.
  const float up_front = air.velocityAt(c + glm::vec3(-r - 0.02f, 0.5f * r, 0)).y;
  const float beside = air.velocityAt(c + glm::vec3(0, r + 0.02f, 0)).x;
  const float behind = air.velocityAt(c + glm::vec3(r + 0.03f, 0, 0)).x;
  std::printf("upward in front %.2f m/s, beside %.2f, behind %.2f (wind 3)\n", up_front, beside, behind);
  EXPECT_GT(up_front, 0.1f * w.speed);
  EXPECT_GT(beside, 0.7f * w.speed);
  EXPECT_LT(behind, 0.3f * w.speed);
}

TEST(AirGrid, AMovingBodyCarriesTheAirBesideIt) {
  WindParams w = box(0.0f);
  AirGrid air(w);
  const glm::vec3 v(0, 0, 1.0f);  // across the box
  double t = 0;
  glm::vec3 c(0, 0, -0.06f);
  air.fill(0.0, ball(c, 0.07f, v));
  for (int s = 0; s < 10; ++s) {
    c += 0.01f * v;
    t += 0.01;
    stepAir(air, 0.01f, t, ball(c, 0.07f, v));
  }
  const float ahead = glm::dot(air.velocityAt(c + glm::vec3(0, 0, 0.07f + 0.02f)), v);
  const float far = glm::length(air.velocityAt(glm::vec3(0.25f, 0.15f, -0.15f)));
  std::printf("air ahead of the moving ball %.2f m/s, far away %.3f m/s\n", ahead, far);
  EXPECT_GT(ahead, 0.3f) << "the ball pushes the air in front of it";
  EXPECT_LT(far, 0.5f * ahead);
}

TEST(AirGrid, HairAirDragIsEqualAndOpposite) {
  AirGrid air(box(3.0f));
  air.fill(0.0, {});
  Hair h = block(glm::vec3(-0.1f), glm::vec3(0.1f), 3000, 2e-5f, 7);
  Random rng(11);
  for (auto& v : h.v) v = glm::vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
  h.root[5] = 1;
  h.x[9] = glm::vec3(2.0f, 0, 0);  // outside the box: no drag
  // a head frame turned and moving: the drag uses world velocities
  HeadKinematics head;
  head.pose.rotation = glm::dmat3(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1));
  head.pose.center = glm::dvec3(0.01, 0, 0);
  head.velocity = glm::dvec3(0.2, 0, 0);
  head.angular_velocity = glm::dvec3(0, 0, 1.0);
  // the hair's head-frame positions that land in the block
  for (auto& x : h.x) x = glm::vec3(glm::transpose(head.pose.rotation) * (glm::dvec3(x) - head.pose.center));
  const AirGrid::State before = air.state();
  const float dt = 0.02f;  // a long step: the limiters act
  air.exchangeDrag(head, h.x, h.v, h.m, h.root, h.f, dt, 2);
  EXPECT_EQ(air.coupledHair(), 2998u);
  EXPECT_EQ(h.f[5], glm::vec3(0)) << "roots are held by the head";
  EXPECT_EQ(h.f[9], glm::vec3(0));
  glm::dvec3 on_hair(0);
  double scale = 0;
  for (const auto& f : h.f) {
    const glm::dvec3 world = head.pose.rotation * glm::dvec3(f);
    on_hair += world;
    scale += glm::length(world);
  }
  ASSERT_GT(scale, 0);
  const glm::dvec3 total = on_hair + air.dragOnAir();
  EXPECT_LT(glm::length(total), 1e-5 * scale) << "momentum is exchanged, not made";
  EXPECT_GT(on_hair.x, 0.0) << "the wind pushes the hair downwind";
  // and the faces' velocities carry it: their momentum change (grid axes,
  // each face the air of one cell) is the hair's gain, reversed
  const AirGrid::State after = air.state();
  glm::dvec3 faces(0.0);
  for (int c = 0; c < 3; ++c)
    for (std::size_t f = 0; f < after.u[c].size(); ++f)
      faces[c] += static_cast<double>(after.u[c][f]) - static_cast<double>(before.u[c][f]);
  const double cell_mass = static_cast<double>(box(3.0f).density) * std::pow(static_cast<double>(air.cellSize()), 3.0);
  const glm::dvec3 on_faces = faces * cell_mass / static_cast<double>(dt);
  EXPECT_NEAR(glm::length(on_faces), glm::length(on_hair), 1e-3 * scale);
  EXPECT_LT(on_faces.x, 0.0) << "the air loses momentum downwind (grid axis 0 is the wind)";
}

TEST(AirGrid, DenseHairSlowsTheAirBehindIt) {
  WindParams w = box(2.0f);
  AirGrid free_air(w), blocked(w);
  free_air.fill(0.0, {});
  blocked.fill(0.0, {});
  // a fixed block of hair across the middle of the box (held: zero velocity)
  Hair h = block(glm::vec3(-0.06f, -0.09f, -0.09f), glm::vec3(0.0f, 0.09f, 0.09f), 6000, 1e-5f, 3);
  const HeadKinematics still;
  const glm::vec3 in_hair(-0.03f, 0, 0), behind(0.08f, 0, 0);
  float slowest_in_hair = INFINITY;
  for (int s = 0; s < 40; ++s) {
    std::fill(h.f.begin(), h.f.end(), glm::vec3(0));
    blocked.exchangeDrag(still, h.x, h.v, h.m, h.root, h.f, 0.01f, 2);
    // right after the drag, before the air moves: the limiter's business
    slowest_in_hair = std::min(slowest_in_hair, blocked.velocityAt(in_hair).x);
    stepAir(blocked, 0.01f, (s + 1) * 0.01, {});
    stepAir(free_air, 0.01f, (s + 1) * 0.01, {});
  }
  const float slowed = blocked.velocityAt(behind).x, open = free_air.velocityAt(behind).x;
  const float inside = blocked.velocityAt(in_hair).x;
  std::printf("air in the hair %.2f m/s (slowest %.2f), behind it %.2f m/s, without hair %.2f m/s\n", inside,
              slowest_in_hair, slowed, open);
  EXPECT_LT(slowed, 0.7f * open) << "the hair pushes back on the air";
  EXPECT_LT(inside, 0.7f * open);
  // The hair is still: the drag may bring the air in it to rest, never
  // push it backwards (the limiters keep either side from overshooting).
  EXPECT_GE(slowest_in_hair, 0.0f);
}

TEST(AirGrid, StepsEveryFewHairStepsAndTheDragActsBetween) {
  WindParams w = box(3.6f);
  AirGrid air(w);
  air.fill(0.0, {});
  EXPECT_NEAR(air.stepLength(), AirGrid::kCellsAStep * 0.03 / 3.6, 1e-9);
  ASSERT_EQ(AirGrid::kCellsAStep, 3.0);
  // hair steps of 1/90 s: the air (25 ms) steps every other one
  std::vector<int> due;
  for (int s = 0; s < 9; ++s) {
    due.push_back(air.due(1.0f / 90.0f) ? 1 : 0);
    if (due.back()) air.advance((s + 1) / 90.0, {}, 2);
  }
  EXPECT_EQ(due, (std::vector<int>{0, 1, 0, 1, 0, 1, 0, 1, 0}));
  // between the air's steps the drag still slows the air at once
  Hair h = block(glm::vec3(-0.03f), glm::vec3(0.03f), 3000, 1e-5f, 5);
  const float before = air.velocityAt(glm::vec3(0)).x;
  air.exchangeDrag(HeadKinematics{}, h.x, h.v, h.m, h.root, h.f, 1.0f / 90.0f, 2);
  const float after = air.velocityAt(glm::vec3(0)).x;
  EXPECT_LT(after, before - 0.1f);
  EXPECT_GT(after, 0.0f) << "the limiter keeps the air from overshooting the hair";
}

TEST(AirGrid, SameBitsForAnyThreadCount) {
  auto run = [](int threads) {
    WindParams w = box(3.0f);
    w.profile = {{0.0, 0.2}, {0.1, 1.0}, {0.2, 0.5}};
    AirGrid air(w);
    const auto body = ball(glm::vec3(0.02f, 0.01f, 0), 0.06f);
    air.fill(0.0, body);
    Hair h = block(glm::vec3(-0.12f), glm::vec3(0.1f), 2000, 1e-5f, 9);
    for (int s = 0; s < 20; ++s) {
      std::fill(h.f.begin(), h.f.end(), glm::vec3(0));
      air.exchangeDrag(HeadKinematics{}, h.x, h.v, h.m, h.root, h.f, 0.01f, threads);
      if (air.due(0.01f)) air.advance((s + 1) * 0.01, body, threads);
    }
    return std::make_pair(air.state(), h.f);
  };
  const auto one = run(1), three = run(3);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(one.first.u[c], three.first.u[c]);
  EXPECT_EQ(one.first.pressure, three.first.pressure);
  EXPECT_EQ(one.second, three.second);
}

TEST(AirGrid, RestoreRefusesAStateOfAnotherSize) {
  AirGrid air(box(1.0f));
  AirGrid::State s = air.state();
  s.u[1].pop_back();
  EXPECT_THROW(air.restore(s), std::invalid_argument);
  WindParams bad = box(1.0f);
  bad.spacing = -1.0f;
  try {
    AirGrid{bad};
    FAIL() << "a negative spacing is accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("wind.spacing = -1"), std::string::npos) << e.what();
  }
}
