#include "wind/air.hpp"

#include "solver/kernel.hpp"
#include "util/parallel.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace loosehair {
namespace {

using Index = std::int64_t;

std::uint64_t cellKeyOf(glm::ivec3 c) {
  constexpr std::int64_t kBias = 1 << 20;
  auto part = [](std::int32_t v) {
    return static_cast<std::uint64_t>(std::clamp<std::int64_t>(v + kBias, 0, (1 << 21) - 1));
  };
  return (part(c.z) << 42) | (part(c.y) << 21) | part(c.x);
}

glm::ivec3 cellOf(const glm::vec3& p, float inv_cell) {
  return glm::ivec3(static_cast<int>(std::floor(p.x * inv_cell)), static_cast<int>(std::floor(p.y * inv_cell)),
                    static_cast<int>(std::floor(p.z * inv_cell)));
}

// A hash of integers to [-0.5, 0.5) for the jitter of emitted layers.
float jitter(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  std::uint64_t z = a * 0x9e3779b97f4a7c15ULL ^ (b + 0x632be59bd9b4e019ULL) * 0xbf58476d1ce4e5b9ULL ^
                    (c + 0x85157af5ULL) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  z *= 0xd6e8feb86659fd93ULL;
  z ^= z >> 32;
  return static_cast<float>(static_cast<double>(z >> 11) * 0x1.0p-53 - 0.5);
}

}  // namespace

std::vector<std::string> validate(const WindParams& w) {
  std::vector<std::string> out;
  auto say = [&](const std::string& field, double value, const std::string& rule) {
    std::ostringstream os;
    os << field << " = " << value << ": " << rule;
    out.push_back(os.str());
  };
  const float dl = glm::length(w.direction);
  if (!std::isfinite(dl) || !(dl > 1e-6f)) say("wind.direction length", dl, "must be a non-zero finite direction");
  if (!std::isfinite(w.speed) || w.speed < 0.0f || w.speed > 100.0f)
    say("wind.speed", w.speed, "must be in [0, 100] m/s");
  for (std::size_t k = 0; k < w.profile.size(); ++k) {
    const auto& [t, s] = w.profile[k];
    if (!std::isfinite(t) || !std::isfinite(s) || s < 0.0f || s > 10.0f)
      say("wind.profile[" + std::to_string(k) + "] scale", s, "must be finite, in [0, 10]");
    if (k > 0 && !(t > w.profile[k - 1].first))
      say("wind.profile[" + std::to_string(k) + "] time", t, "times must increase strictly");
  }
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(w.box_size[a]) || !(w.box_size[a] > 0.0f) || w.box_size[a] > 20.0f)
      say("wind.box_size[" + std::to_string(a) + "]", w.box_size[a], "must be in (0, 20] m");
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(w.box_center[a]))
      say("wind.box_center[" + std::to_string(a) + "]", w.box_center[a], "must be finite");
  if (!std::isfinite(w.spacing) || !(w.spacing > 0.0f) || w.spacing > 1.0f)
    say("wind.spacing", w.spacing, "must be in (0, 1] m");
  else {
    double count = 1;
    for (int a = 0; a < 3; ++a) count *= std::ceil(w.box_size[a] / w.spacing);
    if (count > 2.0e7)
      say("wind.spacing", w.spacing,
          w.model == AirModel::Grid ? "gives more than 20 million grid cells in the box"
                                    : "gives more than 20 million air particles in the box");
  }
  if (!std::isfinite(w.h_scale) || w.h_scale < 0.5f || w.h_scale > 4.0f)
    say("wind.h_scale", w.h_scale, "must be in [0.5, 4]");
  if (!std::isfinite(w.density) || !(w.density > 0.0f) || w.density > 1e4f)
    say("wind.density", w.density, "must be in (0, 1e4] kg/m^3");
  if (!std::isfinite(w.sound_speed) || w.sound_speed < 0.0f || w.sound_speed > 1e4f)
    say("wind.sound_speed", w.sound_speed, "must be in [0, 1e4] m/s");
  if (w.projection_iterations < 0 || w.projection_iterations > 50)
    say("wind.projection_iterations", w.projection_iterations, "must be in [0, 50]");
  if (!std::isfinite(w.viscosity_rate) || w.viscosity_rate < 0.0f || w.viscosity_rate > 1e5f)
    say("wind.viscosity_rate", w.viscosity_rate, "must be in [0, 1e5] 1/s");
  if (!std::isfinite(w.drag_rate) || w.drag_rate < 0.0f || w.drag_rate > 1e5f)
    say("wind.drag_rate", w.drag_rate, "must be in [0, 1e5] 1/s");
  return out;
}

