// The step of SPEC §1: neighbours, density, springs, hair-hair, external,
// integrate, strain limit, directions. Every parallel loop owns particle i
// and gathers from i's sorted lists, so the bits of the result do not depend
// on the thread count (SPEC §5 Determinism).
#include "loosehair/solver.hpp"

#include "connection_builder.hpp"
#include "kernel.hpp"
#include "air.hpp"
#include "neighbor_grid.hpp"

#include <glm/geometric.hpp>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

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
  directions += o.directions;
  return *this;
}

// Per-step spring quantities, one entry per connection entry or particle.
struct Solver::Scratch {
  std::vector<float> k;            // k_ij = c_ij W(|x_ij|, h1), eq. 7
  std::vector<float> r;            // |x_ij| when k was computed
  std::vector<float> factor_root;  // a_r,i, eq. 12
  std::vector<float> factor_tip;   // a_t,i, eq. 13
  std::size_t clamped = 0;         // side factors held at the clamp
  const std::uint8_t* is_root = nullptr;

  // alpha_ij of entry e (owner i, partner j), eq. 14: j on i's tip side means
  // i on j's root side. A root particle is part of the head: a pair with a
  // root takes the hair particle's factor alone, so the hair keeps its
  // modulus where it is attached (a root's tip side gathers many connections
  // and would halve it). Computed where it is used, not stored.
  float alpha(std::size_t i, std::uint32_t j, std::uint8_t tip_side) const {
    const float own = tip_side ? factor_tip[i] : factor_root[i];
    const float other = tip_side ? factor_root[j] : factor_tip[j];
    if (is_root[j]) return own;
    if (is_root[i]) return other;
    return 0.5f * (own + other);
  }
  std::size_t active_entries = 0;  // entries with k > 0 (each pair twice)
};

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

using Index = std::int64_t;  // OpenMP loop index

constexpr std::size_t kBodyBlock = 256;

}  // namespace

