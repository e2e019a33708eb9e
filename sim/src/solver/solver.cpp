// The step of method.md §1: neighbours, density, springs, hair-hair, external,
// integrate, strain limit, directions. Every parallel loop owns particle i
// and gathers from i's sorted lists, so the bits of the result do not depend
// on the thread count (method.md §5 Determinism).
#include "solver/solver_internal.hpp"

namespace loosehair {

StageTimes& StageTimes::operator+=(const StageTimes& o) {
  neighbors += o.neighbors;
  density += o.density;
  springs += o.springs;
  hair_hair += o.hair_hair;
  external += o.external;
  integrate += o.integrate;
  air += o.air;
  strain_limit += o.strain_limit;
  tethers += o.tethers;
  body_contacts += o.body_contacts;
  directions += o.directions;
  return *this;
}

namespace {

SpringSettings springSettingsOf(const SimParams& p) {
  return {p.h1, p.youngs_modulus, p.stiffness_clamp, p.spring_damping};
}

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

}  // namespace

Solver::Solver(const SimParams& params, Particles particles, std::shared_ptr<const Body> head,
               HeadTrajectory trajectory, double start_time)
    : params_(params),
      particles_(std::move(particles)),
      head_(std::move(head)),
      trajectory_(std::move(trajectory)),
      time_(start_time),
      scratch_(std::make_unique<SpringScratch>()),
      sliced_(std::make_unique<SlicedConnections>()) {
  const auto problems = validate(params_);
  if (!problems.empty()) {
    std::string msg = "invalid simulation parameters:";
    for (const auto& p : problems) msg += "\n  " + p;
    throw std::invalid_argument(msg);
  }
  if (!head_) throw std::invalid_argument("the solver needs a head body");
  if (!std::isfinite(start_time)) throw std::invalid_argument("start time is not finite");
  particles_.check();
  setThreadCount(params_.threads);

  const std::size_t n = particles_.size();
  ConnectionOptions copt;
  copt.h1 = params_.h1;
  copt.alignment_threshold = params_.alignment_threshold;
  copt.target_connections = params_.target_connections;
  copt.threads = threads_;
  connections_ =
      buildConnections(particles_.position, particles_.direction, particles_.arc_length, particles_.is_root, copt);
  chain_ = std::make_unique<HairChain>(connections_, particles_.is_root, particles_.arc_length, particles_.root_point,
                                       params_.h1);
  longest_hair_ = 0.0f;
  for (float a : particles_.arc_length) longest_hair_ = std::max(longest_hair_, a);

  // Cross-sections (eq. 9) and the side factors of the rest state, the
  // reference of the stiffness clamp.
  cross_section_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    cross_section_[i] = std::pow(particles_.mass[i] / params_.material_density, 2.0f / 3.0f);
  computeRestFactors();

  inverse_mass_.resize(n);  // 0 for a root (fixed); no root-root connections
  for (std::size_t i = 0; i < n; ++i) inverse_mass_[i] = particles_.is_root[i] ? 0.0f : 1.0f / particles_.mass[i];
  *sliced_ = sliceForPasses(connections_);

  grid_ = std::make_unique<NeighborGrid>();
  density_.assign(n, 0.0f);
  pressure_.assign(n, 0.0f);
  pressure_term_.assign(n, 0.0f);
  step_ = std::make_unique<StepContext>();
  step_->resize(n);
  resizeSpringScratch(*scratch_, n, connections_, *sliced_, false);

  // Initial density: rest density rho0 and the kernel-free collision and
  // friction coefficients (method.md §4: d_c W / m summed over neighbours is about
  // d_c rho / m^2, so d_c = rate * m^2 / rho removes `rate` of the relative
  // normal velocity per second).
  findNeighbors();
  measureDensity(step_->pair_records);
  std::vector<float> hair_density;
  double mass_sum = 0;
  std::size_t hair_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (particles_.is_root[i]) continue;
    hair_density.push_back(density_[i]);
    mass_sum += particles_.mass[i];
    ++hair_count;
  }
  float median = 0;
  if (!hair_density.empty()) {
    auto mid = hair_density.begin() + static_cast<std::ptrdiff_t>(hair_density.size() / 2);
    std::nth_element(hair_density.begin(), mid, hair_density.end());
    median = *mid;
  }
  mean_hair_mass_ = hair_count ? mass_sum / static_cast<double>(hair_count) : 0.0;
  median_density_ = median;
  computeDerivedCoefficients();