AirSystem::AirSystem(const WindParams& params) : p_(params) {
  requireValid(p_);
  const WindAxes axes = windAxes(p_);
  e_wind_ = axes.wind;
  e_up_ = axes.up;
  e_side_ = axes.side;
  h_ = p_.h_scale * p_.spacing;
  mass_ = p_.density * p_.spacing * p_.spacing * p_.spacing;
  // Rest density: the SPH density of the emission lattice.
  const CubicKernel k(h_);
  const int reach = static_cast<int>(std::ceil(2.0f * h_ / p_.spacing));
  double sum = 0;
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x)
        sum += k.W(p_.spacing * std::sqrt(static_cast<float>(x * x + y * y + z * z)));
  rest_density_ = static_cast<float>(mass_ * sum);
  // Kernel mass beyond a plane at distance d (0 <= d <= 2h), by quadrature
  // over slabs: A(z) = int_0^sqrt(4h^2 - z^2) W(sqrt(rho^2 + z^2)) 2 pi rho d rho.
  constexpr int kTable = 65, kQuad = 400;
  const double support = 2.0 * h_;
  std::vector<double> slab(kQuad + 1);
  for (int q = 0; q <= kQuad; ++q) {
    const double z = support * q / kQuad;
    const double rmax = std::sqrt(std::max(0.0, support * support - z * z));
    double area = 0;
    for (int r = 0; r < kQuad; ++r) {
      const double rho = rmax * (r + 0.5) / kQuad;
      area += k.W(static_cast<float>(std::sqrt(rho * rho + z * z))) * 2.0 * std::numbers::pi * rho * (rmax / kQuad);
    }
    slab[static_cast<std::size_t>(q)] = area;
  }
  beyond_.assign(kTable, 0.0f);
  for (int t = 0; t < kTable; ++t) {
    const double d = support * t / (kTable - 1);
    double mass = 0;
    for (int q = 0; q < kQuad; ++q) {
      const double z = support * (q + 0.5) / kQuad;
      if (z < d) continue;
      mass += 0.5 * (slab[static_cast<std::size_t>(q)] + slab[static_cast<std::size_t>(q + 1)]) * (support / kQuad);
    }
    beyond_[static_cast<std::size_t>(t)] = static_cast<float>(mass);
  }
  sound_speed_ = p_.sound_speed > 0.0f ? p_.sound_speed : std::max(0.5f, 2.0f * maxSpeed());
  initProjection();
}

float AirSystem::missingDensity(float d) const {
  const float support = 2.0f * h_;
  if (!(d < support)) return 0.0f;
  const float f = std::max(0.0f, d) / support * static_cast<float>(beyond_.size() - 1);
  const auto k = std::min(static_cast<std::size_t>(f), beyond_.size() - 2);
  const float w = f - static_cast<float>(k);
  return rest_density_ * ((1.0f - w) * beyond_[k] + w * beyond_[k + 1]);
}

glm::vec3 AirSystem::inBox(std::size_t a) const {
  const glm::vec3 q = glm::mat3(pose_.rotation) * x_[a] + glm::vec3(pose_.center) - p_.box_center;
  return {glm::dot(q, e_wind_), glm::dot(q, e_up_), glm::dot(q, e_side_)};
}

bool AirSystem::nearFace(std::size_t a, float reach) const {
  const glm::vec3 c = glm::abs(inBox(a)), half = 0.5f * p_.box_size;
  return c.x > half.x - reach || c.y > half.y - reach || c.z > half.z - reach;
}

float AirSystem::speedAt(double t) const { return windSpeedAt(p_, t); }

