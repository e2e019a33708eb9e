// The step of method.md §1: neighbours, density, springs, hair-hair, external,
// integrate, strain limit, directions. Every parallel loop owns particle i
// and gathers from i's sorted lists, so the bits of the result do not depend
// on the thread count (method.md §5 Determinism).
#include "loosehair/solver.hpp"
#include "loosehair/param_table.hpp"

#include "connection_builder.hpp"
#include "connection_slices.hpp"
#include "hair_chain.hpp"
#include "implicit_springs.hpp"
#include "kernel.hpp"
#include "air.hpp"
#include "air_grid.hpp"
#include "neighbor_grid.hpp"
#include "pair_columns.hpp"
#include "parallel.hpp"
#include "solver_scratch.hpp"
#include "solver/connection_passes.hpp"
#include "solver/step_context.hpp"
#include "solver/strain_limit.hpp"
#include "solver/tethers.hpp"
#include "solver/directions.hpp"
#include "shape_keeping.hpp"
#include "tether.hpp"
#include "thread_choice.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <numbers>
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
  tethers += o.tethers;
  body_contacts += o.body_contacts;
  directions += o.directions;
  return *this;
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

constexpr std::size_t kBodyBlock = 256;
using tether::kSkin;
// m: what a particle's clearance must exceed to skip the exact query, room
// for the rounding of positions and body placements (~1e-7 m) many times over
constexpr float kClearMargin = 2e-5f;
// m/s: the fastest approach to a body that speculative contacts catch
// within one step (faster ones are left to the projection)
constexpr float kSpeculativeSpeed = 2.0f;

}  // namespace

Solver::Solver(const SimParams& params, Particles particles, std::shared_ptr<const Body> head,
               HeadTrajectory trajectory, double start_time)
    : params_(params),
      particles_(std::move(particles)),
      head_(std::move(head)),
      trajectory_(std::move(trajectory)),
      time_(start_time),
      scratch_(std::make_unique<Scratch>()),
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
  connections_ = buildConnections(particles_.position, particles_.direction, particles_.arc_length,
                                  particles_.is_root, copt);
  chain_ = std::make_unique<HairChain>(connections_, particles_.is_root, particles_.arc_length,
                                       particles_.root_point, params_.h1);
  longest_hair_ = 0.0f;
  for (float a : particles_.arc_length) longest_hair_ = std::max(longest_hair_, a);

  // Cross-sections (eq. 9) and the side factors of the rest state, the
  // reference of the stiffness clamp.
  cross_section_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    cross_section_[i] = std::pow(particles_.mass[i] / params_.material_density, 2.0f / 3.0f);
  computeRestFactors();

  inverse_mass_.resize(n);  // 0 for a root (fixed); no root-root connections
  for (std::size_t i = 0; i < n; ++i)
    inverse_mass_[i] = particles_.is_root[i] ? 0.0f : 1.0f / particles_.mass[i];
  *sliced_ = sliceForPasses(connections_);

  grid_ = std::make_unique<NeighborGrid>();
  density_.assign(n, 0.0f);
  pressure_.assign(n, 0.0f);
  pressure_term_.assign(n, 0.0f);
  force_.assign(n, glm::vec3(0.0f));
  body_phi_.assign(n, 0.0f);
  body_normal_.assign(n, glm::vec3(0.0f));
  step_ = std::make_unique<StepContext>();
  step_->resize(n);
  resizeScratch(*scratch_, false);

  // Initial density: rest density rho0 and the kernel-free collision and
  // friction coefficients (method.md §4: d_c W / m summed over neighbours is about
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
  report_.mean_degree =
      hair_count ? static_cast<double>(degree_sum) / static_cast<double>(hair_count) : 0.0;
  report_.stable_time_step = stableTimeStep();
  if (params_.shape_keeping > 0.0f) {
    // the pressure terms with the rest density just set (the first
    // computeDensity ran before it was known)
    computeDensity();
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
    throw std::invalid_argument(std::string(info.name) + " cannot change in a running simulation (" + std::to_string(was) +
                                " to " + std::to_string(now) + "): it applies on restart");
  }
  if (p.shape_keeping > 0.0f && !shape_)
    throw std::invalid_argument("shape_keeping cannot be turned on in a running simulation (the styled rest state is "
                                "set up when it starts): it applies on restart");
  if (shape_ && p.shape_keeping > 0.0f && shape_->fastestWith(p.shape_keeping) * p.time_step > kMaxHoldPhasePerStep)
    throw std::invalid_argument("shape_keeping = " + std::to_string(p.shape_keeping) + " Hz is too strong for time_step = " +
                                std::to_string(p.time_step) + " s");
  const bool stiffness = p.youngs_modulus != params_.youngs_modulus;
  if (!p.implicit_springs && (params_.implicit_springs || stiffness)) {
    // explicit springs from now on: the step must be within their stable
    // limit, which scales as 1/sqrt(E)
    const double limit = stableTimeStep() * std::sqrt(static_cast<double>(params_.youngs_modulus) /
                                                      static_cast<double>(p.youngs_modulus));
    if (p.time_step > limit)
      throw std::invalid_argument("implicit_springs = 0 (explicit springs) with youngs_modulus = " +
                                  std::to_string(p.youngs_modulus) + " needs a time step of at most " +
                                  std::to_string(limit * 1e3) + " ms, and this simulation steps " +
                                  std::to_string(p.time_step * 1e3) +
                                  " ms: keep the implicit springs, or restart with more substeps");
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

// ---- stage 1: neighbours ---------------------------------------------------
void Solver::findNeighbors() {
  // lists of positions in the search order: density and hair-hair work in it
  grid_->build(particles_.position, 2.0f * params_.h2, threads_,
               NeighborGrid::ListIndex::SearchOrder);
}

// ---- stage 2: density, eq. 1 -----------------------------------------------
// A blocked loop (pair_columns.hpp).
namespace {

// What the density and hair-hair gathers read of a partner, as 16-byte
// records in the neighbour search's order (record k is particle
// searchOrder()[k], the lists hold these positions): (x, m) for both,
// (v, P/rho^2) and (t, 0) for hair-hair. The search sorts the particles by
// cell, so a particle's partners lie in a few short runs of records, near
// its own, however the hair has moved since it was made. Four partners'
// records are loaded whole and transposed into the columns (4 loads and a
// few shuffles where a scalar gather makes 12 loads and 12 stores). The
// calling thread's buffers, shared with its team (parallel.hpp), so that const
// queries from several threads stay safe.
struct HairRecords {
  std::vector<glm::vec4> xm, vp, tt;
};
HairRecords& hairRecords() {
  static thread_local HairRecords records;
  return records;
}

// out[k] = (a[i], w[i]), or (a[i], 0) without w, i = ord[k], for k in
// [k0, k1): the calling thread's part of the search order.
void fillRecords(std::vector<glm::vec4>& out, const glm::vec3* a, const float* w,
                 const std::uint32_t* ord, std::size_t k0, std::size_t k1) {
  glm::vec4* o = out.data();
  constexpr std::size_t kAhead = 32;  // ord-indirect: the hardware cannot see these coming
  for (std::size_t k = k0; k < k1; ++k) {
    if (k + kAhead < k1) {
      __builtin_prefetch(&a[ord[k + kAhead]]);
      if (w) __builtin_prefetch(&w[ord[k + kAhead]]);
    }
    const std::uint32_t i = ord[k];
    o[k] = glm::vec4(a[i], w ? w[i] : 0.0f);
  }
}

// The calling thread's part of the search order in the density and
// hair-hair passes: contiguous (the note above kWindowChunks), with about
// as many pairs as the other threads' parts. It starts at a multiple of
// kPartGrain, so the blocks of kPairBlock positions are those of one thread.
static_assert(NeighborGrid::kPartGrain % kPairBlock == 0);
std::pair<std::size_t, std::size_t> pairLoopPart(const NeighborGrid& grid) {
  return grid.pairBalancedPart(parallel::threadIndex(), parallel::threadCount());
}

#if defined(__SSE2__)
// The partners j of a group of 4 entries of a list of `count` (count > g):
// a short last group repeats its last partner, so its extra lanes hold
// valid values, written past the group's end and overwritten by the next
// particle's entries (the columns leave room for 3 more).
struct PartnerGroup {
  std::uint32_t j[4];
  PartnerGroup(std::span<const std::uint32_t> list, std::size_t g) {
    const std::size_t last = list.size() - 1;
    for (std::size_t lane = 0; lane < 4; ++lane) j[lane] = list[std::min(g + lane, last)];
  }
};
// The records of a group's partners, transposed: c[0..3] hold the x, y, z
// and w components of the four.
inline void transposedRecords(const glm::vec4* rec, const PartnerGroup& p, __m128 c[4]) {
  for (int lane = 0; lane < 4; ++lane) c[lane] = _mm_loadu_ps(&rec[p.j[lane]].x);
  _MM_TRANSPOSE4_PS(c[0], c[1], c[2], c[3]);
}
// The four components of record r, each in all lanes.
inline void broadcastRecord(const glm::vec4& r, __m128 c[4]) {
  const __m128 v = _mm_loadu_ps(&r.x);
  c[0] = _mm_shuffle_ps(v, v, 0x00);
  c[1] = _mm_shuffle_ps(v, v, 0x55);
  c[2] = _mm_shuffle_ps(v, v, 0xaa);
  c[3] = _mm_shuffle_ps(v, v, 0xff);
}
#endif

LOOSEHAIR_PAIR_KERNEL
void densityPairTerms(std::size_t pairs, float inv_h, float norm_w, const float* __restrict r2,
                      const float* __restrict mj, float* __restrict rho) {
  for (std::size_t q = 0; q < pairs; ++q) {
    rho[q] = mj[q] * cubicW(std::sqrt(r2[q]), inv_h, norm_w);  // m_j W(r, h2)
  }
}

}  // namespace

void Solver::computeDensity() {
  const CubicKernel k2(params_.h2);
  const std::size_t n = particles_.size();
  const glm::vec3* x = particles_.position.data();
  const float* m = particles_.mass.data();
  const float w0 = k2.W(0.0f), inv_h = 1.0f / k2.h(), norm_w = w0 / 4.0f;
  const float ka = params_.pressure_stiffness;
  // Blocks of points in the search's order, whose lists lie one after the
  // other in memory (each point's sum is the same in any visiting order).
  const std::uint32_t* ord = grid_->searchOrder().data();
  const NeighborGrid& grid = *grid_;
  std::vector<glm::vec4>& records = hairRecords().xm;  // (x, m), kept for the hair-hair pass
  records.resize(n);
  const glm::vec4* xm = records.data();
  enum { R2, MJ, RHO, kColumns };
  parallel::run(threads_, [&] {
    const auto [k0, k1] = pairLoopPart(grid);
    fillRecords(records, x, m, ord, k0, k1);
    parallel::barrier();
    PairColumns& col = threadColumns();
    for (std::size_t b = k0; b < k1; b += kPairBlock) {
      const std::size_t e = std::min(k1, b + kPairBlock);
      std::size_t pairs = 0;
      for (std::size_t p = b; p < e; ++p) pairs += grid.list(p).size();
      col.reserve(pairs + 4, kColumns);  // a group of 4 may write 3 past the last pair
      float* __restrict r2 = col[R2], * __restrict mj = col[MJ], * __restrict rho = col[RHO];
      std::size_t k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const auto list = grid.list(p);
#if defined(__SSE2__)
        const std::size_t count = list.size();
        __m128 ri[4], a[4];
        broadcastRecord(xm[p], ri);
        for (std::size_t g = 0; g < count; g += 4) {
          transposedRecords(xm, PartnerGroup(list, g), a);
          const __m128 dx = _mm_sub_ps(a[0], ri[0]), dy = _mm_sub_ps(a[1], ri[1]),
                       dz = _mm_sub_ps(a[2], ri[2]);
          // (dx dx + dy dy) + dz dz, the order of glm::dot
          _mm_storeu_ps(r2 + k + g, _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)),
                                               _mm_mul_ps(dz, dz)));
          _mm_storeu_ps(mj + k + g, a[3]);
        }
        k += count;
#else
        const glm::vec3 xi(xm[p]);
        for (std::uint32_t j : list) {
          const glm::vec3 d = glm::vec3(xm[j]) - xi;
          r2[k] = glm::dot(d, d);
          mj[k] = xm[j].w;
          ++k;
        }
#endif
      }
      densityPairTerms(pairs, inv_h, norm_w, r2, mj, rho);
      k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const std::uint32_t i = ord[p];
        float sum = m[i] * w0;
        for (std::size_t end = k + grid.list(p).size(); k < end; ++k) sum += rho[k];
        density_[i] = sum;
        pressure_[i] = ka * (sum - rest_density_);
        pressure_term_[i] = pressure_[i] / (sum * sum);  // P_i / rho_i^2 of eq. 16
      }
    }
  });
}

