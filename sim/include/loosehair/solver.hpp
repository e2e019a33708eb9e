// The loosely-connected-particle hair solver (method.md §1-5).
//
//   Solver solver(params, particles, head_body, trajectory);
//   for (int f = 0; f < frames; ++f) solver.advance(substeps);
//   std::printf("%016llx\n", (unsigned long long)solver.stateHash());
//
// One step runs the named stages of method.md §1 in order and times each
// (StepStats). The result is bitwise the same for any thread count: every
// loop gathers into the particle it owns from sorted neighbour lists.
#pragma once

#include "loosehair/body.hpp"
#include "loosehair/connections.hpp"
#include "loosehair/head_motion.hpp"
#include "loosehair/params.hpp"
#include "loosehair/particles.hpp"
#include "loosehair/wind.hpp"

#include <glm/vec4.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace loosehair {

class NeighborGrid;
class WindAir;
class ThreadChoice;
struct ShapeKeeping;
struct SlicedConnections;    // solver/connection_passes.hpp
struct StepContext;          // solver/step_context.hpp
struct PairRecords;          // solver/neighbor_records.hpp
struct SpringScratch;        // solver/spring_scratch.hpp
enum class PositionRecords;  // solver/hair_hair.hpp
class ImplicitSprings;
class HairChain;

/// Wall-clock seconds spent in each stage of a step. After integration:
/// `strain_limit` the strain limit, `tethers` the hair chain and the
/// tethers, `body_contacts` the projection out of the bodies (and the
/// trapped-hair pass).
struct StageTimes {
  double neighbors = 0, density = 0, springs = 0, hair_hair = 0, external = 0, integrate = 0, strain_limit = 0,
         tethers = 0, body_contacts = 0, directions = 0;
  /// The wind's air particles: neighbours, density, forces, integration,
  /// body contact, emission and removal (0 without wind).
  double air = 0;
  double total() const {
    return neighbors + density + springs + hair_hair + external + integrate + strain_limit + tethers + body_contacts +
           directions + air;
  }
  StageTimes& operator+=(const StageTimes& o);
};

struct StepStats {
  StageTimes last;  // the most recent step
  StageTimes sum;   // all steps so far
  std::uint64_t steps = 0;
  std::size_t neighbor_pairs = 0;      // ordered pairs within 2*h2, last step
  std::size_t active_connections = 0;  // pairs closer than 2*h1 at the end of the last step
  std::size_t clamped_sides = 0;       // side factors held at the clamp, last step
  std::size_t body_contacts = 0;       // particles in contact with the body, last step
  std::size_t strain_limited = 0;      // connections corrected by the strain limit, last step
  std::size_t air_particles = 0;       // wind: air particles after the last step
  std::size_t hair_air_pairs = 0;      // wind: hair-air pairs within 2 h_air, last step
  std::size_t coupled_hair = 0;        // wind on a grid: hair particles in the box, last step
  int air_iterations = 0;              // wind on a grid: pressure CG iterations, last step
  int spring_iterations = 0;           // implicit springs: CG iterations, last step
  float spring_residual = 0;           // implicit springs: relative residual, last step
};

/// What initialisation found; printed by the CLI and checked by tests.
struct InitReport {
  std::size_t particles = 0, roots = 0, connection_pairs = 0;
  double mean_degree = 0;
  std::uint32_t min_degree = 0, max_degree = 0;  // over non-root particles
  /// Non-root particles that cannot reach a root through root-side
  /// connections (method.md §3.1): they hang on nothing. Should be 0.
  std::size_t unanchored = 0;
  float median_density = 0;         // kg/m^3, initial
  float rest_density = 0;           // rho0 (kg/m^3)
  double stable_time_step = 0;      // s, initial estimate
  float collision_coefficient = 0;  // d_c of eq. 17 derived from collision_rate (kg m^3/s)
  float friction_coefficient = 0;   // d_fr of eq. 18
};

enum class Side { Root, Tip };

