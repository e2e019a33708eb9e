// A scene's solver (loosehair/scene.hpp, buildSolver): the head and its
// bodies, the hair grown on it (hair_growth.cpp), the particles ordered in
// memory, the smoothing lengths and the time step from the sampling, the
// bodies and the wind, then the settle. Each step is a function below,
// called in order by buildSolverReporting.
#include "scene/hair_growth.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/param_table.hpp"
#include "init/cantilever.hpp"
#include "init/hanging_hair.hpp"
#include "init/poisson_pillar.hpp"
#include "init/length_map.hpp"
#include "init/mesh_scalp.hpp"
#include "init/scalp_surface.hpp"
#include "bodies/head_orientation.hpp"
#include "loosehair/json_checks.hpp"
#include "solver/neighbor_grid.hpp"
#include "util/parallel.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/head_model.hpp"
#include "files/json_fields.hpp"
#include "loosehair/style.hpp"
#include "style/hair_tie.hpp"
#include "style/style_seeding.hpp"
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <chrono>
#include <optional>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <unordered_map>
#include <set>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

namespace loosehair {
namespace {

using detail::num;

// The longest step the implicit springs take by default: the hair's swing
// (its pendulum and head-shake response, 1-3 Hz) is resolved within a few
// per cent at this step (docs/design.md "Implicit springs", measured).
constexpr double kAccurateStep = 1.0 / 90.0;

// Particles that hang on something: in order of arc length, each must have
// a kept particle nearer the root within `reach`. One that has none, but a
// kept particle nearer the root within `pull` (> reach), is moved along the
// line towards the nearest such particle until it is within 0.9 reach of it
// (`pulled` counts them): at the edge of a pillar the sampling thins out,
// and a particle a few millimetres beyond reach is hair all the same. The
// others are left out. Moved particles may end up inside the head or a
// little beyond their tethers; the first step's corrections see to both.
std::vector<std::uint32_t> anchorableParticles(Particles& p, float reach, float pull, std::size_t& pulled) {
  const std::size_t n = p.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return p.arc_length[a] < p.arc_length[b]; });
  NeighborGrid grid;
  grid.build(p.position, reach, 1);
  std::vector<std::uint8_t> kept(n, 0);
  std::vector<std::uint32_t> kept_list;  // by arc length
  // the kept particles by cell of `pull` at their current positions, made
  // at the first straggler (each a list in the order kept: deterministic)
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> kept_cells;
  bool cells_made = false;
  const float inv_pull = 1.0f / pull;
  auto cellOf = [&](const glm::vec3& x) { return glm::ivec3(glm::floor(x * inv_pull)); };
  auto key = [](glm::ivec3 c) {
    const auto u = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffff; };
    return (u(c.x) << 42) | (u(c.y) << 21) | u(c.z);
  };
  auto keep = [&](std::uint32_t i) {
    kept[i] = 1;
    kept_list.push_back(i);
    if (cells_made) kept_cells[key(cellOf(p.position[i]))].push_back(i);
  };
  pulled = 0;
  for (std::uint32_t i : order) {
    if (p.is_root[i]) {
      keep(i);
      continue;
    }
    bool anchored = false;
    for (std::uint32_t j : grid.neighbors(i))
      if (kept[j] && p.arc_length[j] < p.arc_length[i] && glm::length(p.position[j] - p.position[i]) < reach) {
        anchored = true;
        break;
      }
    if (!anchored) {
      // a straggler: the nearest kept particle nearer the root within
      // `pull`, from the cells (a moved particle is no longer where the
      // grid has it)
      if (!cells_made) {
        for (std::uint32_t j : kept_list) kept_cells[key(cellOf(p.position[j]))].push_back(j);
        cells_made = true;
      }
      std::uint32_t best = i;
      float best_d = pull;
      const glm::ivec3 c = cellOf(p.position[i]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = kept_cells.find(key(c + glm::ivec3(dx, dy, dz)));
            if (it == kept_cells.end()) continue;
            for (std::uint32_t j : it->second) {
              if (!(p.arc_length[j] < p.arc_length[i])) continue;
              const float d = glm::length(p.position[j] - p.position[i]);
              if (d < best_d || (d == best_d && best != i && j < best)) best_d = d, best = j;
            }
          }
      if (best == i) continue;  // left out
      const glm::vec3 from = p.position[best];
      p.position[i] = from + (0.9f * reach / best_d) * (p.position[i] - from);
      ++pulled;
    }
    keep(i);
  }
  std::vector<std::uint32_t> which;
  for (std::uint32_t i = 0; i < n; ++i)
    if (kept[i]) which.push_back(i);
  return which;
}