// ---- stage 3a: loose spring coefficients, eqs. 7, 10-14 ---------------------
void Solver::resizeScratch(Scratch& s, bool keep_k) const {
  const std::size_t n = particles_.size(), m = connections_.entryCount();
  s.sum_root.assign(n, 0.0f);
  s.sum_tip.assign(n, 0.0f);
  s.factor_root.assign(n, 0.0f);
  s.factor_tip.assign(n, 0.0f);
  s.weight.assign(sliced_->layout.entryCount(), 0.0f);  // in the slice layout
  s.unit_x.assign(sliced_->layout.entryCount(), 0.0f);
  s.unit_y.assign(sliced_->layout.entryCount(), 0.0f);
  s.unit_z.assign(sliced_->layout.entryCount(), 0.0f);
  s.pull.assign(n, glm::vec3(0.0f));
  s.k.assign(keep_k ? m : 0, 0.0f);
  s.sums_current = false;
}

void Solver::computeSpringFactors(Scratch& s) const {
  const CubicKernel k1(params_.h1);
  const auto& x = particles_.position;
  const auto& c = connections_;
  const double young = params_.youngs_modulus;
  const float clamp = params_.stiffness_clamp;
  const Index n = static_cast<Index>(x.size());
  std::size_t clamped = 0, active = 0;
  const bool measure = !s.sums_current;  // else the direction pass measured (and counted)
  const bool keep_k = !s.k.empty();
  const SpringKernel sk(k1);
  const auto& v = particles_.velocity;
  const auto& root = particles_.is_root;
  s.spring_records.resize(2 * x.size());
  glm::vec4* rec = s.spring_records.data();
  std::atomic<std::size_t> clamped_sum{0};
  std::atomic<std::size_t> active_sum{0};
  parallel::run(threads_, [&] {
    std::size_t clamped_part = 0;
    std::size_t active_part = 0;
    const auto [first, last] = parallel::share(static_cast<std::size_t>(n));
    for (std::size_t i = first; i < last; ++i) {
      if (measure) {
        // k_ij and |x_ij| of every entry, and the two sides' sums of l_ij k_ij
        const glm::vec3 xi = x[i];
        float sums[2] = {0.0f, 0.0f};
        const std::uint32_t bounds[3] = {c.begin(i), c.tipBegin(i), c.end(i)};
        for (int side = 0; side < 2; ++side) {
          float sum = 0.0f;
          for (std::uint32_t e = bounds[side]; e < bounds[side + 1]; ++e) {
            const glm::vec3 d = x[c.partner[e]] - xi;
            const float r = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            const float k = springCoefficient(c.strength[e], r, sk.inv_h, sk.norm_w);
            if (keep_k) s.k[e] = k;
            active_part += k > 0.0f ? 1 : 0;
            sum += c.rest_length[e] * k;
          }
          sums[side] = sum;
        }
        s.sum_root[i] = sums[0];
        s.sum_tip[i] = sums[1];
      }
      const double ea = young * cross_section_[i];
      auto factor = [&](float sum, float rest) {
        if (!(sum > 0.0f)) return 0.0f;
        const float a = static_cast<float>(ea / sum), limit = clamp * rest;
        if (a > limit) {
          ++clamped_part;
          return limit;
        }
        return a;
      };
      s.factor_root[i] = factor(s.sum_root[i], rest_factor_root_[i]);
      s.factor_tip[i] = factor(s.sum_tip[i], rest_factor_tip_[i]);
      // the spring pass's records of i (accumulateSpringForces), a root's
      // factors replaced by the marker
      const bool r = root[i] != 0;
      rec[2 * i] = glm::vec4(x[i], r ? kRootFactor : s.factor_root[i]);
      rec[2 * i + 1] = glm::vec4(v[i], r ? kRootFactor : s.factor_tip[i]);
    }
    clamped_sum += clamped_part;
    active_sum += active_part;
  });
  clamped = clamped_sum.load();
  active = active_sum.load();

  s.clamped = clamped;
  if (measure) s.active_entries = active;
  s.sums_current = false;  // the step moves the particles
}

