#include "init/poisson_pillar.hpp"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {
namespace {

// Hash grid over the 4-D embedding (f^-1(u,v), s) with cells of size 2r: a
// point can only have samples closer than r in the two cells along each axis
// on its own side, so 2^4 = 16 cells are searched.
class Grid4 {
 public:
  Grid4(float radius, std::size_t expected) : inv_cell_(1.0f / (2.0f * radius)) {
    int bits = 8;
    while ((std::size_t{1} << bits) < 4 * expected + 16) ++bits;
    table_.assign(std::size_t{1} << bits, Slot{});
    mask_ = (std::uint64_t{1} << bits) - 1;
  }

  bool farFromAll(const glm::vec4& p, float r2, const std::vector<glm::vec4>& pts) const {
    std::int32_t base[4], step[4];
    for (int a = 0; a < 4; ++a) {
      const float c = p[a] * inv_cell_;
      const float f = std::floor(c);
      base[a] = static_cast<std::int32_t>(f);
      step[a] = (c - f) < 0.5f ? -1 : 1;
    }
    for (int m = 0; m < 16; ++m) {
      std::int32_t cell[4];
      for (int a = 0; a < 4; ++a) cell[a] = base[a] + (((m >> a) & 1) ? step[a] : 0);
      for (std::uint32_t k = head(key(cell)); k != kNone; k = next_[k]) {
        const glm::vec4 d = pts[k] - p;
        if (glm::dot(d, d) < r2) return false;
      }
    }
    return true;
  }

  void insert(const glm::vec4& p, std::uint32_t index) {
    std::int32_t cell[4];
    for (int a = 0; a < 4; ++a) cell[a] = static_cast<std::int32_t>(std::floor(p[a] * inv_cell_));
    const std::uint64_t k = key(cell);
    std::uint64_t slot = hash(k);
    while (table_[slot].used && table_[slot].key != k) slot = (slot + 1) & mask_;
    if (!table_[slot].used) {
      table_[slot].used = true;
      table_[slot].key = k;
      table_[slot].head = kNone;
    }
    if (next_.size() <= index) next_.resize(index + 1, kNone);
    next_[index] = table_[slot].head;
    table_[slot].head = index;
  }

 private:
  static constexpr std::uint32_t kNone = UINT32_MAX;
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t head = kNone;
    bool used = false;
  };
  static std::uint64_t key(const std::int32_t c[4]) {
    std::uint64_t k = 0;
    for (int a = 0; a < 4; ++a) k = (k << 16) | (static_cast<std::uint64_t>(c[a] + 32768) & 0xffff);
    return k;
  }
  std::uint64_t hash(std::uint64_t k) const { return (k * 0x9e3779b97f4a7c15ULL >> 20) & mask_; }
  std::uint32_t head(std::uint64_t k) const {
    std::uint64_t slot = hash(k);
    while (table_[slot].used) {
      if (table_[slot].key == k) return table_[slot].head;
      slot = (slot + 1) & mask_;
    }
    return kNone;
  }

  float inv_cell_;
  std::vector<Slot> table_;
  std::uint64_t mask_ = 0;
  std::vector<std::uint32_t> next_;
};

}  // namespace

std::vector<PillarSample> samplePillarWithRadius(const ScalpSurface& scalp,
                                                 const std::function<float(glm::vec2)>& length, float max_length,
                                                 float radius, float root_depth, std::uint64_t seed,
                                                 std::size_t candidates) {
  Random rng(seed);
  const std::size_t expected = candidates / 4 + 16;
  Grid4 grid(radius, expected);
  std::vector<PillarSample> out;
  std::vector<glm::vec4> pts;
  const float r2 = radius * radius;
  const double pillar_height = static_cast<double>(max_length) + root_depth;
  for (std::size_t c = 0; c < candidates; ++c) {
    // Uniform in the pillar's volume: area-uniform (u, v), accepted with
    // probability proportional to its pillar height, then uniform s.
    const glm::vec2 uv = scalp.sampleByArea(rng);
    const double height = static_cast<double>(length(uv)) + root_depth;
    const double accept = rng.uniform();
    const double sv = rng.uniform();
    if (accept * pillar_height > height) continue;
    const float s = static_cast<float>(-static_cast<double>(root_depth) + sv * height);
    const glm::vec3 p = scalp.point(uv);
    const glm::vec4 q(p, s);
    if (!grid.farFromAll(q, r2, pts)) continue;
    grid.insert(q, static_cast<std::uint32_t>(pts.size()));
    pts.push_back(q);
    out.push_back({uv, s, p});
  }
  return out;
}

PillarResult samplePillar(const ScalpSurface& scalp, const std::function<float(glm::vec2)>& length, float max_length,
                          const PillarOptions& opt) {
  const double target = std::max(1, opt.target_count);
  const std::size_t candidates =
      static_cast<std::size_t>(target) * static_cast<std::size_t>(std::max(2, opt.candidates_per_sample));
  // Pillar volume with the mean length estimated from a fixed probe of L.
  Random probe(opt.seed ^ 0x5eedULL);
  double mean_length = 0;
  constexpr int kProbe = 4096;
  for (int k = 0; k < kProbe; ++k) mean_length += length(scalp.sampleByArea(probe));
  mean_length /= kProbe;
  // Start from the packing density of random sequential addition of balls of
  // diameter r (about N = 0.7 V / r^3); the loop corrects the rest.
  double radius = std::cbrt(0.7 * scalp.area() * mean_length / target);
  PillarResult best;
  double best_error = 1e300;
  for (int round = 0; round < 8; ++round) {
    const float r = static_cast<float>(radius);
    const float depth = opt.root_depth_scale * r;
    auto samples = samplePillarWithRadius(scalp, length, max_length, r, depth, opt.seed, candidates);
    const double count = static_cast<double>(samples.size());
    const double error = std::abs(count - target) / target;
    if (error < best_error) {
      best_error = error;
      best.samples = std::move(samples);
      best.radius = r;
      best.root_depth = depth;
    }
    if (best_error <= 0.01 || count == 0) break;
    radius *= std::cbrt(count / target);
  }
  return best;
}

}  // namespace loosehair