// The head turns about its frame's origin (data/scenes/README.md, Meshes):
// a mesh placed far from it swings on a long arm, at accelerations no
// neck gives (an origin at the feet of a whole-body model, say).
void warnOfALongArm(const HeadModel& model, BuildReport& rep) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& v : model.headMesh().vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const float size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const float arm = glm::length(glm::max(glm::max(lo, -hi), glm::vec3(0.0f)));  // origin to the box
  if (arm > 0.5f * size) {
    char text[160];
    std::snprintf(text, sizeof text, "%.2f m from the head's bounding box (the head is %.2f m across)", arm, size);
    rep.warnings.push_back(std::string("motion: the head turns about its frame's origin, ") + text +
                           ", so it swings on a long arm; place the origin on the neck axis at about ear "
                           "height (head.offset or head.center)");
  }
}

// Orders the particles along a Morton curve so that neighbours are near in
// memory (our choice, not the method's; keeps the gather loops
// cache-friendly).
void mortonOrder(Particles& p, float rp, TieTethers& tie_tethers) {
  const std::size_t n = p.size();
  std::vector<std::uint64_t> key(n);
  for (std::size_t k = 0; k < n; ++k) key[k] = NeighborGrid::cellKey(p.position[k], 1.0f / rp);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  p = p.select(order);
  tie_tethers.select(order);
}

// The mean distance of a hair particle to its nearest neighbour (rp where
// none has one within 2 rp).
float meanNearestNeighbor(const Particles& p, float rp) {
  const std::size_t n = p.size();
  NeighborGrid grid;
  grid.build(p.position, 2.0f * rp, 1);
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.is_root[i]) continue;
    float best = INFINITY;
    for (std::uint32_t j : grid.neighbors(i)) best = std::min(best, glm::length(p.position[j] - p.position[i]));
    if (std::isfinite(best)) {
      sum += best;
      ++count;
    }
  }
  return count ? static_cast<float>(sum / static_cast<double>(count)) : rp;
}

// The solver's parameters: the scene's, with the smoothing lengths from
// the sampling (method.md §9) and, for "substeps": "auto", a provisional
// step for the checks (set from every bound once the solver is made:
// chooseSubsteps); checked, naming the scene's fields.
SimParams solverParams(const SceneDesc& scene, bool styled, float style_shape_keeping, float rp, float mean_nn,
                       BuildReport& rep) {
  const HairSpec& hair = scene.hair;
  SimParams params = scene.sim;
  if (scene.shape_keeping_auto) params.shape_keeping = styled ? style_shape_keeping : 0.0f;
  rep.shape_keeping = params.shape_keeping;
  if (scene.h1_auto) params.h1 = hair.h1_scale * rp;
  // h2 a little below the spacing of the placed hair (method.md §9), and in any
  // case below h1: hair that hangs loosely is not denser than its sampling.
  if (scene.h2_auto) params.h2 = std::min(hair.h2_scale * mean_nn, 0.8f * params.h1);
  if (!(params.h2 < params.h1))
    throw SceneError(scene.source + ": solver.h2 = " + num(params.h2) +
                     " must be smaller than solver.h1 = " + num(params.h1) + " (Poisson radius " + num(rp) +
                     " m, mean nearest-neighbour distance " + num(mean_nn) + " m)");

  params.time_step = 1.0 / scene.frame_rate / (scene.substeps > 0 ? scene.substeps : 1);
  if (scene.substeps == 0) {
    // a provisional step for the checks below; "auto" sets the real one
    // from every bound (below). It is short enough for the damping rates
    // and the holds, whose own bounds then decide how many steps they need.
    double dt = std::min(static_cast<double>(params.time_step), 1.0e-3);
    for (const DecayRate& r : decayRates(params))
      if (std::isfinite(r.rate) && r.rate > 0.0f) dt = std::min(dt, 0.8 * kMaxDecayPerStep / r.rate);
    if (std::isfinite(params.shape_keeping) && params.shape_keeping > 0.0f)
      dt = std::min(dt, 0.8 * kMaxHoldPhasePerStep / (2.0 * std::numbers::pi * params.shape_keeping));
    params.time_step = static_cast<float>(dt);
  }
  auto problems = validate(params);
  if (!problems.empty()) {
    std::string msg = scene.source + ": invalid solver parameters:";
    for (const auto& pr : problems) msg += "\n  solver." + pr;
    const bool about_step = std::any_of(problems.begin(), problems.end(), [](const std::string& pr) {
      return pr.find("time_step") != std::string::npos;
    });
    if (scene.substeps > 0 && about_step)
      msg += "\n  (time_step = 1 / (frame_rate x substeps) = 1 / (" + num(scene.frame_rate) + " x " +
             std::to_string(scene.substeps) + "): more substeps, or \"substeps\": \"auto\", shorten it)";
    throw SceneError(msg);
  }
  return params;
}