/// Thrown by Solver::step when the state stops being finite (an unstable
/// scene); the message says when and how many particles.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Solver {
 public:
  /// Takes the initial state (head frame). Throws std::invalid_argument with
  /// every problem of `params` or of the particles.
  Solver(const SimParams& params, Particles particles, std::shared_ptr<const Body> head,
         HeadTrajectory trajectory = HeadTrajectory::still(), double start_time = 0.0);
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver& operator=(Solver&&) noexcept;

  /// One step of length params().time_step.
  void step();
  void advance(int steps) {
    for (int k = 0; k < steps; ++k) step();
  }
  /// Lets the hair settle from the shape it was grown in: `steps` steps
  /// with the clock held at time() (the head, the bodies and the wind as
  /// they are now), so the hair hangs at rest when the motion starts
  /// (scene "settle"). Throws std::invalid_argument for steps < 0.
  void settle(int steps);

  /// Changes the parameters of a running simulation (the viewer's panel):
  /// those ParamInfo marks live take effect from the next step, and
  /// setting a parameter back gives the same bits as never changing it.
  /// Throws std::invalid_argument, naming the parameter, for invalid
  /// values and for changes that need a new solver (smoothing lengths,
  /// connections, material density, the step, shape keeping turned on).
  /// shape_keeping 0 drops the term for good (plain LCP from then on).
  void setParams(const SimParams& params);

  /// Changes the step length (s); throws std::invalid_argument if the
  /// parameters are no longer valid with it.
  void setTimeStep(double dt);

  /// Adds a body that does not turn with the head (method.md §5): a torso, or a
  /// kinematic obstacle. `body` is given in its own frame, placed in the
  /// world by `motion` (pose of its frame over time), and collides only
  /// while begin <= t < end. Its surface velocity enters the contact
  /// response, so a moving obstacle pushes the hair.
  /// An obstacle (`obstacle` true) pushes hair like any body, but where it
  /// squeezes hair against the head or torso the head and torso win: the
  /// last projection of a step keeps particles out of them only.
  void addWorldBody(std::shared_ptr<const Body> body, HeadTrajectory motion = HeadTrajectory::still(),
                    double begin = -INFINITY, double end = INFINITY, bool obstacle = false);
  std::size_t worldBodyCount() const { return world_bodies_.size(); }

  /// Tethers towards a hair tie (method.md §6.2, docs/design.md): particle i may
  /// be no farther than (1 + tether_slack) reach[i] from point[i] (head
  /// frame), besides its root tether; reach[i] < 0 means none. Hair between
  /// the scalp and a tie is held from both ends, as a tie holds it taut.
  /// Throws std::invalid_argument unless both have one finite entry a particle.
  void setTieTethers(std::vector<glm::vec3> point, std::vector<float> reach);

  /// Per-particle shape-keeping strengths (Hz, SimParams::shape_keeping):
  /// particle i is held at the stronger of hz[i] and the solver's own
  /// strength; the prestress, and so the rest state, is unchanged. Used for
  /// the hair a tie pulls taut (HairTie::hold). Throws std::logic_error when
  /// shape keeping is off (plain LCP has no such term), std::invalid_argument
  /// unless hz has one finite entry >= 0 a particle.
  void setShapeKeepingStrengths(const std::vector<float>& hz);

  /// Turns on wind (method.md §5): fills the air box at the current time.
  /// Throws std::invalid_argument with every problem of `wind`.
  void setWind(const WindParams& wind);
  bool hasWind() const { return air_ != nullptr; }
  /// The wind's air is a grid (WindParams::model), not particles.
  bool windOnGrid() const;
  /// Air particles (0 without wind) and their state in world coordinates;
  /// with the air on a grid, the cells outside the bodies, at their centres.
  std::size_t airCount() const;
  void worldAirPositions(std::vector<glm::vec3>& out) const;
  void worldAirVelocities(std::vector<glm::vec3>& out) const;
  std::span<const float> airDensity() const;
  /// The longest step the shape-keeping holds allow (s): kMaxHoldPhasePerStep
  /// over the fastest hold's angular frequency; infinity without holds.
  double holdTimeStep() const;
  /// The air's own stable step (s); infinity without wind.
  double airStableTimeStep() const;

  /// Signed distance (m) from each head-frame point to the union of the
  /// head and the world bodies active at time t (obstacles too if asked);
  /// negative inside.
  void bodyDistance(std::span<const glm::vec3> head_frame_points, double t, std::vector<float>& phi,
                    bool include_obstacles = false) const;
  /// Signed distance and outward normal (head frame) of the nearest of the
  /// head and the world bodies active at time t, obstacles included, exact
  /// where phi < limit (elsewhere phi >= limit, the normal unspecified);
  /// `rough`: by the bodies' fast approximation (Body::roughDistanceBelow).
  void bodyContacts(std::span<const glm::vec3> head_frame_points, double t, float limit, std::span<float> phi,
                    std::span<glm::vec3> normal, bool rough = false) const;
  /// The head and the world bodies (obstacles too) placed as they are now,
  /// each with the map from the head frame into its own frame: the head
  /// first (identity). Detached from the solver: a thread of its own may
  /// keep them (placedBodyContacts) while the solver steps on or is
  /// replaced (the bodies are shared and do not change). Asked through
  /// placedBodyContacts they answer as bodyContacts does, without surface
  /// velocities or the particles' hints.
  std::vector<BodyPlacement> bodyPlacements() const;

  /// Replaces positions, velocities and directions (head frame), for
  /// resets, user interaction and tests, roots included (roots then stay
  /// where they were put: they are never integrated). Neighbours and
  /// densities are recomputed, so queries see the new state. Root points
  /// (the tethers' anchors) and rest lengths stay as they were built. The
  /// next step moves particles out of the body and back within the strain
  /// limit and tethers without turning those moves into velocity, so a
  /// reset into the head does not throw hair off it.
  /// Throws std::invalid_argument on wrong sizes or non-finite values.
  void setKinematicState(std::span<const glm::vec3> position, std::span<const glm::vec3> velocity,
                         std::span<const glm::vec3> direction);

  double time() const { return time_; }
  std::uint64_t stepCount() const { return stats_.steps; }
  const SimParams& params() const { return params_; }
  const Particles& particles() const { return particles_; }
  const ConnectionSet& connections() const { return connections_; }
  /// With the tethers and solver.hair_chain on, the hair chain (sim/src/solver/hair_chain.hpp) keeps
  /// particle i within reach of a partner nearer the root, or of other hair
  /// nearer the root: its distance to the nearest such partner in units of
  /// that partner's reach; -1 for a root, a particle without such partners,
  /// or the chain off.
  float chainGap(std::size_t i) const;
  const StepStats& stats() const { return stats_; }
  const InitReport& initReport() const { return report_; }
  const HeadTrajectory& trajectory() const { return trajectory_; }
  /// Replaces the head's trajectory from now on (LiveHead: a head moved by
  /// hand). The caller keeps it equal to the old one up to time(): the
  /// solver keeps nothing of the past but the state. Throws
  /// std::invalid_argument if its pose now is not finite.
  void setTrajectory(HeadTrajectory trajectory);
  const Body& headBody() const { return *head_; }
  /// The most threads a step runs on. Unless a count was set ("threads"
  /// > 0 or setThreadCount), a step runs on this many or on one, whichever
  /// the solver measures to be faster on the machine as it is (one while
  /// other processes keep every core busy); otherwise on exactly this many.
  int threadCount() const { return max_threads_; }
  /// The number of threads the last step ran on.
  int lastStepThreads() const { return last_step_threads_; }
  /// Exactly `threads` worker threads from now on (>= 1), or 0: the
  /// solver's choice, as above. Results do not depend on it.
  void setThreadCount(int threads);
  /// SPH density of the last step (kg/m^3), or the initial one.
  std::span<const float> density() const { return density_; }
  /// Head pose and motion at the current time.
  HeadKinematics head() const { return trajectory_.kinematics(time_); }

  /// 64-bit hash of the bits of every position, velocity and direction, in
  /// particle order. Equal states give equal hashes on any thread count.
  std::uint64_t stateHash() const;
  /// A hash of the state the solver started from (particles, connections,
  /// air) and of its physical parameters: equal for solvers built from the
  /// same scene and seed, whatever the thread count. Snapshots carry it
  /// (snapshot.hpp). Taken before the first step, kept after it.
  std::uint64_t sceneFingerprint() const;

  /// Largest stable step for the current state, 2/sqrt(max_i sum_j alpha_ij k_ij / m_i) (s).
  double stableTimeStep() const;

  // ---- world-frame views (x_w = R x + c) --------------------------------
  void worldPositions(std::vector<glm::vec3>& out) const;
  void worldVelocities(std::vector<glm::vec3>& out) const;
  void worldDirections(std::vector<glm::vec3>& out) const;
  void worldRootPoints(std::vector<glm::vec3>& out) const;

  // ---- diagnostics -------------------------------------------------------
  /// (1/A_i) sum_{j in side(i)} l_ij alpha_ij k_ij for every particle at the
  /// current positions (Pa); method.md §3.2 requires it to stay E.
  std::vector<float> tensileModulus(Side side) const;
  /// Spring plus hair-hair forces on every particle at the current state (N).
  std::vector<glm::vec3> internalForces() const;

 private:
  /// The spring stages (solver/spring_forces.hpp) on the solver's state.
  void springFactors(SpringScratch& s) const;
  void springForces(SpringScratch& s, std::vector<glm::vec3>& force) const;
  SpringScratch springFactorsNow() const;  // fresh buffers, for the const queries
  float entryFactor(const SpringScratch& s, std::size_t i, std::uint32_t e) const;  // alpha_ij
  void computeRestFactors();          // side factors of the rest state (E A / sum l k W)
  void computeDerivedCoefficients();  // rho0, d_c, d_fr from the parameters
  /// The density stage (solver/density.hpp) at the current positions:
  /// writes density_, pressure_, pressure_term_ and the (x, m) records.
  void measureDensity(PairRecords& records);
  /// The hair-hair stage (solver/hair_hair.hpp): adds to `force`.
  void addHairHairForces(PairRecords& records, PositionRecords xm, std::vector<glm::vec3>& force) const;
  void findNeighbors();

  struct WorldBody {
    std::shared_ptr<const Body> body;
    HeadTrajectory motion;
    double begin, end;
    bool obstacle;
  };
  struct BodyFrame;  // per-step placement of the world bodies
  void placeBodies(double t, std::vector<BodyFrame>& frames, HeadKinematics& head, bool include_obstacles = true) const;
  /// phi, normal and surface velocity of the nearest body; exact where phi <
  /// limit, elsewhere phi >= limit and the rest unspecified
  /// (Body::signedDistanceBelow; `rough`: Body::roughDistanceBelow).
  /// `index` (optional): the particles the points are, whose exact-query
  /// hints (body_hints_, made by prepareBodyHints) speed the exact queries
  /// up without changing their answers.
  void queryBodies(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* x, std::size_t n,
                   float* phi, glm::vec3* normal, glm::vec3* surface_velocity, float limit = INFINITY,
                   bool rough = false, const std::uint32_t* index = nullptr) const;
  /// A hint a particle for the head and for every body of `frames`.
  void prepareBodyHints(const std::vector<BodyFrame>& frames) const;
  std::int32_t* bodyHints(const Body* body) const;
  void worldBodyDistance(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* world,
                         std::size_t n, float* phi) const;
  // the stages of step() after the forces; each returns what StepStats counts
  class PlacedBodies;  // the bodies as the stages ask them (solver_internal.hpp)
  // step()'s phases, in order (solver.cpp)
  class StageClock;
  void accumulateForces(StepContext& ctx, StageClock& clock);
  void correctPositions(StepContext& ctx, double t_end, HeadKinematics& head_end, StageClock& clock);
  void moveAir(float dt, double t_end, const HeadKinematics& head_start, const HeadKinematics& head_end);
  void finishDirections();
  void recordStepStats(const StepContext& ctx);
  /// Particles that the push-out left beyond their tethers (trapped_) put
  /// back along the hair, within reach of a particle nearer the root
  /// (trapped_hair.cpp).
  void freeTrappedHair(const std::vector<BodyFrame>& frames, const HeadKinematics& head);
  /// The body contacts stage (solver/body_contacts.hpp) on the bodies placed
  /// at the step's end (`start_frames`: where integrate saw them), then the
  /// trapped hair freed.
  class EndBodies;  // the bodies at the step's end, as the body contacts ask them
  void resolveBodyContacts(const StepContext& ctx, const std::vector<BodyFrame>& start_frames,
                           const std::vector<BodyFrame>& frames, const std::vector<BodyFrame>& solid_frames,
                           const HeadKinematics& head);
  /// Whether the bodies are placed otherwise than at the last call (the
  /// grid air's bodies need placing again).
  bool airBodiesMoved(const std::vector<BodyFrame>& frames, const HeadKinematics& head);
  std::vector<double> air_bodies_key_, air_bodies_scratch_;
  /// Body distances and (if `velocity`) world velocities at world points;
  /// `rough`: the bodies' grid distances (Body::roughDistanceBelow).
  void worldBodySample(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* world,
                       std::size_t n, float* phi, glm::vec3* velocity, bool rough) const;

  SimParams params_;
  Particles particles_;
  std::vector<WorldBody> world_bodies_;
  std::unique_ptr<WindAir> air_;  // the wind's, particles or a grid (wind_air.hpp)
  ConnectionSet connections_;
  std::unique_ptr<HairChain> chain_;   // no particle loose from the hair (hair_chain.hpp)
  std::vector<std::uint8_t> trapped_;  // this step's particles caught beyond their tethers
  float longest_hair_ = 0.0f;          // the largest arc length (m)
  std::vector<std::uint32_t> trapped_list_;
  std::shared_ptr<const Body> head_;
  // per body: each particle's nearest triangle from its last exact query
  // (Body::signedDistanceBelowHinted); they change no result, so they are
  // not part of the state
  mutable std::vector<std::pair<const Body*, std::vector<std::int32_t>>> body_hints_;
  HeadTrajectory trajectory_;
  int threads_ = 1;      // the team size of the passes running now
  int max_threads_ = 1;  // threadCount()
  int last_step_threads_ = 1;
  std::unique_ptr<ThreadChoice> thread_choice_;  // null: exactly max_threads_
  double time_ = 0.0;
  mutable std::uint64_t fingerprint_ = 0;  // sceneFingerprint(), once taken
  mutable bool fingerprint_taken_ = false;
  friend struct SnapshotAccess;      // snapshot.cpp
  bool absorb_corrections_ = false;  // the step after setKinematicState

  // derived at initialisation
  std::vector<float> cross_section_;                       // A_i
  std::vector<float> rest_factor_root_, rest_factor_tip_;  // a_r, a_t at rest
  float rest_density_ = 0, dc_ = 0, dfr_ = 0;
  float median_density_ = 0;   // initial median hair density (kg/m^3)
  double mean_hair_mass_ = 0;  // kg

  // per step
  std::unique_ptr<NeighborGrid> grid_;
  std::vector<float> density_, pressure_, pressure_term_;  // rho, P, P / rho^2
  std::vector<float> inverse_mass_;                        // 0 for a root
  std::unique_ptr<StepContext> step_;                      // what the stages hand on (solver/step_context.hpp)
  // step()'s placements of the world bodies, reused from step to step: at
  // the start, at the end, and at the end without obstacles
  std::vector<BodyFrame> start_frames_, end_frames_, solid_frames_;
  std::unique_ptr<SpringScratch> scratch_;
  std::unique_ptr<SlicedConnections> sliced_;  // the connections in the layout of the connection passes
  std::unique_ptr<ShapeKeeping> shape_;        // params_.shape_keeping > 0
  std::unique_ptr<ImplicitSprings> implicit_;  // params_.implicit_springs
  std::vector<glm::vec3> spring_dv_;           // its velocity change, this step (the next one's start)
  std::vector<glm::vec3> tie_point_;           // setTieTethers; both empty: none
  std::vector<float> tie_reach_;

  StepStats stats_;
  InitReport report_;
};

}  // namespace loosehair