  report_.particles = n;
  report_.connection_pairs = connections_.pairCount();
  report_.unanchored = countUnanchored(connections_, particles_.is_root);
  report_.median_density = median;
  report_.rest_density = rest_density_;
  report_.collision_coefficient = dc_;
  report_.friction_coefficient = dfr_;
  std::size_t degree_sum = 0;
  report_.min_degree = hair_count ? UINT32_MAX : 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (particles_.is_root[i]) {
      ++report_.roots;
      continue;
    }
    const std::uint32_t d = connections_.degree(i);
    degree_sum += d;
    report_.min_degree = std::min(report_.min_degree, d);
    report_.max_degree = std::max(report_.max_degree, d);
  }
  report_.mean_degree = hair_count ? static_cast<double>(degree_sum) / static_cast<double>(hair_count) : 0.0;
  report_.stable_time_step = stableTimeStep();
  if (params_.shape_keeping > 0.0f) {
    // the pressure terms with the rest density just set (the first
    // density pass ran before it was known)
    measureDensity(step_->pair_records);
    const glm::dmat3 rt = glm::transpose(trajectory_.kinematics(time_).pose.rotation);
    shape_ = std::make_unique<ShapeKeeping>(params_.shape_keeping, particles_.position, particles_.mass,
                                            internalForces(), glm::vec3(rt * glm::dvec3(params_.gravity)));
  }
}

void Solver::setTrajectory(HeadTrajectory trajectory) {
  const HeadKinematics k = trajectory.kinematics(time_);
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(k.pose.center[a]) || !std::isfinite(k.angular_velocity[a]) ||
        !std::isfinite(k.angular_acceleration[a]) || !std::isfinite(k.acceleration[a]))
      throw std::invalid_argument("setTrajectory: the head's motion is not finite at t = " + std::to_string(time_));
  trajectory_ = std::move(trajectory);
}

void Solver::computeRestFactors() {
  const std::size_t n = particles_.size();
  rest_factor_root_.assign(n, 0.0f);
  rest_factor_tip_.assign(n, 0.0f);
  const CubicKernel k1(params_.h1);
  for (std::size_t i = 0; i < n; ++i) {
    double sr = 0, st = 0;
    for (std::uint32_t e = connections_.begin(i); e < connections_.end(i); ++e) {
      const float l = connections_.rest_length[e];
      const double lk = static_cast<double>(l) * connections_.strength[e] * k1.W(l);
      (connections_.tip_side[e] ? st : sr) += lk;
    }
    const double ea = static_cast<double>(params_.youngs_modulus) * cross_section_[i];
    rest_factor_root_[i] = sr > 0 ? static_cast<float>(ea / sr) : 0.0f;
    rest_factor_tip_[i] = st > 0 ? static_cast<float>(ea / st) : 0.0f;
  }
}

void Solver::computeDerivedCoefficients() {
  const double median = median_density_, mean_mass = mean_hair_mass_;
  rest_density_ = params_.rest_density_scale * median_density_;
  dc_ = dfr_ = 0;
  if (median > 0) {
    dc_ = static_cast<float>(params_.collision_rate * mean_mass * mean_mass / median);
    dfr_ = static_cast<float>(params_.friction_rate * mean_mass * mean_mass / median);
  }
}