Solver::Solver(const SimParams& params, Particles particles, std::shared_ptr<const Body> head,
               HeadTrajectory trajectory, double start_time)
    : params_(params),
      particles_(std::move(particles)),
      head_(std::move(head)),
      trajectory_(std::move(trajectory)),
      time_(start_time),
      scratch_(std::make_unique<Scratch>()) {
  const auto problems = validate(params_);
  if (!problems.empty()) {
    std::string msg = "invalid simulation parameters:";
    for (const auto& p : problems) msg += "\n  " + p;
    throw std::invalid_argument(msg);
  }
  if (!head_) throw std::invalid_argument("the solver needs a head body");
  if (!std::isfinite(start_time)) throw std::invalid_argument("start time is not finite");
  particles_.check();
  threads_ = params_.threads > 0 ? params_.threads : std::max(1, omp_get_max_threads());

  const std::size_t n = particles_.size();
  ConnectionOptions copt;
  copt.h1 = params_.h1;
  copt.alignment_threshold = params_.alignment_threshold;
  copt.target_connections = params_.target_connections;
  copt.threads = threads_;
  connections_ = buildConnections(particles_.position, particles_.direction,
                                  particles_.arc_length, particles_.is_root, copt);

  // Cross-sections (eq. 9) and the side factors of the rest state, the
  // reference of the stiffness clamp.
  cross_section_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    cross_section_[i] = std::pow(particles_.mass[i] / params_.material_density, 2.0f / 3.0f);
  inverse_rest_kernel_.resize(connections_.entryCount());
  {
    const CubicKernel k1(params_.h1);
    for (std::size_t e = 0; e < connections_.entryCount(); ++e)
      inverse_rest_kernel_[e] = 1.0f / k1.W(connections_.rest_length[e]);
  }
  rest_factor_root_.assign(n, 0.0f);
  rest_factor_tip_.assign(n, 0.0f);
  {
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

  grid_ = std::make_unique<NeighborGrid>();
  density_.assign(n, 0.0f);
  pressure_.assign(n, 0.0f);
  force_.assign(n, glm::vec3(0.0f));
  integrated_position_.assign(n, glm::vec3(0.0f));
  limited_position_.assign(n, glm::vec3(0.0f));
  body_phi_.assign(n, 0.0f);
  body_normal_.assign(n, glm::vec3(0.0f));
  scratch_->k.assign(connections_.entryCount(), 0.0f);
  scratch_->r.assign(connections_.entryCount(), 0.0f);
  scratch_->factor_root.assign(n, 0.0f);
  scratch_->factor_tip.assign(n, 0.0f);

  // Initial density: rest density rho0 and the kernel-free collision and
  // friction coefficients (SPEC §4: d_c W / m summed over neighbours is about
  // d_c rho / m^2, so d_c = rate * m^2 / rho removes `rate` of the relative
  // normal velocity per second).
  findNeighbors();
  computeDensity();
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
  const double mean_mass = hair_count ? mass_sum / static_cast<double>(hair_count) : 0.0;
  rest_density_ = params_.rest_density_scale * median;
  if (median > 0) {
    dc_ = static_cast<float>(params_.collision_rate * mean_mass * mean_mass / median);
    dfr_ = static_cast<float>(params_.friction_rate * mean_mass * mean_mass / median);
  }

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
}

void Solver::setTimeStep(double dt) {
  SimParams p = params_;
  p.time_step = dt;
  const auto problems = validate(p);
  if (!problems.empty()) throw std::invalid_argument(problems.front());
  params_ = p;
}

void Solver::setKinematicState(std::span<const glm::vec3> position,
                               std::span<const glm::vec3> velocity,
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
  computeDensity();
  // A reset may leave particles inside the body or over-stretched; the
  // first step moves them back without turning the move into velocity.
  absorb_corrections_ = true;
}

void Solver::setThreadCount(int threads) {
  if (threads < 1 || threads > 1024)
    throw std::invalid_argument("thread count " + std::to_string(threads) + " is not in [1, 1024]");
  threads_ = threads;
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

// ---- stage 1: neighbours ---------------------------------------------------
void Solver::findNeighbors() {
  grid_->build(particles_.position, 2.0f * params_.h2, threads_);
}

// ---- stage 2: density, eq. 1 -----------------------------------------------
void Solver::computeDensity() {
  const CubicKernel k2(params_.h2);
  const auto& x = particles_.position;
  const auto& m = particles_.mass;
  const float w0 = k2.W(0.0f);
  const float ka = params_.pressure_stiffness;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index ii = 0; ii < static_cast<Index>(x.size()); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    float rho = m[i] * w0;
    for (std::uint32_t j : grid_->neighbors(i)) rho += m[j] * k2.W(glm::length(x[j] - x[i]));
    density_[i] = rho;
    pressure_[i] = ka * (rho - rest_density_);
  }
}

// ---- stage 3a: loose spring coefficients, eqs. 7, 10-14 ---------------------
void Solver::computeSpringFactors(Scratch& s) const {
  const CubicKernel k1(params_.h1);
  const auto& x = particles_.position;
  const auto& c = connections_;
  const double young = params_.youngs_modulus;
  const float clamp = params_.stiffness_clamp;
  const auto& root = particles_.is_root;
  const Index n = static_cast<Index>(x.size());
  std::size_t clamped = 0, active = 0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(+ : clamped, active)
  for (Index ii = 0; ii < n; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    float sr = 0, st = 0;
    for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
      const float r = glm::length(x[c.partner[e]] - x[i]);
      const float k = c.strength[e] * k1.W(r);
      s.k[e] = k;
      s.r[e] = r;
      active += k > 0.0f ? 1 : 0;
      (c.tip_side[e] ? st : sr) += c.rest_length[e] * k;
    }
    const double ea = young * cross_section_[i];
    auto factor = [&](float sum, float rest) {
      if (!(sum > 0.0f)) return 0.0f;
      const float a = static_cast<float>(ea / sum), limit = clamp * rest;
      if (a > limit) {
        ++clamped;
        return limit;
      }
      return a;
    };
    s.factor_root[i] = factor(sr, rest_factor_root_[i]);
    s.factor_tip[i] = factor(st, rest_factor_tip_[i]);
  }
  s.clamped = clamped;
  s.active_entries = active;
  s.is_root = root.data();
}