// Stragglers (method.md §3.1 connectivity): a particle with no particle
// nearer the root within the springs' reach (most of 2 h1) can hang on its
// root tether alone; the Poisson sampling leaves a few where a pillar thins
// out at its edge. In order of s, those within twice that reach of hair
// nearer the root are drawn in to it, the others are dropped, so that the
// rest each have a neighbour on the root side; the dropped ones' mass is
// shared.
void dropStragglers(const SceneDesc& scene, const SimParams& params, Particles& p, TieTethers& tie_tethers,
                    BuildReport& rep) {
  const float total_mass = scene.hair.mass;
  const std::size_t before = p.size();
  std::size_t free_before = 0;
  for (std::size_t k = 0; k < before; ++k) free_before += p.is_root[k] ? 0 : 1;
  const std::vector<std::uint32_t> kept =
      anchorableParticles(p, 1.8f * params.h1, 3.6f * params.h1, rep.stragglers_pulled);
  if (kept.size() < before) {
    p = p.select(kept);
    tie_tethers.select(kept);
    for (float& m : p.mass) m = total_mass / static_cast<float>(kept.size());
  }
  rep.stragglers_dropped = before - kept.size();
  if (free_before > 0 && 2 * rep.stragglers_dropped > free_before)
    throw SceneError(scene.source + ": " + std::to_string(rep.stragglers_dropped) + " of " +
                     std::to_string(free_before) + " hair particles have no particle nearer the root within 1.8 h1 = " +
                     num(1.8 * params.h1) + " m, so they cannot reach a root and would fall (" +
                     (scene.h1_auto ? "raise hair.h1_scale or hair.particles, or make the scalp larger"
                                    : "solver.h1 is too small for the particle spacing: raise it, or "
                                      "leave it out to have it set from the sampling") +
                     ")");
}

// The ties' tethers and holds (hair between the scalp and a tie).
void holdTiedHair(const SceneDesc& scene, const SimParams& params, TieTethers& tie_tethers, Solver& solver) {
  if (tie_tethers.reach.empty()) return;
  if (params.shape_keeping > 0.0f) {
    try {
      solver.setShapeKeepingStrengths(tie_tethers.hold);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.source + ": hair.style: a tie's hold is too strong for the time step (" +
                       std::string(e.what()) + "): lower ties[].hold or raise substeps");
    }
  }
  solver.setTieTethers(std::move(tie_tethers.point), std::move(tie_tethers.reach));
}

// Hair that hangs on nothing: no roots, no connections, or most of the
// hair unable to reach a root through its connections (a scalp too small
// for the sampling, a smoothing length below the particle spacing).
void checkTheHairHangs(const SceneDesc& scene, const SimParams& params, const Solver& solver) {
  const InitReport& r = solver.initReport();
  const std::size_t free_particles = r.particles - r.roots;
  const std::string fix =
      " (the scalp is too small for the hair, or hair.h1_scale too small for the particle "
      "spacing: make the head or scalp larger, or raise hair.h1_scale or hair.particles)";
  if (r.roots == 0)
    throw SceneError(scene.source + ": no particle lies under the scalp, so the hair hangs on nothing" + fix);
  if (r.connection_pairs == 0)
    throw SceneError(scene.source + ": no two particles are within h1 = " + num(params.h1) +
                     " m of each other, so nothing holds the hair together" + fix);
  if (free_particles > 0 && 2 * r.unanchored > free_particles)
    throw SceneError(scene.source + ": " + std::to_string(r.unanchored) + " of " + std::to_string(free_particles) +
                     " hair particles cannot reach a root through their connections and would fall" + fix);
}

// The obstacles of the scene, as world bodies.
void addObstacles(const SceneDesc& scene, Solver& solver) {
  for (const ObstacleSpec& o : scene.obstacles) {
    std::shared_ptr<const Body> shape;
    if (o.shape == ObstacleSpec::Shape::Sphere)
      shape = std::make_shared<SphereBody>(o.a, o.radius);
    else
      shape = std::make_shared<CapsuleBody>(o.a, o.b, o.radius);
    solver.addWorldBody(shape, o.motion, o.begin, o.end, true);
  }
}