void Solver::setParams(const SimParams& p) {
  const auto problems = validate(p);
  if (!problems.empty()) throw std::invalid_argument(problems.front());
  for (const ParamInfo& info : paramTable()) {
    const double was = info.get(params_), now = info.get(p);
    if (was == now || info.live) continue;
    throw std::invalid_argument(std::string(info.name) + " cannot change in a running simulation (" +
                                std::to_string(was) + " to " + std::to_string(now) + "): it applies on restart");
  }
  if (p.shape_keeping > 0.0f && !shape_)
    throw std::invalid_argument(
        "shape_keeping cannot be turned on in a running simulation (the styled rest state is "
        "set up when it starts): it applies on restart");
  if (shape_ && p.shape_keeping > 0.0f && shape_->fastestWith(p.shape_keeping) * p.time_step > kMaxHoldPhasePerStep)
    throw std::invalid_argument("shape_keeping = " + std::to_string(p.shape_keeping) +
                                " Hz is too strong for time_step = " + std::to_string(p.time_step) + " s");
  const bool stiffness = p.youngs_modulus != params_.youngs_modulus;
  if (!p.implicit_springs && (params_.implicit_springs || stiffness)) {
    // explicit springs from now on: the step must be within their stable
    // limit, which scales as 1/sqrt(E)
    const double limit = stableTimeStep() *
                         std::sqrt(static_cast<double>(params_.youngs_modulus) / static_cast<double>(p.youngs_modulus));
    if (p.time_step > limit)
      throw std::invalid_argument(
          "implicit_springs = 0 (explicit springs) with youngs_modulus = " + std::to_string(p.youngs_modulus) +
          " needs a time step of at most " + std::to_string(limit * 1e3) + " ms, and this simulation steps " +
          std::to_string(p.time_step * 1e3) + " ms: keep the implicit springs, or restart with more substeps");
  }
  const bool threads = p.threads != params_.threads;
  params_ = p;
  if (stiffness) computeRestFactors();
  computeDerivedCoefficients();
  report_.rest_density = rest_density_;
  report_.collision_coefficient = dc_;
  report_.friction_coefficient = dfr_;
  if (shape_ && p.shape_keeping == 0.0f) shape_.reset();  // plain LCP from now on
  if (shape_) shape_->setBase(p.shape_keeping);
  if (threads) setThreadCount(p.threads);  // a new count starts a new measurement
}

void Solver::setTimeStep(double dt) {
  SimParams p = params_;
  p.time_step = dt;
  const auto problems = validate(p);
  if (!problems.empty()) throw std::invalid_argument(problems.front());
  if (shape_ && shape_->fastest() * dt > kMaxHoldPhasePerStep)
    throw std::invalid_argument("time_step = " + std::to_string(dt) + " s is too long for a shape-keeping hold of " +
                                std::to_string(shape_->fastest() / (2.0 * std::numbers::pi)) + " Hz");
  params_ = p;
}

void Solver::setKinematicState(std::span<const glm::vec3> position, std::span<const glm::vec3> velocity,
                               std::span<const glm::vec3> direction) {
  const std::size_t n = particles_.size();
  if (position.size() != n || velocity.size() != n || direction.size() != n)
    throw std::invalid_argument("setKinematicState: expected " + std::to_string(n) +
                                " positions, velocities and directions");
  Particles next = particles_;
  for (std::size_t i = 0; i < n; ++i) {
    next.position[i] = position[i];
    next.velocity[i] = velocity[i];
    next.direction[i] = direction[i];
  }
  next.check();  // finite, unit directions
  particles_ = std::move(next);
  // Queries between steps (internalForces, density) see the new state.
  findNeighbors();
  measureDensity(step_->pair_records);
  scratch_->sums_current = false;
  // A reset may leave particles inside the body or over-stretched; the
  // first step moves them back without turning the move into velocity.
  absorb_corrections_ = true;
  spring_dv_.clear();  // the next implicit solve starts from zero
}