float AirSystem::maxSpeed() const { return windMaxSpeed(p_); }

double AirSystem::stableTimeStep() const {
  if (p_.projection_iterations > 0) return static_cast<double>(h_) / std::max(0.1, static_cast<double>(maxSpeed()));
  return 0.5 * static_cast<double>(h_) / (static_cast<double>(sound_speed_) + maxSpeed());
}

void AirSystem::emitLayer(float along, const HeadKinematics& head, const WorldDistance& bodies, float speed) {
  const glm::vec3 size = p_.box_size;
  const int n_up = std::max(1, static_cast<int>(std::floor(size.y / p_.spacing)));
  const int n_side = std::max(1, static_cast<int>(std::floor(size.z / p_.spacing)));
  std::vector<glm::vec3> world;
  world.reserve(static_cast<std::size_t>(n_up) * static_cast<std::size_t>(n_side));
  for (int j = 0; j < n_up; ++j)
    for (int k = 0; k < n_side; ++k) {
      const float a =
          along + 0.2f * p_.spacing *
                      jitter(layer_counter_, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(k) * 3 + 0);
      const float u = -0.5f * size.y + (static_cast<float>(j) + 0.5f +
                                        0.3f * jitter(layer_counter_, static_cast<std::uint64_t>(j),
                                                      static_cast<std::uint64_t>(k) * 3 + 1)) *
                                           p_.spacing;
      const float s = -0.5f * size.z + (static_cast<float>(k) + 0.5f +
                                        0.3f * jitter(layer_counter_, static_cast<std::uint64_t>(j),
                                                      static_cast<std::uint64_t>(k) * 3 + 2)) *
                                           p_.spacing;
      world.push_back(p_.box_center + a * e_wind_ + u * e_up_ + s * e_side_);
    }
  ++layer_counter_;
  std::vector<float> phi(world.size(), 1.0f);
  if (bodies) bodies(world.data(), world.size(), phi.data());
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 omega(head.angular_velocity);
  const glm::dvec3 vw = glm::dvec3(speed * e_wind_) - head.velocity;
  for (std::size_t q = 0; q < world.size(); ++q) {
    if (phi[q] < 0.5f * p_.spacing) continue;  // not inside the head or torso
    const glm::vec3 xh(rt * (glm::dvec3(world[q]) - head.pose.center));
    x_.push_back(xh);
    v_.push_back(glm::vec3(rt * vw) - glm::cross(omega, xh));
    density_.push_back(rest_density_);
    ++emitted_;
  }
}

void AirSystem::fill(double t, const HeadKinematics& head, const WorldDistance& bodies) {
  x_.clear();
  v_.clear();
  density_.clear();
  const float speed = speedAt(t);
  const int layers = std::max(1, static_cast<int>(std::floor(p_.box_size.x / p_.spacing)));
  for (int l = 0; l < layers; ++l)
    emitLayer(-0.5f * p_.box_size.x + (static_cast<float>(l) + 0.5f) * p_.spacing, head, bodies, speed);
  advance_ = 0.5 * p_.spacing;
}