// The wind's air (limits, parameters), and a warning where its box misses
// the hair.
void addWind(const SceneDesc& scene, Solver& solver, BuildReport& rep) {
  const glm::vec3 box = scene.wind.box_size;
  const double air =
      static_cast<double>(box.x) * box.y * box.z / std::pow(static_cast<double>(scene.wind.spacing), 3.0);
  if (air > static_cast<double>(scene.limits.max_air_particles))
    throw SceneError(scene.source + ": wind.spacing: " + num(scene.wind.spacing) + " m fills the air box with about " +
                     std::to_string(static_cast<long long>(air)) +
                     " air particles (or cells of the air grid), above the limit of " +
                     std::to_string(scene.limits.max_air_particles) +
                     ": use a larger spacing or a smaller wind.box_size (or --allow-expensive)");
  try {
    solver.setWind(scene.wind);
  } catch (const std::invalid_argument& e) {
    throw SceneError(scene.source + ": " + e.what());
  }
  // A wind that cannot reach the hair runs (hair may swing into the box)
  // but is rarely what was meant: say so.
  auto text = [](glm::vec3 v) {
    std::string t = "[";
    for (int a = 0; a < 3; ++a) (t += num(v[a])) += a < 2 ? ", " : "]";
    return t;
  };
  const std::string where =
      "wind.box_center " + text(scene.wind.box_center) + ", wind.box_size " + text(scene.wind.box_size);
  if (solver.airCount() == 0)
    rep.warnings.push_back(where + ": the air box holds no air (it is smaller than wind.spacing " +
                           num(scene.wind.spacing) + " m, or inside the bodies): the wind does nothing");
  else {
    std::vector<glm::vec3> world;
    solver.worldPositions(world);
    const WindAxes axes = windAxes(scene.wind);
    const glm::vec3 half = 0.5f * scene.wind.box_size;
    const bool reaches = std::any_of(world.begin(), world.end(), [&](const glm::vec3& x) {
      const glm::vec3 d = x - scene.wind.box_center;
      return std::abs(glm::dot(d, axes.wind)) <= half.x && std::abs(glm::dot(d, axes.up)) <= half.y &&
             std::abs(glm::dot(d, axes.side)) <= half.z;
    });
    if (!reaches)
      rep.warnings.push_back(where +
                             ": the air box holds none of the hair at the start: the wind touches it "
                             "only where it swings into the box");
  }
}

// The longest step each bound allows, and what to change to relax it: the
// auto step takes the shortest; a scene that would need more steps a frame
// than the limit (given or auto) is refused naming the bound. Returns the
// steps a frame, and sets the solver's step for "auto".
int chooseSubsteps(const SceneDesc& scene, const SimParams& params, Solver& solver) {
  const double frame_time = 1.0 / scene.frame_rate;
  struct StepBound {
    double seconds;
    std::string what, fix;
  };
  std::vector<StepBound> bounds;
  if (params.implicit_springs)  // accuracy only (docs/design.md "Implicit springs": kAccurateStep)
    bounds.push_back(
        {kAccurateStep, "the implicit springs' accuracy (at most 1/90 s a step)", "raise frame_rate (shorter frames)"});
  else  // 60% of the stable spring step
    bounds.push_back({0.6 * solver.initReport().stable_time_step,
                      "the explicit springs' stability (solver.youngs_modulus = " + num(params.youngs_modulus) + ")",
                      "lower solver.youngs_modulus, raise the particle spacing (fewer hair.particles) or set "
                      "solver.implicit_springs to true"});
  // no velocity-decay rate above kMaxDecayPerStep a step (validate() rejects more)
  for (const DecayRate& r : decayRates(params))
    if (r.rate > 0.0f)
      bounds.push_back({kMaxDecayPerStep / r.rate, std::string("solver.") + r.name + " = " + num(r.rate) + " 1/s",
                        std::string("lower solver.") + r.name});
  bounds.push_back({solver.airStableTimeStep(), "the wind's air particles (wind.speed, wind.spacing)",
                    "use the grid air (wind.model \"grid\"), a larger wind.spacing or a lower wind.speed"});
  bounds.push_back({solver.holdTimeStep(), "the style's holds (solver.shape_keeping and the ties' stiffness)",
                    "soften the style's holds (a lower solver.shape_keeping)"});
  const StepBound& tightest = *std::min_element(
      bounds.begin(), bounds.end(), [](const StepBound& a, const StepBound& b) { return a.seconds < b.seconds; });
  // (a bound that divides the frame exactly is not rounded up a step)
  const double needed = scene.substeps > 0 ? scene.substeps : std::ceil(frame_time / tightest.seconds * (1.0 - 1e-6));
  if (needed > scene.limits.max_substeps) {
    const std::string frame = "a frame (1/" + num(scene.frame_rate) + " s)";
    if (scene.substeps > 0)
      throw SceneError(scene.source + ": substeps: " + std::to_string(scene.substeps) +
                       " steps a frame are above the limit of " + std::to_string(scene.limits.max_substeps) +
                       ": use fewer substeps or \"auto\" (or --allow-expensive)");
    throw SceneError(scene.source + ": " + tightest.what + " bounds the step to " + num(tightest.seconds * 1e3) +
                     " ms, so " + frame + " would need " + std::to_string(static_cast<long long>(needed)) +
                     " steps, above the limit of " + std::to_string(scene.limits.max_substeps) + ": " + tightest.fix +
                     " (or --allow-expensive)");
  }
  if (scene.substeps > 0) return scene.substeps;
  const int substeps = std::max(1, static_cast<int>(needed));
  solver.setTimeStep(frame_time / substeps);
  return substeps;
}