void Solver::setThreadCount(int threads) {
  if (threads < 0 || threads > parallel::kMaxThreads)
    throw std::invalid_argument("thread count " + std::to_string(threads) + " is not in [0, " +
                                std::to_string(parallel::kMaxThreads) + "]");
  max_threads_ = threads > 0 ? threads : parallel::availableThreads();
  thread_choice_ = threads > 0 ? nullptr : std::make_unique<ThreadChoice>(max_threads_);
  threads_ = max_threads_;
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;

float Solver::chainGap(std::size_t i) const {
  if (!params_.tether || !params_.hair_chain) return -1.0f;
  const auto cand = chain_->candidates(i);
  const auto reach = chain_->reaches(i);
  if (cand.empty()) return -1.0f;
  float gap = INFINITY;
  for (std::size_t k = 0; k < cand.size(); ++k)
    gap = std::min(gap, glm::length(particles_.position[i] - particles_.position[cand[k]]) / reach[k]);
  return gap;
}
Solver& Solver::operator=(Solver&&) noexcept = default;

void Solver::setShapeKeepingStrengths(const std::vector<float>& hz) {
  if (!shape_) throw std::logic_error("setShapeKeepingStrengths: shape keeping is off (solver.shape_keeping = 0)");
  if (hz.size() != particles_.size())
    throw std::invalid_argument("setShapeKeepingStrengths: " + std::to_string(hz.size()) + " strengths for " +
                                std::to_string(particles_.size()) + " particles");
  for (std::size_t i = 0; i < hz.size(); ++i) {
    if (!(std::isfinite(hz[i]) && hz[i] >= 0.0f))
      throw std::invalid_argument("setShapeKeepingStrengths: particle " + std::to_string(i) + ": strength " +
                                  std::to_string(hz[i]) + " Hz is not a finite value >= 0");
    if (2.0 * std::numbers::pi * hz[i] * params_.time_step > kMaxHoldPhasePerStep)
      throw std::invalid_argument("setShapeKeepingStrengths: particle " + std::to_string(i) + ": " +
                                  std::to_string(hz[i]) +
                                  " Hz is too strong for time_step = " + std::to_string(params_.time_step) + " s");
  }
  shape_->setHolds(hz);
}

void Solver::setTieTethers(std::vector<glm::vec3> point, std::vector<float> reach) {
  const std::size_t n = particles_.size();
  if (point.size() != n || reach.size() != n)
    throw std::invalid_argument("setTieTethers: " + std::to_string(point.size()) + " points and " +
                                std::to_string(reach.size()) + " reaches for " + std::to_string(n) + " particles");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(point[i].x + point[i].y + point[i].z) || !std::isfinite(reach[i]))
      throw std::invalid_argument("setTieTethers: particle " + std::to_string(i) + ": not a finite tether");
  tie_point_ = std::move(point);
  tie_reach_ = std::move(reach);
}

void Solver::settle(int steps) {
  if (steps < 0) throw std::invalid_argument("settle: " + std::to_string(steps) + " steps");
  const double now = time_;
  for (int k = 0; k < steps; ++k) {
    step();
    time_ = now;  // the head, the bodies and the wind stay as they are now
  }
}

// ---- the step ---------------------------------------------------------------
// Times the stages of one step: lap(field) adds the time since the last lap.
class Solver::StageClock {
 public:
  void lap(double& stage) {
    const auto t = Clock::now();
    stage += seconds(t0_, t);
    t0_ = t;
  }

 private:
  Clock::time_point t0_ = Clock::now();
};

void Solver::step() {
  if (!fingerprint_taken_) (void)sceneFingerprint();
  threads_ = thread_choice_ ? thread_choice_->next() : max_threads_;
  last_step_threads_ = threads_;
  const auto step_start = Clock::now();
  const double t_end = time_ + params_.time_step;
  StageClock clock;
  StepContext& ctx = *step_;
  ctx.dt = static_cast<float>(params_.time_step);
  ctx.absorb_corrections = absorb_corrections_;
  ctx.times = StageTimes{};
  absorb_corrections_ = false;

  accumulateForces(ctx, clock);
  HeadKinematics head_start;
  placeBodies(time_, start_frames_, head_start);
  ctx.contacts = integrate(
      {params_.contact_thickness, params_.body_friction}, PlacedBodies(*this, start_frames_, head_start),
      {particles_.position, particles_.velocity, particles_.mass, inverse_mass_, particles_.is_root},
      params_.implicit_springs ? std::span<const glm::vec3>(spring_dv_) : std::span<const glm::vec3>(), ctx, threads_);
  clock.lap(ctx.times.integrate);
  HeadKinematics head_end;
  correctPositions(ctx, t_end, head_end, clock);
  if (air_ && air_->due(ctx.dt)) {
    moveAir(ctx.dt, t_end, head_start, head_end);
    clock.lap(ctx.times.air);
  }
  finishDirections();
  clock.lap(ctx.times.directions);

  time_ = t_end;
  recordStepStats(ctx);
  if (thread_choice_) thread_choice_->record(seconds(step_start, Clock::now()));
  threads_ = max_threads_;
}