// Keeps the air sorted by cell (a stable sort, so the order is
// deterministic): neighbours are then near in memory, and the cells are
// contiguous ranges for the hair-air search.
void AirSystem::sortByCell(float support, int threads) {
  const std::size_t na = x_.size();
  const float inv_cell = 1.0f / support;
  auto& key = key_;
  key.resize(na);
  for (std::size_t a = 0; a < na; ++a) key[a] = cellKeyOf(cellOf(x_[a], inv_cell));
  sorted_index_.resize(na);
  for (std::uint32_t a = 0; a < na; ++a) sorted_index_[a] = a;
  std::stable_sort(sorted_index_.begin(), sorted_index_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  x_tmp_.resize(na);
  v_tmp_.resize(na);
  key_tmp_.resize(na);
  for (std::size_t q = 0; q < na; ++q) {
    x_tmp_[q] = x_[sorted_index_[q]];
    v_tmp_[q] = v_[sorted_index_[q]];
    key_tmp_[q] = key[sorted_index_[q]];
  }
  x_.swap(x_tmp_);
  v_.swap(v_tmp_);
  key.swap(key_tmp_);
  grid_.build(x_, support, threads);
  cell_key_.clear();
  cell_begin_.clear();
  for (std::uint32_t q = 0; q < na; ++q) {
    const std::uint64_t kq = key[q];
    if (cell_key_.empty() || cell_key_.back() != kq) {
      cell_key_.push_back(kq);
      cell_begin_.push_back(q);
    }
  }
  cell_begin_.push_back(static_cast<std::uint32_t>(na));
}

// Hair -> air lists: each thread takes a contiguous block of hair particles
// (which are ordered along a Morton curve, so consecutive ones share a cell
// and reuse its 27 ranges) into its own buffer; the blocks are joined in
// order, so the lists do not depend on the thread count. Then the
// transpose: each air particle's hair neighbours in increasing order,
// remembering which hair-list entry each came from.
void AirSystem::listHairAir(std::span<const glm::vec3> hair_x, float support, float support2, int threads) {
  const std::size_t na = x_.size(), nh = hair_x.size();
  const float inv_cell = 1.0f / support;
  const int nt = std::max(1, threads);
  auto& buffers = buffers_;
  buffers.resize(static_cast<std::size_t>(nt));
  hair_start_.assign(nh + 1, 0);
  parallel::run(nt, [&] {
    const auto [b, e] = parallel::share(nh);
    auto& out = buffers[static_cast<std::size_t>(parallel::threadIndex())];
    out.clear();
    glm::ivec3 cached(INT32_MIN);
    std::uint32_t rb[27], re[27];
    int ranges = 0;
    for (std::size_t i = b; i < e; ++i) {
      const glm::ivec3 c = cellOf(hair_x[i], inv_cell);
      if (c != cached) {
        cached = c;
        ranges = 0;
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const std::uint64_t kc = cellKeyOf(c + glm::ivec3(dx, dy, dz));
              const auto it = std::lower_bound(cell_key_.begin(), cell_key_.end(), kc);
              if (it == cell_key_.end() || *it != kc) continue;
              const auto ci = static_cast<std::size_t>(it - cell_key_.begin());
              rb[ranges] = cell_begin_[ci];
              re[ranges] = cell_begin_[ci + 1];
              ++ranges;
            }
      }
      std::uint32_t count = 0;
      for (int r = 0; r < ranges; ++r)
        for (std::uint32_t q = rb[r]; q < re[r]; ++q) {
          const std::uint32_t a = q;  // the air is in cell order
          const glm::vec3 d = hair_x[i] - x_[a];
          if (glm::dot(d, d) < support2) {
            out.push_back(a);
            ++count;
          }
        }
      hair_start_[i + 1] = count;
    }
  });
  for (std::size_t i = 0; i < nh; ++i) hair_start_[i + 1] += hair_start_[i];
  hair_list_.clear();
  hair_list_.reserve(hair_start_[nh]);
  for (const auto& buf : buffers) hair_list_.insert(hair_list_.end(), buf.begin(), buf.end());
  air_start_.assign(na + 1, 0);
  for (std::uint32_t a : hair_list_) ++air_start_[a + 1];
  for (std::size_t a = 0; a < na; ++a) air_start_[a + 1] += air_start_[a];
  air_list_.resize(hair_list_.size());
  air_pair_.resize(hair_list_.size());
  auto& fill = fill_;
  fill.assign(air_start_.begin(), air_start_.end() - 1);
  for (std::uint32_t i = 0; i < nh; ++i)
    for (std::uint32_t q = hair_start_[i]; q < hair_start_[i + 1]; ++q) {
      const std::uint32_t slot = fill[hair_list_[q]]++;
      air_list_[slot] = i;
      air_pair_[slot] = q;
    }
}