// ---- stage 3b: damped spring forces (method.md §3.2) ----------------------------
namespace {

// The damped spring forces of the connections of a run of slices:
// alpha_ij k_ij (|x_ij| - l_ij + gamma (v_ij . n)) n, n = x_ij / |x_ij|,
// summed per lane in list order; and alpha_ij k_ij per entry, kept for the
// direction pass; for the implicit solve (implicit_springs.hpp), n per
// entry and alpha_ij k_ij (v_ij . n) n summed per lane as well. alpha_ij
// (eq. 14) from the owner's factor on the entry's side and the partner's on
// the other side (gathered); roots are known by their factors' kRootFactor.
struct SpringTerms {
  float inv_h, norm_w;  // kernel W(r, h1)
  float gamma;          // spring damping (s)
};
LOOSEHAIR_PAIR_KERNEL
void springSlices(
    std::size_t slices, const std::uint32_t* __restrict rows, const SpringTerms& p,
    const float* __restrict degree, const float* __restrict root_degree, const float* __restrict xi,
    const float* __restrict yi, const float* __restrict zi, const float* __restrict vxi,
    const float* __restrict vyi, const float* __restrict vzi, const float* __restrict own_root,
    const float* __restrict own_tip, const float* __restrict xj, const float* __restrict yj,
    const float* __restrict zj, const float* __restrict vxj, const float* __restrict vyj,
    const float* __restrict vzj, const float* __restrict frj, const float* __restrict ftj,
    const float* __restrict strength, const float* __restrict rest, float* __restrict weight,
    float* __restrict nx_out, float* __restrict ny_out, float* __restrict nz_out,
    float* __restrict fx_out, float* __restrict fy_out, float* __restrict fz_out,
    float* __restrict px_out, float* __restrict py_out, float* __restrict pz_out) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const float inv_h = p.inv_h, norm_w = p.norm_w, gamma = p.gamma;
  std::size_t q0 = 0;
  for (std::size_t sl = 0; sl < slices; ++sl) {
    float fx[L], fy[L], fz[L], px[L], py[L], pz[L];
    for (std::size_t l = 0; l < L; ++l) fx[l] = fy[l] = fz[l] = px[l] = py[l] = pz[l] = 0.0f;
    const std::size_t o = sl * L;
    for (std::uint32_t r = 0; r < rows[sl]; ++r, q0 += L) {
      const float row = static_cast<float>(r);
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t q = q0 + l;
        const float dx = xj[q] - xi[o + l], dy = yj[q] - yi[o + l], dz = zj[q] - zi[o + l];
        const float ux = vxj[q] - vxi[o + l], uy = vyj[q] - vyi[o + l], uz = vzj[q] - vzi[o + l];
        // root side: own factor a_r,i and the partner's a_t,j; tip side the
        // reverse (all four loaded, then selected: the loop vectorises)
        const float own_r = own_root[o + l], own_t = own_tip[o + l], fr_j = frj[q], ft_j = ftj[q];
        const bool root_side = row < root_degree[o + l];
        const float own = root_side ? own_r : own_t;
        const float other = root_side ? ft_j : fr_j;
        const float alpha = pairFactor(own, other, ownWeight(own_r < 0.0f, fr_j < 0.0f));
        const float len = std::sqrt(dx * dx + dy * dy + dz * dz);  // |x_ij|
        const float w = alpha * springCoefficient(strength[q], len, inv_h, norm_w);
        const float inv_r = len > 0.0f ? 1.0f / len : 0.0f;
        const float nx = dx * inv_r, ny = dy * inv_r, nz = dz * inv_r;
        const float closing = ux * nx + uy * ny + uz * nz;
        const float f = w * ((len - rest[q]) + gamma * closing);
        const bool valid = row < degree[o + l];
        weight[q] = w;
        fx[l] = valid ? fx[l] + f * nx : fx[l];
        fy[l] = valid ? fy[l] + f * ny : fy[l];
        fz[l] = valid ? fz[l] + f * nz : fz[l];
        // the implicit solve's n, by division (its own rounding, kept)
        const float mx = len > 0.0f ? dx / len : 0.0f, my = len > 0.0f ? dy / len : 0.0f,
                    mz = len > 0.0f ? dz / len : 0.0f;
        nx_out[q] = mx;
        ny_out[q] = my;
        nz_out[q] = mz;
        const float g = w * (mx * ux + my * uy + mz * uz);
        px[l] = valid ? px[l] + g * mx : px[l];
        py[l] = valid ? py[l] + g * my : py[l];
        pz[l] = valid ? pz[l] + g * mz : pz[l];
      }
    }
    for (std::size_t l = 0; l < L; ++l) {
      fx_out[o + l] = fx[l];
      fy_out[o + l] = fy[l];
      fz_out[o + l] = fz[l];
      px_out[o + l] = px[l];
      py_out[o + l] = py[l];
      pz_out[o + l] = pz[l];
    }
  }
}

}  // namespace

void Solver::accumulateSpringForces(Scratch& s, std::vector<glm::vec3>& force) const {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const SlicedConnections& sl = *sliced_;
  const ConnectionSlices& cs = sl.layout;
  const CubicKernel k1(params_.h1);
  const SpringKernel sk(k1);
  const SpringTerms terms{sk.inv_h, sk.norm_w, params_.spring_damping};
  // the first 8 columns of each: the two records' 4 + 4 floats (gatherRecordPairs)
  enum { XJ, YJ, ZJ, FRJ, VXJ, VYJ, VZJ, FTJ, kEntryColumns };
  enum { XI, YI, ZI, OWN_R, VXI, VYI, VZI, OWN_T, FX, FY, FZ, PX, PY, PZ, kLaneColumns };
  const std::size_t n = particles_.size();
  assert(s.spring_records.size() == 2 * n);  // made by computeSpringFactors
  const float* records = &s.spring_records[0].x;
  parallel::run(threads_, [&] {
    SliceColumns& col = threadSliceColumns();
    forOwnWorkItems(cs, [&](const SliceRun& run) {
      const std::size_t q0 = run.q0, s0 = run.s0;
      col.reserve(run.entries, kEntryColumns, run.lanes, kLaneColumns);
      const std::uint32_t* partner = cs.partner.data() + q0;
      const std::uint32_t* owner = cs.owner.data() + s0 * L;
      run.prefetchNext(cs.partner.data(), sl.strength.data(), sl.rest.data(), s.weight.data());
      // (x, a_r) and (v, a_t) of the partners and of the owners
      gatherRecordPairs(records, partner, run.entries, run.gatherAhead(n * 2 * sizeof(glm::vec4)),
                        col.entry(XJ), col.entryStride());
      gatherRecordPairs(records, owner, run.lanes, 0, col.lane(XI), col.laneStride());
      springSlices(run.s1 - s0, run.rows, terms, cs.degree.data() + s0 * L,
                   cs.root_degree.data() + s0 * L, col.lane(XI), col.lane(YI), col.lane(ZI),
                   col.lane(VXI), col.lane(VYI), col.lane(VZI), col.lane(OWN_R), col.lane(OWN_T),
                   col.entry(XJ), col.entry(YJ), col.entry(ZJ), col.entry(VXJ), col.entry(VYJ),
                   col.entry(VZJ), col.entry(FRJ), col.entry(FTJ), sl.strength.data() + q0,
                   sl.rest.data() + q0, s.weight.data() + q0, s.unit_x.data() + q0,
                   s.unit_y.data() + q0, s.unit_z.data() + q0, col.lane(FX), col.lane(FY),
                   col.lane(FZ), col.lane(PX), col.lane(PY), col.lane(PZ));
      for (std::size_t l = 0; l < run.used; ++l) {
        force[owner[l]] = glm::vec3(col.lane(FX)[l], col.lane(FY)[l], col.lane(FZ)[l]);
        s.pull[owner[l]] = glm::vec3(col.lane(PX)[l], col.lane(PY)[l], col.lane(PZ)[l]);
      }
    });
  });
}