// ---- stage 3b: damped spring forces (SPEC §3.2) ----------------------------
void Solver::accumulateSpringForces(Scratch& s, std::vector<glm::vec3>& force) const {
  const auto& x = particles_.position;
  const auto& v = particles_.velocity;
  const auto& c = connections_;
  const float gamma = params_.spring_damping;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index ii = 0; ii < static_cast<Index>(x.size()); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    glm::vec3 f(0.0f);
    for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
      if (s.k[e] == 0.0f) continue;
      const std::uint32_t j = c.partner[e];
      const float ak = s.alpha(i, j, c.tip_side[e]) * s.k[e];
      const glm::vec3 xij = x[j] - x[i];
      const float r = s.r[e];  // |x_ij|, from computeSpringFactors
      if (!(r > 0.0f)) continue;
      const glm::vec3 n = xij / r;
      const float stretch = r - c.rest_length[e];
      const float closing = glm::dot(v[j] - v[i], n);
      f += (ak * (stretch + gamma * closing)) * n;
    }
    force[i] = f;
  }
}

// ---- stage 3c: hair-hair pressure, collision, friction (SPEC §4) -----------
void Solver::accumulateHairHairForces(std::vector<glm::vec3>& force) const {
  const CubicKernel k2(params_.h2);
  const auto& x = particles_.position;
  const auto& v = particles_.velocity;
  const auto& t = particles_.direction;
  const auto& m = particles_.mass;
  const float dc = dc_, dfr = dfr_;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index ii = 0; ii < static_cast<Index>(x.size()); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    const float pi_term = pressure_[i] / (density_[i] * density_[i]);
    glm::vec3 f(0.0f);
    for (std::uint32_t j : grid_->neighbors(i)) {
      const glm::vec3 xij = x[j] - x[i];
      const float r2 = glm::dot(xij, xij);
      if (!(r2 > 0.0f)) continue;
      const float r = std::sqrt(r2);
      // eq. 16: -m_i m_j (P_i/rho_i^2 + P_j/rho_j^2) grad_i W, grad_i W = -dW/dr x_ij / r
      const float pj_term = pressure_[j] / (density_[j] * density_[j]);
      f += (m[i] * m[j] * (pi_term + pj_term) * k2.dWdr(r) / r) * xij;

      // eq. 17: collision direction t_i x t_j; for near-parallel hairs the
      // part of x_ij normal to their mean direction (our symmetric choice,
      // so that the pair force is exactly opposite on j).
      glm::vec3 dn = glm::cross(t[i], t[j]);
      float dn2 = glm::dot(dn, dn);
      if (dn2 < 1e-6f) {
        const glm::vec3 tm = glm::dot(t[i], t[j]) >= 0.0f ? t[i] + t[j] : t[i] - t[j];
        const float tm2 = glm::dot(tm, tm);
        if (!(tm2 > 0.0f)) continue;
        dn = xij - (glm::dot(xij, tm) / tm2) * tm;
        dn2 = glm::dot(dn, dn);
        if (dn2 < 1e-6f * r2) continue;
      }
      dn *= 1.0f / std::sqrt(dn2);
      const glm::vec3 vij = v[j] - v[i];
      const float vn = glm::dot(vij, dn);
      if (glm::dot(xij, dn) * vn >= 0.0f) continue;  // not approaching
      const float w = k2.W(r);
      f += (dc * w * vn) * dn;                 // eq. 17, inelastic collision
      f += (dfr * w) * (vij - vn * dn);        // eq. 18, friction (approaching pairs only)
    }
    force[i] += f;
  }
}

// ---- bodies (SPEC §5) ---------------------------------------------------------
// A world body seen from the head frame at one time: q = M x + d in the
// body's frame, n_head = M^T n_body.
struct Solver::BodyFrame {
  const Body* body = nullptr;
  glm::mat3 m{1.0f};
  glm::vec3 d{0.0f};
  // for the surface velocity: world velocity vo + Ro (wo x q)
  glm::mat3 ro{1.0f}, rh_t{1.0f};
  glm::vec3 vo{0.0f}, wo{0.0f};
};

void Solver::addWorldBody(std::shared_ptr<const Body> body, HeadTrajectory motion, double begin,
                          double end, bool obstacle) {
  if (!body) throw std::invalid_argument("addWorldBody: no body");
  if (std::isnan(begin) || std::isnan(end) || !(begin < end))
    throw std::invalid_argument("addWorldBody: the active time interval is empty");
  world_bodies_.push_back({std::move(body), std::move(motion), begin, end, obstacle});
}