void AirSystem::findNeighbors(std::span<const glm::vec3> hair_x, float dt, int threads) {
  const std::size_t na = x_.size();
  const CubicKernel k(h_);
  const float support = k.support(), support2 = k.support2();
  sortByCell(support, threads);
  // Without a sound speed: the density projection (air_projection.cpp) on
  // the air's own neighbour lists, before the hair looks for its air. The
  // cell ranges below keep the cells from before the shifts: a shifted
  // particle is at most its shift (a small part of h_air) away from its
  // cell, so only pairs within that much of the support's edge, where W is
  // nearly 0, can be missed.
  if (p_.projection_iterations > 0) projectDensity(dt, threads);

  listHairAir(hair_x, support, support2, threads);
  // Air density (air only: the hair is not air).
  density_.resize(na);
  const float c2 = sound_speed_ * sound_speed_;
  // Projected air has no pressure force (the projection is its pressure).
  const bool projected = p_.projection_iterations > 0;
  pressure_.resize(projected ? 0 : na);
  parallel::forEach(threads, static_cast<std::size_t>(na), [&](std::size_t a) {
    const float rho = densityAt(a, k);
    density_[a] = rho;
    // Weakly compressible; thinned air pulls (so a wake fills), but never
    // harder than a vacuum would.
    if (!projected) pressure_[a] = std::max(-c2 * rest_density_, c2 * (rho - rest_density_));
  });
}

float AirSystem::densityAt(std::size_t a, const CubicKernel& k) const {
  float rho = mass_ * k.W(0.0f);
  for (std::uint32_t b : grid_.neighbors(a)) rho += mass_ * k.W(glm::length(x_[a] - x_[b]));
  return rho + faceDensity(a);
}

float AirSystem::faceDensity(std::size_t a) const {
  // The box is open: the air beyond its faces is missing from the sums, so
  // its density is added from the kernel mass beyond each face. Without it
  // the air at the faces would be thin and pulled inwards.
  const glm::vec3 c = inBox(a), half = 0.5f * p_.box_size;
  return missingDensity(half.x + c.x) + missingDensity(half.x - c.x) + missingDensity(half.y + c.y) +
         missingDensity(half.y - c.y) + missingDensity(half.z + c.z) + missingDensity(half.z - c.z);
}

void AirSystem::accumulateForces(std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                                 std::span<const float> hair_m, std::span<const std::uint8_t> hair_root,
                                 std::span<glm::vec3> hair_force, float dt, int threads) {
  const std::size_t na = x_.size(), nh = hair_x.size();
  const CubicKernel k(h_);
  const float k_over_rho = p_.drag_rate / rest_density_;
  // Kernel values of the hair-air pairs and the drag limiters: a particle
  // whose relative velocity would decay by more than half in one step,
  // dt * (k / rho0) sum m W > 0.5, has its pair forces scaled down so that
  // it does not overshoot; a pair uses the smaller of its two limiters, so
  // its two forces stay equal and opposite.
  pair_w_.resize(hair_list_.size());
  hair_limiter_.resize(nh);
  air_limiter_.resize(na);
  parallel::forEach(threads, static_cast<std::size_t>(nh), [&](std::size_t i) {
    float sum = 0;
    for (std::uint32_t q = hair_start_[i]; q < hair_start_[i + 1]; ++q) {
      const float w = k.W(glm::length(hair_x[i] - x_[hair_list_[q]]));
      pair_w_[q] = w;
      sum += mass_ * w;
    }
    const float rate = k_over_rho * sum;
    hair_limiter_[i] = rate * dt > 0.5f ? 0.5f / (rate * dt) : 1.0f;
  });
  parallel::forEach(threads, static_cast<std::size_t>(na), [&](std::size_t a) {
    float sum = 0;
    for (std::uint32_t q = air_start_[a]; q < air_start_[a + 1]; ++q) {
      const std::uint32_t i = air_list_[q];
      if (!hair_root[i]) sum += hair_m[i] * pair_w_[air_pair_[q]];
    }
    const float rate = k_over_rho * sum;
    air_limiter_[a] = rate * dt > 0.5f ? 0.5f / (rate * dt) : 1.0f;
  });
  // The pair force on hair i from air a (hair-list entry q); the air gets
  // exactly its negative, from the same expression.
  auto drag = [&](std::size_t i, std::size_t a, std::uint32_t q) {
    const float c = k_over_rho * hair_m[i] * mass_ * std::min(hair_limiter_[i], air_limiter_[a]);
    return (c * pair_w_[q]) * (v_[a] - hair_v[i]);
  };
  parallel::forEach(threads, static_cast<std::size_t>(nh), [&](std::size_t i) {
    if (hair_root[i]) return;  // roots are held by the head
    glm::vec3 f(0.0f);
    for (std::uint32_t q = hair_start_[i]; q < hair_start_[i + 1]; ++q) f += drag(i, hair_list_[q], q);
    hair_force[i] += f;
  });
  force_.resize(na);
  drag_on_air_.resize(na);
  const float mu = p_.viscosity_rate;
  // projected air has no pressure force (the projection is its pressure)
  const bool pressure = p_.projection_iterations == 0;
  parallel::forEach(threads, static_cast<std::size_t>(na), [&](std::size_t a) {
    glm::vec3 f(0.0f);
    const float pa = pressure ? pressure_[a] / (density_[a] * density_[a]) : 0.0f;
    for (std::uint32_t b : grid_.neighbors(a)) {
      const glm::vec3 d = x_[a] - x_[b];
      const float r = glm::length(d);
      if (pressure) {
        const float pb = pressure_[b] / (density_[b] * density_[b]);
        f -= (mass_ * mass_ * (pa + pb)) * k.gradW(d, r);
      }
      f += (mu * 2.0f * mass_ * mass_ / (density_[a] + density_[b]) * k.W(r)) * (v_[b] - v_[a]);
    }
    glm::vec3 g(0.0f);
    for (std::uint32_t q = air_start_[a]; q < air_start_[a + 1]; ++q) {
      const std::uint32_t i = air_list_[q];
      if (hair_root[i]) continue;
      g -= drag(i, a, air_pair_[q]);
    }
    drag_on_air_[a] = g;
    force_[a] = f + g;
  });
}