namespace {

// The hair-hair force on i of each gathered pair (method.md §4, eqs. 16-18), for
// accumulateHairHairForces. A function of its own with plain arguments so
// that the loop vectorises (inside the parallel region's lambda it may not).
struct HairHairTerms {
  float inv_h, norm_w, norm_g;  // kernel W(r, h2): 1/h, 1/(4 pi h^3), 1/(4 pi h^4)
  float dc, dfr;                // collision and friction coefficients
};
LOOSEHAIR_PAIR_KERNEL
void hairHairPairTerms(std::size_t pairs, const HairHairTerms& p, const float* __restrict dx,
                       const float* __restrict dy, const float* __restrict dz,
                       const float* __restrict vx, const float* __restrict vy,
                       const float* __restrict vz, const float* __restrict tix,
                       const float* __restrict tiy, const float* __restrict tiz,
                       const float* __restrict tjx, const float* __restrict tjy,
                       const float* __restrict tjz, const float* __restrict mm,
                       const float* __restrict pp, float* __restrict fx, float* __restrict fy,
                       float* __restrict fz) {
  const float inv_h = p.inv_h, norm_w = p.norm_w, norm_g = p.norm_g, dc = p.dc, dfr = p.dfr;
  for (std::size_t q = 0; q < pairs; ++q) {
    const float r2 = dx[q] * dx[q] + dy[q] * dy[q] + dz[q] * dz[q];
    const float r = std::sqrt(r2);
    const float inv_r = r > 0.0f ? 1.0f / r : 0.0f;
    const float w = cubicW(r, inv_h, norm_w);      // W(r, h2)
    const float dw = cubicDWdr(r, inv_h, norm_g);  // dW/dr
    // eq. 16: -m_i m_j (P_i/rho_i^2 + P_j/rho_j^2) grad_i W, grad_i W = -dW/dr x_ij / r
    const float pc = mm[q] * pp[q] * dw * inv_r;
    // eq. 17: collision direction t_i x t_j; for near-parallel hairs the
    // part of x_ij normal to their mean direction (our symmetric choice,
    // so that the pair force is exactly opposite on j).
    const float cx = tiy[q] * tjz[q] - tiz[q] * tjy[q];
    const float cy = tiz[q] * tjx[q] - tix[q] * tjz[q];
    const float cz = tix[q] * tjy[q] - tiy[q] * tjx[q];
    const float c2 = cx * cx + cy * cy + cz * cz;
    const float sgn = tix[q] * tjx[q] + tiy[q] * tjy[q] + tiz[q] * tjz[q] >= 0.0f ? 1.0f : -1.0f;
    const float mx = tix[q] + sgn * tjx[q], my = tiy[q] + sgn * tjy[q], mz = tiz[q] + sgn * tjz[q];
    const float m2 = mx * mx + my * my + mz * mz;
    const float along = (dx[q] * mx + dy[q] * my + dz[q] * mz) / (m2 > 0.0f ? m2 : 1.0f);
    const float ax = dx[q] - along * mx, ay = dy[q] - along * my, az = dz[q] - along * mz;
    const float a2 = ax * ax + ay * ay + az * az;
    const bool parallel = c2 < 1e-6f;
    // the fallback direction is usable if the hairs are not on one line
    // (float masks, not bools: the loop then vectorises)
    const float usable = m2 > 0.0f ? (a2 < 1e-6f * r2 ? 0.0f : 1.0f) : 0.0f;
    const float valid = parallel ? usable : 1.0f;
    const float d2 = parallel ? a2 : c2;
    const float inv_d = valid / std::sqrt(valid > 0.0f ? d2 : 1.0f);
    const float nx = (parallel ? ax : cx) * inv_d, ny = (parallel ? ay : cy) * inv_d,
                nz = (parallel ? az : cz) * inv_d;
    const float vn = vx[q] * nx + vy[q] * ny + vz[q] * nz;
    // approaching pairs only (eqs. 17-18)
    const float wc = (dx[q] * nx + dy[q] * ny + dz[q] * nz) * vn < 0.0f ? w : 0.0f;
    const float cn = dc * wc * vn, ft = dfr * wc;
    fx[q] = pc * dx[q] + cn * nx + ft * (vx[q] - vn * nx);
    fy[q] = pc * dy[q] + cn * ny + ft * (vy[q] - vn * ny);
    fz[q] = pc * dz[q] + cn * nz + ft * (vz[q] - vn * nz);
  }
}

}  // namespace

// ---- stage 3c: hair-hair pressure, collision, friction (method.md §4) -----------
// A blocked pair loop (pair_columns.hpp): every neighbour is within the
// kernel's support; the terms are selected, not branched on.
void Solver::accumulateHairHairForces(std::vector<glm::vec3>& force, bool xm_ready) const {
  const CubicKernel k2(params_.h2);
  const std::size_t n = particles_.size();
  const glm::vec3* x = particles_.position.data();
  const glm::vec3* v = particles_.velocity.data();
  const glm::vec3* t = particles_.direction.data();
  const float* m = particles_.mass.data();
  const float* pterm = pressure_term_.data();
  const HairHairTerms terms{1.0f / k2.h(), k2.W(0.0f) / 4.0f, -k2.dWdr(k2.h()) / 3.0f, dc_, dfr_};
  const std::uint32_t* ord = grid_->searchOrder().data();  // as in computeDensity
  const NeighborGrid& grid = *grid_;
  enum { DX, DY, DZ, VX, VY, VZ, TIX, TIY, TIZ, TJX, TJY, TJZ, MM, PP, FX, FY, FZ, kColumns };
  // The partners' records (hairRecords()); (x, m) comes from computeDensity
  // in a step, and is made here for a query between steps.
  HairRecords& rec = hairRecords();
  rec.xm.resize(n);
  rec.vp.resize(n);
  rec.tt.resize(n);
  const glm::vec4 *xm = rec.xm.data(), *vp = rec.vp.data(), *tt = rec.tt.data();
  parallel::run(threads_, [&] {
    const auto [k0, k1] = pairLoopPart(grid);
    if (!xm_ready) fillRecords(rec.xm, x, m, ord, k0, k1);
    fillRecords(rec.vp, v, pterm, ord, k0, k1);
    fillRecords(rec.tt, t, nullptr, ord, k0, k1);
    parallel::barrier();
    PairColumns& col = threadColumns();
    for (std::size_t b = k0; b < k1; b += kPairBlock) {
      const std::size_t e = std::min(k1, b + kPairBlock);
      std::size_t pairs = 0;
      for (std::size_t p = b; p < e; ++p) {
        pairs += grid.list(p).size();
        __builtin_prefetch(&force[ord[p]], 1);  // added to in step 3, in search order
      }
      col.reserve(pairs + 4, kColumns);  // a group of 4 may write 3 past the last pair
      float* __restrict dx = col[DX], * __restrict dy = col[DY], * __restrict dz = col[DZ];
      float* __restrict vx = col[VX], * __restrict vy = col[VY], * __restrict vz = col[VZ];
      float* __restrict tix = col[TIX], * __restrict tiy = col[TIY], * __restrict tiz = col[TIZ];
      float* __restrict tjx = col[TJX], * __restrict tjy = col[TJY], * __restrict tjz = col[TJZ];
      float* __restrict mm = col[MM], * __restrict pp = col[PP];
      float* __restrict fx = col[FX], * __restrict fy = col[FY], * __restrict fz = col[FZ];
      // 1. gather: x_ij, v_ij, t_i, t_j, m_i m_j, P_i/rho_i^2 + P_j/rho_j^2
      std::size_t k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const auto list = grid.list(p);
#if defined(__SSE2__)
        const std::size_t count = list.size();
        __m128 ri[4], qi[4], ui[4], a[4], bv[4], c[4];  // i's and the partners' records
        broadcastRecord(xm[p], ri);
        broadcastRecord(vp[p], qi);
        broadcastRecord(tt[p], ui);
        for (std::size_t g = 0; g < count; g += 4) {
          const PartnerGroup group(list, g);
          transposedRecords(xm, group, a);
          transposedRecords(vp, group, bv);
          transposedRecords(tt, group, c);
          const std::size_t q = k + g;
          _mm_storeu_ps(dx + q, _mm_sub_ps(a[0], ri[0]));
          _mm_storeu_ps(dy + q, _mm_sub_ps(a[1], ri[1]));
          _mm_storeu_ps(dz + q, _mm_sub_ps(a[2], ri[2]));
          _mm_storeu_ps(mm + q, _mm_mul_ps(ri[3], a[3]));
          _mm_storeu_ps(vx + q, _mm_sub_ps(bv[0], qi[0]));
          _mm_storeu_ps(vy + q, _mm_sub_ps(bv[1], qi[1]));
          _mm_storeu_ps(vz + q, _mm_sub_ps(bv[2], qi[2]));
          _mm_storeu_ps(pp + q, _mm_add_ps(qi[3], bv[3]));
          _mm_storeu_ps(tjx + q, c[0]);
          _mm_storeu_ps(tjy + q, c[1]);
          _mm_storeu_ps(tjz + q, c[2]);
          _mm_storeu_ps(tix + q, ui[0]);
          _mm_storeu_ps(tiy + q, ui[1]);
          _mm_storeu_ps(tiz + q, ui[2]);
        }
        k += count;
#else
        const glm::vec3 xi(xm[p]), vi(vp[p]), ti(tt[p]);
        const float mi = xm[p].w, pi = vp[p].w;
        for (std::uint32_t j : list) {
          const glm::vec3 xij = glm::vec3(xm[j]) - xi, vij = glm::vec3(vp[j]) - vi;
          const glm::vec3 tj(tt[j]);
          dx[k] = xij.x, dy[k] = xij.y, dz[k] = xij.z;
          vx[k] = vij.x, vy[k] = vij.y, vz[k] = vij.z;
          tix[k] = ti.x, tiy[k] = ti.y, tiz[k] = ti.z;
          tjx[k] = tj.x, tjy[k] = tj.y, tjz[k] = tj.z;
          mm[k] = mi * xm[j].w;
          pp[k] = pi + vp[j].w;
          ++k;
        }
#endif
      }
      // 2. compute each pair's force on i
      hairHairPairTerms(pairs, terms, dx, dy, dz, vx, vy, vz, tix, tiy, tiz, tjx, tjy, tjz, mm, pp,
                        fx, fy, fz);
      // 3. reduce in list order
      k = 0;
      for (std::size_t p = b; p < e; ++p) {
        glm::vec3 f(0.0f);
        for (std::size_t end = k + grid.list(p).size(); k < end; ++k)
          f += glm::vec3(fx[k], fy[k], fz[k]);
        force[ord[p]] += f;
      }
    }
  });
}