// Neighbours, density, the springs, hair-hair, the wind's air, the external
// forces into ctx.force; with implicit springs, the velocity change.
void Solver::accumulateForces(StepContext& ctx, StageClock& clock) {
  SpringScratch& s = *scratch_;
  StageTimes& st = ctx.times;
  findNeighbors();
  clock.lap(st.neighbors);
  measureDensity(ctx.pair_records);
  clock.lap(st.density);
  springFactors(s);
  springForces(s, ctx.force);
  clock.lap(st.springs);
  // the (x, m) records are the density pass's
  if (params_.hair_hair) addHairHairForces(ctx.pair_records, PositionRecords::Made, ctx.force);
  clock.lap(st.hair_hair);
  if (air_) {
    // the hair-air drag (method.md §5; wind_air.hpp)
    air_->exchange(trajectory_.kinematics(time_), particles_.position, particles_.velocity, particles_.mass,
                   particles_.is_root, ctx.force, ctx.dt, threads_);
    clock.lap(st.air);
  }
  addExternalForces({params_.gravity, params_.air_drag}, trajectory_.kinematics(time_),
                    {particles_.position, particles_.velocity, particles_.mass, particles_.is_root}, shape_.get(),
                    ctx.force, threads_);
  clock.lap(st.external);
  if (params_.implicit_springs) {
    if (!implicit_) implicit_ = std::make_unique<ImplicitSprings>();
    const ImplicitSpringReport rep = solveImplicitSpringStep(
        {params_.spring_damping, params_.implicit_tolerance, params_.implicit_iterations}, *sliced_, s, ctx.force,
        particles_.mass, particles_.is_root, ctx.dt, *implicit_, spring_dv_, threads_);
    stats_.spring_iterations = rep.iterations;
    stats_.spring_residual = rep.residual;
    clock.lap(st.springs);
  }
}

// Corrections: the strain limit, the hair chain and the tethers, and no
// particle left inside a body (the bodies where they are at t_end).
void Solver::correctPositions(StepContext& ctx, double t_end, HeadKinematics& head_end, StageClock& clock) {
  StageTimes& st = ctx.times;
  ctx.limited = 0;
  if (params_.strain_limit)
    ctx.limited =
        limitStrain({params_.h1, params_.max_strain, params_.strain_limit_iterations}, *sliced_, particles_.is_root,
                    particles_.position, ctx.strain_records, ctx.limited_position, threads_);
  clock.lap(st.strain_limit);
  if (params_.tether && params_.hair_chain)
    holdHairChains(*chain_, params_.tether_slack, particles_.root_point, particles_.arc_length, tie_point_, tie_reach_,
                   particles_.position, ctx.chain_moved);
  else
    ctx.chain_moved.clear();
  if (params_.tether)
    applyTethers(params_.tether_slack, particles_.is_root, particles_.root_point, particles_.arc_length, tie_point_,
                 tie_reach_, particles_.position, threads_);
  clock.lap(st.tethers);
  const std::vector<BodyFrame>& frames = end_frames_;
  placeBodies(t_end, end_frames_, head_end);
  placeBodies(t_end, solid_frames_, head_end, false);  // without obstacles: the last round
  resolveBodyContacts(ctx, start_frames_, frames, solid_frames_, head_end);
  clock.lap(st.body_contacts);
}