void AirSystem::integrate(double t, float dt, const HeadKinematics& head, int threads) {
  const std::size_t na = x_.size();
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 frame_accel(rt * head.acceleration);
  const glm::vec3 frame_vel(rt * head.velocity);
  const glm::vec3 omega(head.angular_velocity), alpha(head.angular_acceleration);
  const glm::mat3 rot(head.pose.rotation);
  const glm::vec3 centre(head.pose.center);
  // Inflow: the air within one kernel support of the upwind face moves with
  // the wind (it is the boundary condition the rest of the air feels).
  const float inflow_end = -0.5f * p_.box_size.x + 2.0f * h_;
  const glm::vec3 wind_head = glm::vec3(rt * glm::dvec3(speedAt(t) * e_wind_)) - frame_vel;
  const float inv_m = 1.0f / mass_;
  parallel::forEach(threads, static_cast<std::size_t>(na), [&](std::size_t a) {
    const glm::vec3 r = x_[a], u = v_[a];
    const float along = glm::dot(rot * r + centre - p_.box_center, e_wind_);
    if (along < inflow_end) {
      v_[a] = wind_head - glm::cross(omega, r);
    } else {
      const glm::vec3 inertial =
          frame_accel + glm::cross(alpha, r) + 2.0f * glm::cross(omega, u) + glm::cross(omega, glm::cross(omega, r));
      v_[a] = u + dt * (inv_m * force_[a] - inertial);
    }
    x_[a] = r + dt * v_[a];
  });
}

void AirSystem::emitAndRemove(double t, float dt, const HeadKinematics& head, const WorldDistance& bodies) {
  // Remove what left the box (world frame), keeping the order of the rest.
  const glm::vec3 half = 0.5f * p_.box_size;
  const float slack = p_.spacing;
  std::size_t kept = 0;
  for (std::size_t a = 0; a < x_.size(); ++a) {
    const glm::vec3 w(head.pose.rotation * glm::dvec3(x_[a]) + head.pose.center);
    const glm::vec3 q = w - p_.box_center;
    const float al = glm::dot(q, e_wind_), up = glm::dot(q, e_up_), side = glm::dot(q, e_side_);
    const bool inside = al < half.x && al > -half.x - 2.0f * slack && std::abs(up) < half.y + slack &&
                        std::abs(side) < half.z + slack && std::isfinite(al + up + side);
    if (!inside) {
      ++removed_;
      continue;
    }
    x_[kept] = x_[a];
    v_[kept] = v_[a];
    if (a < density_.size()) density_[kept] = density_[a];
    ++kept;
  }
  x_.resize(kept);
  v_.resize(kept);
  density_.resize(kept);
  // New layers through the upwind face for the wind run of this step.
  const float speed = speedAt(t);
  advance_ += static_cast<double>(speed) * dt;
  while (advance_ >= p_.spacing) {
    advance_ -= p_.spacing;
    emitLayer(-half.x + static_cast<float>(advance_), head, bodies, speed);
  }
}