// ---- bodies (method.md §5) ---------------------------------------------------------
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

void Solver::prepareBodyHints(const std::vector<BodyFrame>& frames) const {
  const std::size_t n = particles_.size();
  auto want = [&](const Body* body) {
    for (auto& [b, hints] : body_hints_)
      if (b == body) {
        if (hints.size() != n) hints.assign(n, -1);
        return;
      }
    body_hints_.emplace_back(body, std::vector<std::int32_t>(n, -1));
  };
  want(head_.get());
  for (const BodyFrame& f : frames) want(f.body);
  // the hints of bodies not asked this step (an obstacle that ended) go:
  // hints change no answer, so one that comes back starts without
  std::erase_if(body_hints_, [&](const auto& entry) {
    if (entry.first == head_.get()) return false;
    for (const BodyFrame& f : frames)
      if (f.body == entry.first) return false;
    return true;
  });
}

std::int32_t* Solver::bodyHints(const Body* body) const {
  for (auto& [b, hints] : body_hints_)
    if (b == body && hints.size() == particles_.size()) return hints.data();
  return nullptr;
}

void Solver::queryBodies(const std::vector<BodyFrame>& frames, const HeadKinematics& head,
                         const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal,
                         glm::vec3* surface_velocity, float limit, bool rough,
                         const std::uint32_t* index) const {
  // The exact queries of one body over the points, with the particles'
  // hints for it where there are any.
  std::int32_t hint[kBodyBlock];
  auto exact = [&](const Body& body, const glm::vec3* p, std::size_t count, std::size_t first, float* out_phi,
                   glm::vec3* out_normal) {
    std::int32_t* hints = index ? bodyHints(&body) : nullptr;
    if (!hints) {
      body.signedDistanceBelow(p, count, limit, out_phi, out_normal);
      return;
    }
    for (std::size_t b = 0; b < count; b += kBodyBlock) {
      const std::size_t len = std::min(kBodyBlock, count - b);
      for (std::size_t k = 0; k < len; ++k) hint[k] = hints[index[first + b + k]];
      body.signedDistanceBelowHinted(p + b, len, limit, out_phi + b, out_normal + b, hint);
      for (std::size_t k = 0; k < len; ++k) hints[index[first + b + k]] = hint[k];
    }
  };
  // Where every body answers phi >= limit, the nearest may be any of them:
  // the callers only look at the normal and the surface velocity below it.
  if (rough)
    head_->roughDistanceBelow(x, n, limit, phi, normal);
  else
    exact(*head_, x, n, 0, phi, normal);
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
      if (rough)
        f.body->roughDistanceBelow(q, len, limit, pb, nb);
      else
        exact(*f.body, q, len, b, pb, nb);
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

void Solver::bodyDistance(std::span<const glm::vec3> points, double t, std::vector<float>& phi,
                          bool include_obstacles) const {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(t, frames, head, include_obstacles);
  phi.resize(points.size());
  std::vector<glm::vec3> nrm(points.size());
  queryBodies(frames, head, points.data(), points.size(), phi.data(), nrm.data(), nullptr);
}

std::vector<BodyPlacement> Solver::bodyPlacements() const {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(time_, frames, head, true);
  std::vector<BodyPlacement> placed{{head_, glm::mat3(1.0f), glm::vec3(0.0f)}};
  for (const BodyFrame& f : frames)
    for (const WorldBody& wb : world_bodies_)
      if (wb.body.get() == f.body) {
        placed.push_back({wb.body, f.m, f.d});
        break;
      }
  return placed;
}

void Solver::bodyContacts(std::span<const glm::vec3> points, double t, float limit,
                          std::span<float> phi, std::span<glm::vec3> normal, bool rough) const {
  if (phi.size() < points.size() || normal.size() < points.size())
    throw std::invalid_argument("Solver::bodyContacts: output spans shorter than the points");
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(t, frames, head, true);
  queryBodies(frames, head, points.data(), points.size(), phi.data(), normal.data(), nullptr, limit, rough);
}

// ---- wind (method.md §5) -----------------------------------------------------------
void Solver::setWind(const WindParams& wind) {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(time_, frames, head);
  if (wind.model == AirModel::Grid) {
    auto grid = std::make_unique<AirGrid>(wind);
    air_bodies_key_.clear();
    airBodiesMoved(frames, head);
    grid->fill(time_, [&](const glm::vec3* w, std::size_t n, float* phi, glm::vec3* v) {
      worldBodySample(frames, head, w, n, phi, v, true);
    });
    air_ = std::move(grid);
    return;
  }
  auto air = std::make_unique<AirSystem>(wind);
  air->fill(time_, head, [&](const glm::vec3* w, std::size_t n, float* phi) {
    worldBodyDistance(frames, head, w, n, phi);
  });
  air_ = std::move(air);
}

bool Solver::airBodiesMoved(const std::vector<BodyFrame>& frames, const HeadKinematics& head) {
  // Everything the bodies' distances and velocities depend on, bit for bit
  // (the scratch keeps its capacity from step to step).
  std::vector<double>& key = air_bodies_scratch_;
  key.clear();
  auto put = [&key](const auto& v, int n) {
    for (int k = 0; k < n; ++k) key.push_back(static_cast<double>(glm::value_ptr(v)[k]));
  };
  put(head.pose.rotation, 9);
  put(head.pose.center, 3);
  put(head.velocity, 3);
  put(head.angular_velocity, 3);
  for (const BodyFrame& f : frames) {
    key.push_back(static_cast<double>(reinterpret_cast<std::uintptr_t>(f.body)));
    put(f.m, 9);
    put(f.d, 3);
    put(f.ro, 9);
    put(f.rh_t, 9);
    put(f.vo, 3);
    put(f.wo, 3);
  }
  const bool moved = key.size() != air_bodies_key_.size() ||
                     std::memcmp(key.data(), air_bodies_key_.data(), key.size() * sizeof(double)) != 0;
  std::swap(key, air_bodies_key_);
  return moved;
}

void Solver::worldBodySample(const std::vector<BodyFrame>& frames, const HeadKinematics& head,
                             const glm::vec3* world, std::size_t n, float* phi, glm::vec3* velocity,
                             bool rough) const {
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 omega(head.angular_velocity);
  const glm::mat3 rot(head.pose.rotation);
  const glm::vec3 frame_v(head.velocity);
  parallel::forEach(threads_, (n + kBodyBlock - 1) / kBodyBlock, [&](std::size_t bb) {
    const std::size_t b = bb * kBodyBlock, len = std::min(kBodyBlock, n - b);
    glm::vec3 local[kBodyBlock]{}, nrm[kBodyBlock], surface[kBodyBlock];
    for (std::size_t k = 0; k < len; ++k) local[k] = glm::vec3(rt * (glm::dvec3(world[b + k]) - head.pose.center));
    queryBodies(frames, head, local, len, phi + b, nrm, velocity ? surface : nullptr, INFINITY, rough);
    // the bodies' velocity relative to the head frame, made a world one
    if (velocity)
      for (std::size_t k = 0; k < len; ++k)
        velocity[b + k] = rot * (surface[k] + glm::cross(omega, local[k])) + frame_v;
  });
}

void Solver::worldBodyDistance(const std::vector<BodyFrame>& frames, const HeadKinematics& head,
                               const glm::vec3* world, std::size_t n, float* phi) const {
  worldBodySample(frames, head, world, n, phi, nullptr, false);
}

bool Solver::windOnGrid() const { return air_ && air_->model() == AirModel::Grid; }

std::size_t Solver::airCount() const { return air_ ? air_->count() : 0; }

void Solver::worldAirPositions(std::vector<glm::vec3>& out) const {
  out.clear();
  if (air_) air_->worldState(trajectory_.kinematics(time_), &out, nullptr);
}

void Solver::worldAirVelocities(std::vector<glm::vec3>& out) const {
  out.clear();
  if (air_) air_->worldState(trajectory_.kinematics(time_), nullptr, &out);
}

std::span<const float> Solver::airDensity() const {
  return air_ ? air_->density() : std::span<const float>();
}

double Solver::holdTimeStep() const {
  const double w = shape_ ? shape_->fastest() : 0.0;
  return w > 0.0 ? kMaxHoldPhasePerStep / w : INFINITY;
}

double Solver::airStableTimeStep() const { return air_ ? air_->stableTimeStep() : INFINITY; }

// ---- external forces in the head frame (method.md §5) ----------------------------
void Solver::addExternalForces() {
  const std::size_t n = particles_.size();
  const auto& x = particles_.position;
  const auto& v = particles_.velocity;
  const auto& m = particles_.mass;
  const auto& root = particles_.is_root;
  const HeadKinematics head = trajectory_.kinematics(time_);
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 gravity(rt * glm::dvec3(params_.gravity));
  const glm::vec3 frame_accel(rt * head.acceleration);  // R^T c''
  const glm::vec3 frame_vel(rt * head.velocity);        // R^T c'
  const glm::vec3 omega(head.angular_velocity), alpha(head.angular_acceleration);
  const float drag = params_.air_drag;
  const ShapeKeeping* shape = shape_.get();
  parallel::forEach(threads_, static_cast<std::size_t>(n), [&](std::size_t i) {
    if (root[i]) return;
    const glm::vec3 r = x[i], u = v[i];
    const glm::vec3 inertial = frame_accel + glm::cross(alpha, r) + 2.0f * glm::cross(omega, u) +
                               glm::cross(omega, glm::cross(omega, r));
    const glm::vec3 world_velocity = u + glm::cross(omega, r) + frame_vel;
    glm::vec3 a = gravity - inertial - drag * world_velocity;
    if (shape) a += shape->acceleration(i, r);
    force_[i] += m[i] * a;
  });
}

// ---- implicit springs: the velocity change of the step (implicit_springs.hpp)
void Solver::solveSpringsImplicitly(const Scratch& s, float dt) {
  if (!implicit_) implicit_ = std::make_unique<ImplicitSprings>();
  ImplicitSprings::Input in;
  in.layout = &sliced_->layout;
  in.weight = s.weight.data();
  in.unit_x = s.unit_x.data();
  in.unit_y = s.unit_y.data();
  in.unit_z = s.unit_z.data();
  in.pull = s.pull.data();
  in.force = force_.data();
  in.mass = particles_.mass.data();
  in.is_root = particles_.is_root.data();
  in.particles = particles_.size();
  in.dt = dt;
  in.gamma = params_.spring_damping;
  in.tolerance = params_.implicit_tolerance;
  in.max_iterations = params_.implicit_iterations;
  // warm start from the last step's answer (kept in snapshots)
  if (spring_dv_.size() == particles_.size()) in.guess = spring_dv_.data();
  const ImplicitSpringReport rep = implicit_->solve(in, threads_, spring_dv_);
  stats_.spring_iterations = rep.iterations;
  stats_.spring_residual = rep.residual;
}

// ---- integrate: symplectic Euler with the inelastic, frictional body contact
// applied to the new velocity (method.md §5 body collisions) -------------------------
std::size_t Solver::integrate(StepContext& ctx, const std::vector<BodyFrame>& frames,
                              const HeadKinematics& head) {
  const std::size_t n = particles_.size();
  const float dt = ctx.dt;
  auto& x = particles_.position;
  auto& v = particles_.velocity;
  const auto& m = particles_.mass;
  const auto& root = particles_.is_root;
  const float thickness = params_.contact_thickness, mu = params_.body_friction;
  const bool implicit = params_.implicit_springs;
  const float reach = thickness + kSpeculativeSpeed * dt;
  // the strain limit's first records, (x, 1/m), made here in the same pass
  ctx.strain_records[0].resize(n);
  glm::vec4* strain_record = ctx.strain_records[0].data();
  const float* inv_mass = inverse_mass_.data();
  // the rough answers' worst error over the bodies asked: phi - error is a
  // lower bound of the distance (Body::roughError); a body without such a
  // bound leaves every particle to be asked
  auto error = [](const Body& body) { return body.roughError() < 0.0f ? INFINITY : body.roughError(); };
  float rough_error = error(*head_);
  for (const BodyFrame& f : frames) rough_error = std::max(rough_error, error(*f.body));
  float* clearance = ctx.body_clearance.data();
  glm::vec3* integrated_position = ctx.integrated_position.data();
  std::size_t contacts = 0;
  std::atomic<std::size_t> contacts_sum{0};
  parallel::run(threads_, [&] {
    std::size_t contacts_part = 0;
    const auto [first, last] =
        parallel::share(static_cast<std::size_t>((n + kBodyBlock - 1) / kBodyBlock));
    for (std::size_t bb = first; bb < last; ++bb) {
      const std::size_t b = bb * kBodyBlock;
      const std::size_t e = std::min(n, b + kBodyBlock);
      glm::vec3 surface[kBodyBlock];
      // the velocity response tolerates the grid's error; the projection
      // after the constraints keeps particles out of the exact surface.
      // Beyond the contact thickness, as far as a particle at
      // kSpeculativeSpeed gets in a step: speculative contacts.
      queryBodies(frames, head, &x[b], e - b, &body_phi_[b], &body_normal_[b], surface, reach, true);
      for (std::size_t i = b; i < e; ++i) {
        if (root[i]) {
          strain_record[i] = glm::vec4(x[i], inv_mass[i]);
          continue;
        }
        glm::vec3 vi = v[i] + (implicit ? spring_dv_[i] : (dt / m[i]) * force_[i]);
        if (body_phi_[i] >= thickness && body_phi_[i] < reach) {
          // Speculative: a particle that would go through the contact
          // layer into the body within this step only reaches the layer
          // (the step's penetration, which the projection afterwards turns
          // into an outward push and the tether's excess, stays small at
          // any step).
          const glm::vec3 nrm = body_normal_[i];
          const float vn = glm::dot(vi - surface[i - b], nrm);
          const float allowed = -(body_phi_[i] - thickness) / dt;
          if (vn < allowed) vi += (allowed - vn) * nrm;
        }
        if (body_phi_[i] < thickness) {
          // The response acts on the velocity relative to the body's surface.
          const glm::vec3 us = surface[i - b];
          const glm::vec3 nrm = body_normal_[i];
          const glm::vec3 vr = vi - us;
          const float vn = glm::dot(vr, nrm);
          if (vn < 0.0f) {
            ++contacts_part;
            glm::vec3 vt = vr - vn * nrm;  // inelastic: normal approach removed
            const float vt_len = glm::length(vt);
            const float slip = vt_len - mu * (-vn);  // Coulomb: |dv_t| <= mu |dv_n|
            vi = us + (slip > 0.0f ? vt * (slip / vt_len) : glm::vec3(0.0f));
          }
        }
        v[i] = vi;
        x[i] += dt * vi;
        integrated_position[i] = x[i];
        // phi is 1-Lipschitz: the step moved the particle dt |v| at most
        clearance[i] = body_phi_[i] - rough_error - dt * glm::length(vi);
        strain_record[i] = glm::vec4(x[i], inv_mass[i]);
      }
    }
    contacts_sum += contacts_part;
  });
  contacts = contacts_sum.load();

  return contacts;
}

// The hair chain (sim/src/hair_chain.hpp) with the tethers: each particle
// within reach of hair nearer its root and of its root (and tie), nearer
// the root first. Its moves may stop a particle moving away from the hair,
// never throw it back (`moved`, projectOutOfBodies).
void Solver::holdHairChains(std::vector<std::uint8_t>& moved) {
  const auto& rp = particles_.root_point;
  const auto& sarc = particles_.arc_length;
  const float scale = 1.0f + params_.tether_slack;
  moved.assign(particles_.size(), 0);
  chain_->project(particles_.position, sarc, [&](std::size_t i, glm::vec3 y) {
    moved[i] = 1;
    y = tether::within(y, rp[i], scale * sarc[i]);
    if (!tie_reach_.empty() && tie_reach_[i] >= 0.0f) y = tether::within(y, tie_point_[i], scale * tie_reach_[i]);
    return y;
  });
}

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
                                  std::to_string(hz[i]) + " Hz is too strong for time_step = " +
                                  std::to_string(params_.time_step) + " s");
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