void Solver::placeBodies(double t, std::vector<BodyFrame>& frames, HeadKinematics& head,
                         bool include_obstacles) const {
  head = trajectory_.kinematics(t);
  frames.clear();
  for (const auto& wb : world_bodies_) {
    if (!(t >= wb.begin && t < wb.end)) continue;
    if (wb.obstacle && !include_obstacles) continue;
    const HeadKinematics o = wb.motion.kinematics(t);
    const glm::dmat3 ro_t = glm::transpose(o.pose.rotation);
    BodyFrame f;
    f.body = wb.body.get();
    f.m = glm::mat3(ro_t * head.pose.rotation);
    f.d = glm::vec3(ro_t * (head.pose.center - o.pose.center));
    f.ro = glm::mat3(o.pose.rotation);
    f.rh_t = glm::mat3(glm::transpose(head.pose.rotation));
    f.vo = glm::vec3(o.velocity);
    f.wo = glm::vec3(o.angular_velocity);
    frames.push_back(f);
  }
}

void Solver::queryBodies(const std::vector<BodyFrame>& frames, const HeadKinematics& head,
                         const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal,
                         glm::vec3* surface_velocity) const {
  head_->signedDistance(x, n, phi, normal);
  if (surface_velocity)
    for (std::size_t k = 0; k < n; ++k) surface_velocity[k] = glm::vec3(0.0f);
  if (frames.empty()) return;
  glm::vec3 q[kBodyBlock], nb[kBodyBlock];
  float pb[kBodyBlock];
  const glm::vec3 omega(head.angular_velocity);
  const glm::vec3 frame_vel(glm::transpose(head.pose.rotation) * head.velocity);
  for (std::size_t b = 0; b < n; b += kBodyBlock) {
    const std::size_t len = std::min(kBodyBlock, n - b);
    for (const BodyFrame& f : frames) {
      for (std::size_t k = 0; k < len; ++k) q[k] = f.m * x[b + k] + f.d;
      f.body->signedDistance(q, len, pb, nb);
      for (std::size_t k = 0; k < len; ++k) {
        if (!(pb[k] < phi[b + k])) continue;
        phi[b + k] = pb[k];
        normal[b + k] = glm::transpose(f.m) * nb[k];
        if (surface_velocity) {
          const glm::vec3 vw = f.vo + f.ro * glm::cross(f.wo, q[k]);
          surface_velocity[b + k] = f.rh_t * vw - glm::cross(omega, x[b + k]) - frame_vel;
        }
      }
    }
  }
}

void Solver::bodyDistance(std::span<const glm::vec3> points, double t,
                          std::vector<float>& phi, bool include_obstacles) const {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(t, frames, head, include_obstacles);
  phi.resize(points.size());
  std::vector<glm::vec3> nrm(points.size());
  queryBodies(frames, head, points.data(), points.size(), phi.data(), nrm.data(), nullptr);
}

// ---- wind (SPEC §5) -----------------------------------------------------------
void Solver::setWind(const WindParams& wind) {
  auto air = std::make_unique<AirSystem>(wind);
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(time_, frames, head);
  air->fill(time_, head, [&](const glm::vec3* w, std::size_t n, float* phi) {
    worldBodyDistance(frames, head, w, n, phi);
  });
  air_ = std::move(air);
}

void Solver::worldBodyDistance(const std::vector<BodyFrame>& frames, const HeadKinematics& head,
                               const glm::vec3* world, std::size_t n, float* phi) const {
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  std::vector<glm::vec3> local(n), nrm(n);
  for (std::size_t k = 0; k < n; ++k) local[k] = glm::vec3(rt * (glm::dvec3(world[k]) - head.pose.center));
  queryBodies(frames, head, local.data(), n, phi, nrm.data(), nullptr);
}

std::size_t Solver::airCount() const { return air_ ? air_->size() : 0; }