// ---- WindAir ------------------------------------------------------------------
void AirSystem::exchange(const HeadKinematics& head, std::span<const glm::vec3> hair_x,
                         std::span<const glm::vec3> hair_v, std::span<const float> hair_m,
                         std::span<const std::uint8_t> hair_root, std::span<glm::vec3> hair_force, float dt,
                         int threads) {
  // air neighbours, density, pressure, viscosity and the hair-air drag
  setPose(head.pose);
  findNeighbors(hair_x, dt, threads);
  accumulateForces(hair_x, hair_v, hair_m, hair_root, hair_force, dt, threads);
}

void AirSystem::move(double t, double t_end, float dt, const Bodies& bodies, int threads) {
  // Move the air, keep it out of the bodies (free slip), emit upwind and
  // remove what left the box.
  integrate(t, dt, bodies.start, threads);
  constexpr std::size_t kBlock = 256;
  const std::size_t na = x_.size();
  parallel::forEach(threads, (na + kBlock - 1) / kBlock, [&](std::size_t bb) {
    const std::size_t b = bb * kBlock, e = std::min(na, b + kBlock);
    float phi[kBlock];
    glm::vec3 nrm[kBlock], surface[kBlock];
    bodies.local(&x_[b], e - b, phi, nrm, surface);
    for (std::size_t a = b; a < e; ++a) {
      const std::size_t k = a - b;
      if (!(phi[k] < 0.0f)) continue;
      x_[a] -= phi[k] * nrm[k];
      const float vn = glm::dot(v_[a] - surface[k], nrm[k]);
      if (vn < 0.0f) v_[a] -= vn * nrm[k];
    }
  });
  emitAndRemove(t_end, dt, bodies.end,
                [&bodies](const glm::vec3* w, std::size_t n, float* phi) { bodies.worldDistance(w, n, phi); });
}

void AirSystem::worldState(const HeadKinematics& head, std::vector<glm::vec3>* x, std::vector<glm::vec3>* v) const {
  if (x) {
    x->clear();
    for (const auto& r : x_) x->emplace_back(head.pose.rotation * glm::dvec3(r) + head.pose.center);
  }
  if (v) {
    v->clear();
    for (std::size_t a = 0; a < x_.size(); ++a) {
      const glm::dvec3 u = glm::dvec3(v_[a]) + glm::cross(head.angular_velocity, glm::dvec3(x_[a]));
      v->emplace_back(head.pose.rotation * u + head.velocity);
    }
  }
}

void AirSystem::report(StepStats& stats) const {
  stats.air_particles = x_.size();
  stats.hair_air_pairs = hair_list_.size();
  stats.coupled_hair = 0;
  stats.air_iterations = 0;
}

std::size_t AirSystem::nonFinite() const {
  std::size_t n = 0;
  for (std::size_t a = 0; a < x_.size(); ++a)
    n += !std::isfinite(x_[a].x + x_[a].y + x_[a].z + v_[a].x + v_[a].y + v_[a].z);
  for (float d : density_) n += !std::isfinite(d);
  return n;
}

void AirSystem::hashState(const std::function<void(const void* data, std::size_t bytes)>& mix) const {
  const std::size_t na = x_.size();
  mix(&na, sizeof na);
  mix(x_.data(), na * sizeof(glm::vec3));
  mix(v_.data(), na * sizeof(glm::vec3));
}

}  // namespace loosehair