Solver buildSolverReporting(const SceneDesc& scene, BuildReport* report, BuildReport& rep) {
  const HairSpec& hair = scene.hair;
  // about 3.7 kB a particle with its connections, neighbours and scratch
  // (1 million: 3.6 GB and 100 s to start, on the sphere)
  if (static_cast<std::size_t>(hair.particles) > scene.limits.max_particles)
    throw SceneError(scene.source + ": hair.particles: " + std::to_string(hair.particles) + " is above the limit of " +
                     std::to_string(scene.limits.max_particles) +
                     " (about 3.7 kB of memory a particle): use fewer (or --allow-expensive)");
  // The head, its scalp and the bodies (method.md §5, §6.1).
  const HeadModel model = HeadModel::build(scene, scene.source, scene.limits.mesh, &rep);
  if (scene.motion.kind() != HeadTrajectory::Kind::Still && !model.headMesh().vertices.empty())
    warnOfALongArm(model, rep);
  // The particles: from a style's strands (method.md §6.2) or hung by
  // cantilever strands (method.md §6.1).
  const bool styled = hair.style_data || !hair.style.empty();
  Particles p;
  float rp = 0;
  float style_shape_keeping = 0;
  TieTethers tie_tethers;
  if (styled)
    style_shape_keeping = growFromStyle(scene, model, p, rp, rep, tie_tethers);
  else
    growCantilever(scene, model, p, rp, rep);
  mortonOrder(p, rp, tie_tethers);
  const float mean_nn = meanNearestNeighbor(p, rp);
  const SimParams params = solverParams(scene, styled, style_shape_keeping, rp, mean_nn, rep);
  dropStragglers(scene, params, p, tie_tethers, rep);
  Solver solver(params, std::move(p), model.head(), scene.motion);
  holdTiedHair(scene, params, tie_tethers, solver);
  checkTheHairHangs(scene, params, solver);
  if (model.torso()) solver.addWorldBody(model.torso());
  addObstacles(scene, solver);
  if (scene.has_wind) addWind(scene, solver, rep);
  const int substeps = chooseSubsteps(scene, params, solver);
  // the hair comes to rest before the first frame (as grown, it fans out)
  if (scene.settle > 0.0) {
    rep.grown = std::make_shared<const Particles>(solver.particles());
    solver.settle(static_cast<int>(std::lround(scene.settle * scene.frame_rate * substeps)));
  }
  if (report) {
    rep.poisson_radius = rp;
    rep.mean_neighbor_distance = mean_nn;
    rep.substeps = substeps;
    rep.time_step = solver.params().time_step;
    *report = rep;
  }
  return solver;
}

}  // namespace

Solver buildSolver(const SceneDesc& scene, BuildReport* report) {
  BuildReport rep;
  try {
    return buildSolverReporting(scene, report, rep);
  } catch (const SceneError& e) {
    // The warnings so far (a head far from human size, on its side) often
    // explain the error: they go with it.
    std::string msg = e.what();
    for (const std::string& w : rep.warnings)
      if (msg.find(w) == std::string::npos) msg += "\n  (" + w + ")";
    throw SceneError(msg);
  }
}

}  // namespace loosehair