// The wind's air moves (the grid's at its own pace), the bodies where they
// are at the step's end.
void Solver::moveAir(float dt, double t_end, const HeadKinematics& head_start, const HeadKinematics& head_end) {
  const std::vector<BodyFrame>& frames = end_frames_;
  struct StepBodies final : WindAir::Bodies {
    const Solver& solver;
    const std::vector<BodyFrame>& frames;
    StepBodies(const Solver& s, const std::vector<BodyFrame>& f) : solver(s), frames(f) {}
    void local(const glm::vec3* x, std::size_t count, float* phi, glm::vec3* normal, glm::vec3* v) const override {
      solver.queryBodies(frames, end, x, count, phi, normal, v, INFINITY, true);
    }
    void worldSample(const glm::vec3* w, std::size_t count, float* phi, glm::vec3* v) const override {
      solver.worldBodySample(frames, end, w, count, phi, v, true);
    }
    void worldDistance(const glm::vec3* w, std::size_t count, float* phi) const override {
      solver.worldBodyDistance(frames, end, w, count, phi);
    }
  } bodies(*this, frames);
  bodies.start = head_start;
  bodies.end = head_end;
  bodies.moved = airBodiesMoved(frames, head_end);
  air_->move(time_, t_end, dt, bodies, threads_);
  if (const std::size_t bad = air_->nonFinite(); bad > 0)
    throw SimulationError("the simulation became unstable at t = " + std::to_string(time_) +
                          " s: " + std::to_string(bad) +
                          " numbers of the wind's air are not finite; lower wind.speed "
                          "or reduce the time step");
}

// The direction pass (its spring sums are the next step's), and no
// non-finite state passed on.
void Solver::finishDirections() {
  SpringScratch& s = *scratch_;
  const DirectionPassResult directions =
      updateDirections(params_.h1, *sliced_, s.weight, particles_.is_root, particles_.position, particles_.velocity,
                       particles_.direction, s.sum_root, s.sum_tip, threads_);
  s.sums_current = true;  // the next step's factor pass takes the sums from here
  s.active_entries = directions.active_entries;
  const std::size_t broken = directions.broken;
  if (broken > 0) {
    const auto& x = particles_.position;
    const auto& v = particles_.velocity;
    const std::size_t n = particles_.size();
    std::size_t first = 0;
    for (; first < n; ++first)
      if (!std::isfinite(x[first].x + x[first].y + x[first].z + v[first].x + v[first].y + v[first].z)) break;
    throw SimulationError("the simulation became unstable at t = " + std::to_string(time_) + " s: " +
                          std::to_string(broken) + " particles have non-finite state (first: " + std::to_string(first) +
                          "); reduce the time step or the stiffness");
  }
}

void Solver::recordStepStats(const StepContext& ctx) {
  const SpringScratch& s = *scratch_;
  stats_.last = ctx.times;
  stats_.sum += ctx.times;
  ++stats_.steps;
  stats_.neighbor_pairs = grid_->pairCount();
  stats_.clamped_sides = s.clamped;
  stats_.body_contacts = ctx.contacts;
  stats_.strain_limited = ctx.limited;
  stats_.active_connections = s.active_entries / 2;
  if (air_) {
    air_->report(stats_);
  } else {
    stats_.air_particles = stats_.hair_air_pairs = stats_.coupled_hair = 0;
    stats_.air_iterations = 0;
  }
}

// ---- queries -----------------------------------------------------------------
std::uint64_t Solver::stateHash() const {
  // FNV-1a over the raw bits, in particle order.
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) {
      h ^= p[k];
      h *= 0x100000001b3ULL;
    }
  };
  const std::size_t n = particles_.size();
  mix(&n, sizeof n);
  mix(particles_.position.data(), n * sizeof(glm::vec3));
  mix(particles_.velocity.data(), n * sizeof(glm::vec3));
  mix(particles_.direction.data(), n * sizeof(glm::vec3));
  if (air_) air_->hashState(mix);
  return h;
}

// ---- stage 1: neighbours (method.md §1 step 1) ------------------------------
void Solver::findNeighbors() {
  // lists of positions in the search order: density and hair-hair work in it
  grid_->build(particles_.position, 2.0f * params_.h2, threads_, NeighborGrid::ListIndex::SearchOrder);
}

void Solver::measureDensity(PairRecords& records) {
  computeDensity({params_.h2, params_.pressure_stiffness, rest_density_}, *grid_, particles_.position, particles_.mass,
                 records, density_, pressure_, pressure_term_, threads_);
}