// The tethers, then: project what is still inside the body to its surface
// and take the new velocity from the corrected positions (no added normal
// speed, so nothing is thrown off the body).
// Several bodies (head, torso, obstacles) may meet in a crease, where
// leaving one can mean entering another: a few rounds settle it. The first
// round asks the bodies about every particle of a block; a later round only
// about the particles whose answer can differ from what asking all of them
// would give: a particle that has not moved gets the same answer from the
// same bodies, so the rounds with obstacles ask those pushed in the round
// before, and the last round, without obstacles, asks every particle pushed
// so far (its surface velocity is the one that counts). The particles never
// pushed are outside the bodies with obstacles, so outside those without.
// On the mesh-head scenes the later rounds asked all 256 particles of any
// block with one particle inside.
void Solver::projectOutOfBodies(const StepContext& ctx, const std::vector<BodyFrame>& start_frames,
                                const std::vector<BodyFrame>& frames,
                                const std::vector<BodyFrame>& solid_frames,
                                const HeadKinematics& head) {
  const std::size_t n = particles_.size();
  auto& x = particles_.position;
  auto& v = particles_.velocity;
  const auto& root = particles_.is_root;
  // rounds of the head and the world bodies (obstacles too): all but the
  // last slide round the tethers (docs/design.md "Implicit springs")
  const int rounds = frames.empty() ? 2 : 4;
  const bool has_obstacles = solid_frames.size() != frames.size();
  const float dt = ctx.dt;
  const bool absorb = ctx.absorb_corrections;
  const auto& chain_moved = ctx.chain_moved;
  const glm::vec3* integrated_position = ctx.integrated_position.data();
  const int total_rounds = rounds + (has_obstacles ? 1 : 0);
  const bool slide = params_.tether;
  const auto& rp = particles_.root_point;
  const auto& sarc = particles_.arc_length;
  const float reach_scale = 1.0f + params_.tether_slack;
  if (slide) trapped_.resize(n);
  std::atomic<bool> any_trapped{false};
  static_assert(kBodyBlock <= 65536);
  prepareBodyHints(frames);
  // A particle's clearance now: integrate()'s bound, less how far it moved
  // since (the strain limit, the tethers) and how far any world body moved
  // in its frame (rigidly: a body's distance is 1-Lipschitz in the point).
  // Bodies that came or went since integrate(): no bound.
  const bool same_bodies =
      start_frames.size() == frames.size() &&
      std::equal(frames.begin(), frames.end(), start_frames.begin(),
                 [](const BodyFrame& a, const BodyFrame& c) { return a.body == c.body; });
  bool bodies_moved = false;
  for (std::size_t k = 0; same_bodies && k < frames.size(); ++k)
    bodies_moved = bodies_moved || frames[k].m != start_frames[k].m || frames[k].d != start_frames[k].d;
  const float* clear = ctx.body_clearance.data();
  auto clearance = [&](std::size_t i) {
    if (!same_bodies) return -INFINITY;
    const glm::vec3 xi = integrated_position[i];
    float body_move = 0.0f;  // the farthest a world body moved at xi
    for (std::size_t k = 0; bodies_moved && k < frames.size(); ++k)
      body_move = std::max(body_move, glm::length((frames[k].m * xi + frames[k].d) -
                                                  (start_frames[k].m * xi + start_frames[k].d)));
    return clear[i] - glm::length(x[i] - xi) - body_move;
  };
  // Blocks near the surface cost the exact queries, the others little:
  // handed out one by one (each block's result is its own).
  parallel::forEachDynamic(
      threads_, static_cast<std::size_t>((n + kBodyBlock - 1) / kBodyBlock), [&](std::size_t bb) {
        const std::size_t b = bb * kBodyBlock;
        const std::size_t len = std::min(n, b + kBodyBlock) - b;
        glm::vec3 surface[kBodyBlock];
        bool pushed[kBodyBlock] = {};
        glm::vec3 push_normal[kBodyBlock];
        std::uint16_t ask[kBodyBlock];  // the block's particles asked in this round
        glm::vec3 q[kBodyBlock], q_normal[kBodyBlock], q_surface[kBodyBlock];
        float q_phi[kBodyBlock];
        std::size_t asked = 0;
        std::uint32_t index[kBodyBlock];  // the particles asked
        // The first round asks about the particles integrate() did not
        // prove clear of every body; the others keep that proof.
        for (std::size_t o = 0; o < len; ++o) {
          const std::size_t i = b + o;
          if (root[i]) continue;  // never pushed
          const float lower = clearance(i);
          if (lower > kClearMargin) {
            body_phi_[i] = lower;
            continue;
          }
          ask[asked++] = static_cast<std::uint16_t>(o);
        }
        for (int round = 0; round < total_rounds; ++round) {
          if (round == 0 && asked == len) {
            for (std::size_t o = 0; o < len; ++o) index[o] = static_cast<std::uint32_t>(b + o);
            queryBodies(frames, head, &x[b], len, &body_phi_[b], &body_normal_[b], surface, 0.0f, false,
                        index);
          } else {
            for (std::size_t k = 0; k < asked; ++k) {
              q[k] = x[b + ask[k]];
              index[k] = static_cast<std::uint32_t>(b + ask[k]);
            }
            queryBodies(round < rounds ? frames : solid_frames, head, q, asked, q_phi, q_normal,
                        q_surface, 0.0f, false, index);
            for (std::size_t k = 0; k < asked; ++k) {
              body_phi_[b + ask[k]] = q_phi[k];
              body_normal_[b + ask[k]] = q_normal[k];
              surface[ask[k]] = q_surface[k];
            }
          }
          std::size_t moved = 0;  // pushed in this round, kept in ask[0, moved)
          for (std::size_t k = 0; k < asked; ++k) {
            const std::size_t o = ask[k], i = b + o;
            if (root[i] || !(body_phi_[i] < 0.0f)) continue;
            // onto the surface and kSkin beyond, so that rounding does not
            // leave it a hair's breadth inside (and asked again)
            x[i] -= (body_phi_[i] - kSkin) * body_normal_[i];
            // a tether through the body: slide round it (a later round
            // checks where that went; the last one only pushes out)
            if (slide && round + 1 < total_rounds)
              x[i] += tether::slideAlongSurface(x[i], body_normal_[i], rp[i], reach_scale * sarc[i]);
            if (!pushed[o]) push_normal[o] = body_normal_[i];
            pushed[o] = true;
            ask[moved++] = static_cast<std::uint16_t>(o);
          }
          if (moved == 0) break;
          asked = moved;
          if (round + 1 == rounds && has_obstacles) {  // next: the round without obstacles
            asked = 0;
            for (std::size_t o = 0; o < len; ++o)
              if (pushed[o]) ask[asked++] = static_cast<std::uint16_t>(o);
          }
        }
        for (std::size_t i = b; i < b + len; ++i) {
          if (root[i]) continue;
          glm::vec3 vi = v[i];
          if (x[i] != integrated_position[i] && !absorb) {
            // The corrections' move over dt is a velocity (position-based
            // dynamics: hair dragged along keeps the drag's speed), but
            // where the hair chain moved the particle (chain_moved) the
            // move only stops a motion against it: counted whole, a
            // particle the chain drew back flew on past it, and fell again.
            const glm::vec3 d = x[i] - integrated_position[i];
            if (!chain_moved.empty() && chain_moved[i]) {
              const float moved = glm::length(d);
              const glm::vec3 dir = d / moved;
              const float a = glm::dot(vi, dir);
              vi += (std::min(a + moved / dt, std::max(a, 0.0f)) - a) * dir;
            } else {
              vi += d / dt;
            }
          }
          if (pushed[i - b]) {
            const glm::vec3 nrm = push_normal[i - b];
            const float vn = glm::dot(vi - surface[i - b], nrm);
            if (vn > 0.0f) vi -= vn * nrm;  // the push-out is not a velocity
          }
          v[i] = vi;
          // pushed out beyond its tether's reach: caught where sliding
          // does not help (freeTrappedHair)
          if (slide) {
            const float caught = reach_scale * sarc[i] + tether::kTrappedExcess * longest_hair_;
            const glm::vec3 d = x[i] - rp[i];
            trapped_[i] = pushed[i - b] && glm::dot(d, d) > caught * caught;
            if (trapped_[i]) any_trapped.store(true, std::memory_order_relaxed);
          }
        }
      });
  if (any_trapped.load()) freeTrappedHair(solid_frames, head);  // rare: most steps catch none
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
void Solver::step() {
  if (!fingerprint_taken_) (void)sceneFingerprint();
  threads_ = thread_choice_ ? thread_choice_->next() : max_threads_;
  last_step_threads_ = threads_;
  const auto step_start = Clock::now();
  const float dt = static_cast<float>(params_.time_step);
  const double t_end = time_ + params_.time_step;
  Scratch& s = *scratch_;
  StageTimes st;
  auto t0 = Clock::now();
  auto lap = [&t0](double& stage) {
    const auto t = Clock::now();
    stage += seconds(t0, t);
    t0 = t;
  };

  findNeighbors();
  lap(st.neighbors);
  computeDensity();
  lap(st.density);
  computeSpringFactors(s);
  accumulateSpringForces(s, force_);
  lap(st.springs);
  // the (x, m) records are computeDensity's
  if (params_.hair_hair) accumulateHairHairForces(force_, true);
  lap(st.hair_hair);
  if (air_) {
    // the hair-air drag (method.md §5; wind_air.hpp)
    air_->exchange(trajectory_.kinematics(time_), particles_.position, particles_.velocity, particles_.mass,
                   particles_.is_root, force_, dt, threads_);
    lap(st.air);
  }
  addExternalForces();
  lap(st.external);
  if (params_.implicit_springs) {
    solveSpringsImplicitly(s, dt);
    lap(st.springs);
  }

  StepContext& ctx = *step_;
  ctx.dt = dt;
  ctx.t_start = time_;
  ctx.t_end = t_end;
  ctx.threads = threads_;
  ctx.absorb_corrections = absorb_corrections_;
  absorb_corrections_ = false;

  HeadKinematics head_start;
  placeBodies(time_, start_frames_, head_start);
  ctx.contacts = integrate(ctx, start_frames_, head_start);
  lap(st.integrate);

  // Corrections: strain limit, the hair chain and the tethers, and no
  // particle left inside a body.
  ctx.limited = 0;
  if (params_.strain_limit)
    ctx.limited = limitStrain({params_.h1, params_.max_strain, params_.strain_limit_iterations}, *sliced_,
                              particles_.is_root, particles_.position, ctx.strain_records,
                              ctx.limited_position, threads_);
  lap(st.strain_limit);
  if (params_.tether && params_.hair_chain) holdHairChains(ctx.chain_moved);
  else ctx.chain_moved.clear();
  if (params_.tether)
    applyTethers(params_.tether_slack, particles_.is_root, particles_.root_point, particles_.arc_length,
                 tie_point_, tie_reach_, particles_.position, threads_);
  lap(st.tethers);
  HeadKinematics head_end;
  const std::vector<BodyFrame>& frames = end_frames_;
  placeBodies(t_end, end_frames_, head_end);
  placeBodies(t_end, solid_frames_, head_end, false);  // without obstacles: the last round
  projectOutOfBodies(ctx, start_frames_, frames, solid_frames_, head_end);
  lap(st.body_contacts);

  if (air_ && air_->due(dt)) {
    // the air moves (the grid's at its own pace), the bodies where they
    // are at the step's end
    struct StepBodies final : WindAir::Bodies {
      const Solver& solver;
      const std::vector<BodyFrame>& frames;
      StepBodies(const Solver& s, const std::vector<BodyFrame>& f) : solver(s), frames(f) {}
      void local(const glm::vec3* x, std::size_t count, float* phi, glm::vec3* normal,
                 glm::vec3* v) const override {
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
      throw SimulationError("the simulation became unstable at t = " + std::to_string(time_) + " s: " +
                            std::to_string(bad) + " numbers of the wind's air are not finite; lower wind.speed "
                            "or reduce the time step");
    lap(st.air);
  }

  const DirectionPassResult directions =
      updateDirections(params_.h1, *sliced_, s.weight, particles_.is_root, particles_.position,
                       particles_.velocity, particles_.direction, s.sum_root, s.sum_tip, threads_);
  s.sums_current = true;  // the next step's factor pass takes the sums from here
  s.active_entries = directions.active_entries;
  const std::size_t broken = directions.broken;
  if (broken > 0) {
    const auto& x = particles_.position;
    const auto& v = particles_.velocity;
    const std::size_t n = particles_.size();
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
  lap(st.directions);

  time_ = t_end;
  stats_.last = st;
  stats_.sum += st;
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
  if (thread_choice_) thread_choice_->record(seconds(step_start, Clock::now()));
  threads_ = max_threads_;
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

Solver::Scratch Solver::springFactorsNow() const {
  Scratch s;
  resizeScratch(s, true);
  computeSpringFactors(s);
  return s;
}

float Solver::entryFactor(const Scratch& s, std::size_t i, std::uint32_t e) const {
  const bool tip = e >= connections_.tipBegin(i);
  const std::uint32_t j = connections_.partner[e];
  const float own = tip ? s.factor_tip[i] : s.factor_root[i];
  const float other = tip ? s.factor_root[j] : s.factor_tip[j];
  return pairFactor(own, other, ownWeight(particles_.is_root[i], particles_.is_root[j]));
}

double Solver::stableTimeStep() const {
  Scratch s = springFactorsNow();
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
  Scratch s = springFactorsNow();
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
  Scratch s = springFactorsNow();
  std::vector<glm::vec3> f(particles_.size());
  accumulateSpringForces(s, f);
  if (params_.hair_hair) accumulateHairHairForces(f, false);
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