void Solver::worldAirPositions(std::vector<glm::vec3>& out) const {
  out.clear();
  if (!air_) return;
  const HeadPose pose = trajectory_.pose(time_);
  for (const auto& x : air_->positions()) out.emplace_back(pose.rotation * glm::dvec3(x) + pose.center);
}

void Solver::worldAirVelocities(std::vector<glm::vec3>& out) const {
  out.clear();
  if (!air_) return;
  const HeadKinematics k = trajectory_.kinematics(time_);
  const auto& x = air_->positions();
  const auto& v = air_->velocities();
  for (std::size_t a = 0; a < x.size(); ++a) {
    const glm::dvec3 u = glm::dvec3(v[a]) + glm::cross(k.angular_velocity, glm::dvec3(x[a]));
    out.emplace_back(k.pose.rotation * u + k.velocity);
  }
}

std::span<const float> Solver::airDensity() const {
  return air_ ? air_->density() : std::span<const float>();
}

double Solver::airStableTimeStep() const { return air_ ? air_->stableTimeStep() : INFINITY; }

// ---- the step ---------------------------------------------------------------
void Solver::step() {
  const float dt = static_cast<float>(params_.time_step);
  const std::size_t n = particles_.size();
  auto& x = particles_.position;
  auto& v = particles_.velocity;
  const auto& m = particles_.mass;
  const auto& root = particles_.is_root;
  Scratch& s = *scratch_;
  StageTimes st;
  auto t0 = Clock::now();

  findNeighbors();
  auto t1 = Clock::now();
  st.neighbors = seconds(t0, t1);

  computeDensity();
  t0 = Clock::now();
  st.density = seconds(t1, t0);

  computeSpringFactors(s);
  accumulateSpringForces(s, force_);
  t1 = Clock::now();
  st.springs = seconds(t0, t1);

  if (params_.hair_hair) accumulateHairHairForces(force_);
  t0 = Clock::now();
  st.hair_hair = seconds(t1, t0);

  // ---- wind: air neighbours, density, pressure, viscosity and the hair-air
  // drag (SPEC §5) -------------------------------------------------------------
  if (air_) {
    air_->setPose(trajectory_.pose(time_));
    air_->findNeighbors(x, threads_);
    air_->accumulateForces(x, v, m, root, force_, dt, threads_);
    t1 = Clock::now();
    st.air += seconds(t0, t1);
    t0 = t1;
  }

  // ---- external forces in the head frame (SPEC §5) --------------------------
  const HeadKinematics head = trajectory_.kinematics(time_);
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 gravity(rt * glm::dvec3(params_.gravity));
  const glm::vec3 frame_accel(rt * head.acceleration);  // R^T c''
  const glm::vec3 frame_vel(rt * head.velocity);        // R^T c'
  const glm::vec3 omega(head.angular_velocity), alpha(head.angular_acceleration);
  const float drag = params_.air_drag;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index ii = 0; ii < static_cast<Index>(n); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    if (root[i]) continue;
    const glm::vec3 r = x[i], u = v[i];
    const glm::vec3 inertial = frame_accel + glm::cross(alpha, r) + 2.0f * glm::cross(omega, u) +
                               glm::cross(omega, glm::cross(omega, r));
    const glm::vec3 world_velocity = u + glm::cross(omega, r) + frame_vel;
    force_[i] += m[i] * (gravity - inertial - drag * world_velocity);
  }
  t1 = Clock::now();
  st.external = seconds(t0, t1);

  // ---- integrate: symplectic Euler with the inelastic, frictional body
  // contact applied to the new velocity (SPEC §5 body collisions) ------------
  const float thickness = params_.contact_thickness, mu = params_.body_friction;
  std::size_t contacts = 0;
  std::vector<BodyFrame> frames;
  HeadKinematics head_now;
  placeBodies(time_, frames, head_now);
  const HeadKinematics head_now_start = head_now;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(+ : contacts)
  for (Index bb = 0; bb < static_cast<Index>((n + kBodyBlock - 1) / kBodyBlock); ++bb) {
    const std::size_t b = static_cast<std::size_t>(bb) * kBodyBlock;
    const std::size_t e = std::min(n, b + kBodyBlock);
    glm::vec3 surface[kBodyBlock];
    queryBodies(frames, head_now, &x[b], e - b, &body_phi_[b], &body_normal_[b], surface);
    for (std::size_t i = b; i < e; ++i) {
      if (root[i]) continue;
      glm::vec3 vi = v[i] + (dt / m[i]) * force_[i];
      if (body_phi_[i] < thickness) {
        // The response acts on the velocity relative to the body's surface.
        const glm::vec3 us = surface[i - b];
        const glm::vec3 nrm = body_normal_[i];
        const glm::vec3 vr = vi - us;
        const float vn = glm::dot(vr, nrm);
        if (vn < 0.0f) {
          ++contacts;
          glm::vec3 vt = vr - vn * nrm;  // inelastic: normal approach removed
          const float vt_len = glm::length(vt);
          const float slip = vt_len - mu * (-vn);  // Coulomb: |dv_t| <= mu |dv_n|
          vi = us + (slip > 0.0f ? vt * (slip / vt_len) : glm::vec3(0.0f));
        }
      }
      v[i] = vi;
      x[i] += dt * vi;
      integrated_position_[i] = x[i];
    }
  }
  t0 = Clock::now();
  st.integrate = seconds(t1, t0);

  // ---- strain limit (SPEC §5, §9) and no particle left inside the body -----
  std::size_t limited = 0;
  if (params_.strain_limit && params_.strain_limit_iterations > 0) {
    const CubicKernel k1(params_.h1);
    const float support2 = k1.support2();
    const float max_len_scale = 1.0f + params_.max_strain;
    const auto& c = connections_;
    for (int it = 0; it < params_.strain_limit_iterations; ++it) {
      std::size_t count = 0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(+ : count)
      for (Index ii = 0; ii < static_cast<Index>(n); ++ii) {
        const auto i = static_cast<std::size_t>(ii);
        limited_position_[i] = x[i];
        if (root[i]) continue;
        glm::vec3 shift(0.0f);
        int active = 0;
        const float wi = 1.0f / m[i];
        for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
          const std::uint32_t j = c.partner[e];
          const glm::vec3 xij = x[j] - x[i];
          const float r2 = glm::dot(xij, xij);
          const float limit = max_len_scale * c.rest_length[e];
          // Most connections are not over-stretched: decide on squares and
          // take the root only for the few that are.
          if (!(r2 > limit * limit) || !(r2 < support2)) continue;  // slack connections stay free
          const float r = std::sqrt(r2);
          if (!(r > limit)) continue;
          // The correction follows the spring's looseness, so a connection
          // that is letting go (hair splitting) is not pulled back hard.
          const float looseness = std::min(1.0f, k1.W(r) * inverse_rest_kernel_[e]);
          const float wj = root[j] ? 0.0f : 1.0f / m[j];
          shift += (looseness * (r - limit) * wi / (wi + wj) / r) * xij;
          ++active;
        }
        if (active > 0) {
          limited_position_[i] = x[i] + shift / static_cast<float>(active);
          ++count;
        }
      }
      x.swap(limited_position_);
      if (it == 0) limited = count;
      if (count == 0) break;
    }
  }

  // Tethers (long-range attachments; our addition to SPEC §5's strain limit):
  // a particle may be no further from its own root point than its arc length
  // allows, |x_i - r_i| <= (1 + slack) s_i. This is the no-stretch promise
  // itself, enforced per particle in O(N) without adding shear stiffness, so
  // the springs can be soft enough for the hair to bend and swing.
  if (params_.tether) {
    const auto& rp = particles_.root_point;
    const auto& sarc = particles_.arc_length;
    const float scale = 1.0f + params_.tether_slack;
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (Index ii = 0; ii < static_cast<Index>(n); ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      if (root[i]) continue;
      const glm::vec3 d = x[i] - rp[i];
      const float dist = glm::length(d);
      const float reach = scale * sarc[i];
      if (dist > reach) x[i] = rp[i] + (reach / dist) * d;
    }
  }

  // Project what is still inside the body to its surface and take the new
  // velocity from the corrected positions (no added normal speed, so nothing
  // is thrown off the body).
  // Several bodies (head, torso, obstacles) may meet in a crease, where
  // leaving one can mean entering another: a few rounds settle it.
  placeBodies(time_ + params_.time_step, frames, head_now);
  std::vector<BodyFrame> solid_frames;  // without obstacles: the last round
  placeBodies(time_ + params_.time_step, solid_frames, head_now, false);
  const int rounds = frames.empty() ? 1 : 3;
  const bool has_obstacles = solid_frames.size() != frames.size();
  const bool absorb = absorb_corrections_;
  absorb_corrections_ = false;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index bb = 0; bb < static_cast<Index>((n + kBodyBlock - 1) / kBodyBlock); ++bb) {
    const std::size_t b = static_cast<std::size_t>(bb) * kBodyBlock;
    const std::size_t e = std::min(n, b + kBodyBlock);
    glm::vec3 surface[kBodyBlock];
    bool pushed[kBodyBlock] = {};
    glm::vec3 push_normal[kBodyBlock];
    for (int round = 0; round < rounds + (has_obstacles ? 1 : 0); ++round) {
      queryBodies(round < rounds ? frames : solid_frames, head_now, &x[b], e - b, &body_phi_[b],
                  &body_normal_[b], surface);
      bool any = false;
      for (std::size_t i = b; i < e; ++i) {
        if (root[i] || !(body_phi_[i] < 0.0f)) continue;
        x[i] -= body_phi_[i] * body_normal_[i];
        if (!pushed[i - b]) push_normal[i - b] = body_normal_[i];
        pushed[i - b] = true;
        any = true;
      }
      if (!any) break;
    }
    for (std::size_t i = b; i < e; ++i) {
      if (root[i]) continue;
      glm::vec3 vi = v[i];
      if (x[i] != integrated_position_[i] && !absorb) vi += (x[i] - integrated_position_[i]) / dt;
      if (pushed[i - b]) {
        const glm::vec3 nrm = push_normal[i - b];
        const float vn = glm::dot(vi - surface[i - b], nrm);
        if (vn > 0.0f) vi -= vn * nrm;  // the push-out is not a velocity
      }
      v[i] = vi;
    }
  }
  t1 = Clock::now();
  st.strain_limit = seconds(t0, t1);

  // ---- wind: move the air, keep it out of the bodies (free slip), emit
  // upwind and remove what left the box ---------------------------------------
  if (air_) {
    air_->integrate(time_, dt, head_now_start, threads_);
    auto& ax = air_->positions();
    auto& av = air_->velocities();
    const std::size_t na = ax.size();
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (Index bb = 0; bb < static_cast<Index>((na + kBodyBlock - 1) / kBodyBlock); ++bb) {
      const std::size_t b = static_cast<std::size_t>(bb) * kBodyBlock;
      const std::size_t e = std::min(na, b + kBodyBlock);
      float phi[kBodyBlock];
      glm::vec3 nrm[kBodyBlock], surface[kBodyBlock];
      queryBodies(frames, head_now, &ax[b], e - b, phi, nrm, surface);
      for (std::size_t a = b; a < e; ++a) {
        const std::size_t k = a - b;
        if (!(phi[k] < 0.0f)) continue;
        ax[a] -= phi[k] * nrm[k];
        const float vn = glm::dot(av[a] - surface[k], nrm[k]);
        if (vn < 0.0f) av[a] -= vn * nrm[k];
      }
    }
    air_->emitAndRemove(time_ + params_.time_step, dt, head_now,
                        [&](const glm::vec3* w, std::size_t count, float* phi) {
                          worldBodyDistance(frames, head_now, w, count, phi);
                        });
    const auto t2 = Clock::now();
    st.air += seconds(t1, t2);
    t1 = t2;
  }

  // ---- hair directions, eq. 15 ----------------------------------------------
  {
    auto& dir = particles_.direction;
    const auto& c = connections_;
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (Index ii = 0; ii < static_cast<Index>(n); ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      if (root[i]) continue;
      const glm::vec3 ti = dir[i];
      glm::vec3 sum(0.0f);
      for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
        if (!(s.k[e] > 0.0f)) continue;
        const std::uint32_t j = c.partner[e];
        const float w = s.alpha(i, j, c.tip_side[e]) * s.k[e];
        if (!(w > 0.0f)) continue;
        const glm::vec3 xij = x[j] - x[i];
        const float r = glm::length(xij);
        if (!(r > 0.0f)) continue;
        const glm::vec3 xhat = xij / r;
        // Rotate x_ij by its rest angle towards t_i: cos(theta) xhat + sin(theta) t_perp.
        const glm::vec3 perp = ti - glm::dot(ti, xhat) * xhat;
        const float perp_len = glm::length(perp);
        glm::vec3 tij;
        if (perp_len > 1e-6f)
          tij = c.cos_rest[e] * xhat + (c.sin_rest[e] / perp_len) * perp;
        else
          tij = c.cos_rest[e] >= 0.0f ? xhat : -xhat;
        sum += w * tij;
      }
      const float len = glm::length(sum);
      if (len > 0.0f) dir[i] = sum / len;
    }
  }
  // Never go on silently with a broken state.
  std::size_t broken = 0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(+ : broken)
  for (Index ii = 0; ii < static_cast<Index>(n); ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    const glm::vec3 a = x[i], b = v[i], c = particles_.direction[i];
    const float probe = a.x + a.y + a.z + b.x + b.y + b.z + c.x + c.y + c.z;
    broken += std::isfinite(probe) ? 0 : 1;
  }
  if (broken > 0) {
    std::size_t first = 0;
    for (; first < n; ++first)
      if (!std::isfinite(x[first].x + x[first].y + x[first].z + v[first].x + v[first].y +
                         v[first].z))
        break;
    throw SimulationError("the simulation became unstable at t = " + std::to_string(time_) +
                          " s: " + std::to_string(broken) +
                          " particles have non-finite state (first: " + std::to_string(first) +
                          "); reduce the time step or the stiffness");
  }
  st.directions = seconds(t1, Clock::now());

  time_ += params_.time_step;
  stats_.last = st;
  stats_.sum += st;
  ++stats_.steps;
  stats_.neighbor_pairs = grid_->pairCount();
  stats_.clamped_sides = s.clamped;
  stats_.body_contacts = contacts;
  stats_.strain_limited = limited;
  stats_.active_connections = s.active_entries / 2;
  stats_.air_particles = air_ ? air_->size() : 0;
  stats_.hair_air_pairs = air_ ? air_->hairAirPairs() : 0;
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
  if (air_) {
    const std::size_t na = air_->size();
    mix(&na, sizeof na);
    mix(air_->positions().data(), na * sizeof(glm::vec3));
    mix(air_->velocities().data(), na * sizeof(glm::vec3));
  }
  return h;
}