void Solver::addHairHairForces(PairRecords& records, PositionRecords xm, std::vector<glm::vec3>& force) const {
  const HairHairInput in{particles_.position, particles_.velocity, particles_.direction, particles_.mass,
                         pressure_term_};
  accumulateHairHair({params_.h2, dc_, dfr_}, *grid_, in, records, xm, force, threads_);
}

void Solver::springFactors(SpringScratch& s) const {
  const SpringParticles p{particles_.position, particles_.velocity, particles_.is_root,
                          cross_section_,      rest_factor_root_,   rest_factor_tip_};
  computeSpringFactors(springSettingsOf(params_), connections_, p, s, threads_);
}

void Solver::springForces(SpringScratch& s, std::vector<glm::vec3>& force) const {
  accumulateSpringForces(springSettingsOf(params_), *sliced_, particles_.size(), s, force, threads_);
}

SpringScratch Solver::springFactorsNow() const {
  SpringScratch s;
  resizeSpringScratch(s, particles_.size(), connections_, *sliced_, true);
  springFactors(s);
  return s;
}

float Solver::entryFactor(const SpringScratch& s, std::size_t i, std::uint32_t e) const {
  const bool tip = e >= connections_.tipBegin(i);
  const std::uint32_t j = connections_.partner[e];
  const float own = tip ? s.factor_tip[i] : s.factor_root[i];
  const float other = tip ? s.factor_root[j] : s.factor_tip[j];
  return pairFactor(own, other, ownWeight(particles_.is_root[i], particles_.is_root[j]));
}

double Solver::stableTimeStep() const {
  SpringScratch s = springFactorsNow();
  double worst = 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.is_root[i]) continue;
    double stiff = 0;
    for (std::uint32_t e = connections_.begin(i); e < connections_.end(i); ++e)
      stiff += static_cast<double>(entryFactor(s, i, e)) * s.k[e];
    worst = std::max(worst, stiff / particles_.mass[i]);
  }
  return worst > 0 ? 2.0 / std::sqrt(worst) : std::numeric_limits<double>::infinity();
}

std::vector<float> Solver::tensileModulus(Side side) const {
  SpringScratch s = springFactorsNow();
  std::vector<float> out(particles_.size(), 0.0f);
  const std::uint8_t want = side == Side::Tip ? 1 : 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    double sum = 0;
    for (std::uint32_t e = connections_.begin(i); e < connections_.end(i); ++e)
      if (connections_.tip_side[e] == want)
        sum += static_cast<double>(connections_.rest_length[e]) * entryFactor(s, i, e) * s.k[e];
    out[i] = static_cast<float>(sum / cross_section_[i]);
  }
  return out;
}

std::vector<glm::vec3> Solver::internalForces() const {
  SpringScratch s = springFactorsNow();
  std::vector<glm::vec3> f(particles_.size());
  springForces(s, f);
  if (params_.hair_hair) {
    PairRecords records;
    addHairHairForces(records, PositionRecords::Make, f);
  }
  return f;
}

void Solver::worldPositions(std::vector<glm::vec3>& out) const {
  const HeadPose p = trajectory_.pose(time_);
  const glm::mat3 r(p.rotation);
  const glm::vec3 c(p.center);
  out.resize(particles_.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = r * particles_.position[i] + c;
}

void Solver::worldVelocities(std::vector<glm::vec3>& out) const {
  const HeadKinematics k = head();
  const glm::mat3 r(k.pose.rotation);
  const glm::vec3 omega(k.angular_velocity), cv(k.velocity);
  out.resize(particles_.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = r * (particles_.velocity[i] + glm::cross(omega, particles_.position[i])) + cv;
}

void Solver::worldDirections(std::vector<glm::vec3>& out) const {
  const glm::mat3 r(trajectory_.pose(time_).rotation);
  out.resize(particles_.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = r * particles_.direction[i];
}

void Solver::worldRootPoints(std::vector<glm::vec3>& out) const {
  const HeadPose p = trajectory_.pose(time_);
  const glm::mat3 r(p.rotation);
  const glm::vec3 c(p.center);
  out.resize(particles_.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = r * particles_.root_point[i] + c;
}

}  // namespace loosehair