Solver::Scratch Solver::springFactorsNow() const {
  Scratch s;
  s.k.resize(connections_.entryCount());
  s.r.resize(connections_.entryCount());
  s.factor_root.resize(particles_.size());
  s.factor_tip.resize(particles_.size());
  computeSpringFactors(s);
  return s;
}

double Solver::stableTimeStep() const {
  Scratch s = springFactorsNow();
  double worst = 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.is_root[i]) continue;
    double stiff = 0;
    for (std::uint32_t e = connections_.begin(i); e < connections_.end(i); ++e)
      stiff += static_cast<double>(s.alpha(i, connections_.partner[e], connections_.tip_side[e])) *
               s.k[e];
    worst = std::max(worst, stiff / particles_.mass[i]);
  }
  return worst > 0 ? 2.0 / std::sqrt(worst) : std::numeric_limits<double>::infinity();
}

std::vector<float> Solver::tensileModulus(Side side) const {
  Scratch s = springFactorsNow();
  std::vector<float> out(particles_.size(), 0.0f);
  const std::uint8_t want = side == Side::Tip ? 1 : 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    double sum = 0;
    for (std::uint32_t e = connections_.begin(i); e < connections_.end(i); ++e)
      if (connections_.tip_side[e] == want)
        sum += static_cast<double>(connections_.rest_length[e]) *
               s.alpha(i, connections_.partner[e], connections_.tip_side[e]) * s.k[e];
    out[i] = static_cast<float>(sum / cross_section_[i]);
  }
  return out;
}

std::vector<glm::vec3> Solver::internalForces() const {
  Scratch s = springFactorsNow();
  std::vector<glm::vec3> f(particles_.size());
  accumulateSpringForces(s, f);
  if (params_.hair_hair) accumulateHairHairForces(f);
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
