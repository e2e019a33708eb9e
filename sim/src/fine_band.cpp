// The fine band's lazy bricks and trilinear samples (fine_band.hpp).
#include "fine_band.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {

FineBand::FineBand(const glm::vec3& lower, const glm::vec3& upper, float voxel, Exact exact)
    : lower_(lower), voxel_(voxel), inv_voxel_(1.0f / voxel), exact_(std::move(exact)) {
  if (!(voxel > 0.0f) || !std::isfinite(voxel))
    throw std::invalid_argument("FineBand: voxel " + std::to_string(voxel) + " must be > 0");
  const glm::vec3 extent = upper - lower;
  if (!(extent.x >= 0.0f && extent.y >= 0.0f && extent.z >= 0.0f) ||
      !std::isfinite(extent.x + extent.y + extent.z))
    throw std::invalid_argument("FineBand: the box is empty or not finite");
  const glm::vec3 cells = glm::ceil(extent * inv_voxel_) + 1.0f;
  if (cells.x * cells.y * cells.z > 1e13f)
    throw std::invalid_argument("FineBand: the box is too large for voxels of " + std::to_string(voxel) + " m");
  cells_ = glm::ivec3(cells);
  constexpr int span = kBrickCells * kSuperBricks;
  supers_ = (cells_ + (span - 1)) / span;
  const std::size_t n = static_cast<std::size_t>(supers_.x) * static_cast<std::size_t>(supers_.y) *
                        static_cast<std::size_t>(supers_.z);
  table_ = std::make_unique<std::atomic<Super*>[]>(n);
  for (std::size_t i = 0; i < n; ++i) table_[i].store(nullptr, std::memory_order_relaxed);
  // sqrt(3)/2 of a voxel, and a little for the rounding of the blend
  error_ = 0.8661f * voxel_ * 1.001f + 1e-7f;
}

FineBand::~FineBand() {
  const std::size_t n = static_cast<std::size_t>(supers_.x) * static_cast<std::size_t>(supers_.y) *
                        static_cast<std::size_t>(supers_.z);
  for (std::size_t i = 0; i < n; ++i) {
    Super* s = table_[i].load(std::memory_order_relaxed);
    if (!s) continue;
    for (auto& b : s->brick) delete b.load(std::memory_order_relaxed);
    delete s;
  }
}

FineBand::Brick* FineBand::build(const glm::ivec3& b) const {
  auto made = std::make_unique<Brick>();
  const glm::vec3 origin = lower_ + voxel_ * glm::vec3(b * kBrickCells);
  std::int32_t hint = -1;
  // in a snake order, so that each lattice point starts its search from
  // the nearest triangle of the one before
  for (int k = 0; k < kSamples; ++k)
    for (int jj = 0; jj < kSamples; ++jj) {
      const int j = (k & 1) ? kSamples - 1 - jj : jj;
      for (int ii = 0; ii < kSamples; ++ii) {
        const int i = ((k * kSamples + jj) & 1) ? kSamples - 1 - ii : ii;
        const glm::vec3 p = origin + voxel_ * glm::vec3(i, j, k);
        made->value[(k * kSamples + j) * kSamples + i] = exact_(p, hint);
      }
    }
  return made.release();
}

const FineBand::Brick& FineBand::brick(const glm::ivec3& b) const {
  const glm::ivec3 s = b / kSuperBricks, l = b % kSuperBricks;
  std::atomic<Super*>& slot =
      table_[(static_cast<std::size_t>(s.z) * static_cast<std::size_t>(supers_.y) + static_cast<std::size_t>(s.y)) *
                 static_cast<std::size_t>(supers_.x) +
             static_cast<std::size_t>(s.x)];
  Super* sup = slot.load(std::memory_order_acquire);
  if (!sup) {
    auto fresh = std::make_unique<Super>();
    Super* expected = nullptr;
    if (slot.compare_exchange_strong(expected, fresh.get(), std::memory_order_acq_rel))
      sup = fresh.release();
    else
      sup = expected;
  }
  std::atomic<Brick*>& bslot = sup->brick[(l.z * kSuperBricks + l.y) * kSuperBricks + l.x];
  Brick* br = bslot.load(std::memory_order_acquire);
  if (!br) {
    std::unique_ptr<Brick> fresh(build(b));
    Brick* expected = nullptr;
    if (bslot.compare_exchange_strong(expected, fresh.get(), std::memory_order_acq_rel)) {
      br = fresh.release();
      built_.fetch_add(1, std::memory_order_relaxed);
    } else {
      br = expected;  // the same values, built by another thread first
    }
  }
  return *br;
}

bool FineBand::sample(const glm::vec3& p, float& phi, glm::vec3& normal) const {
  const glm::vec3 u = (p - lower_) * inv_voxel_;
  if (!(u.x >= 0.0f && u.y >= 0.0f && u.z >= 0.0f)) return false;  // also NaN
  const glm::vec3 fl = glm::floor(u);
  if (!(fl.x < static_cast<float>(cells_.x - 1) && fl.y < static_cast<float>(cells_.y - 1) &&
        fl.z < static_cast<float>(cells_.z - 1)))
    return false;
  const glm::ivec3 c(fl);
  const glm::vec3 f = u - fl;
  const Brick& br = brick(c / kBrickCells);
  const glm::ivec3 l = c % kBrickCells;
  auto at = [&](int i, int j, int k) {
    return br.value[((l.z + k) * kSamples + (l.y + j)) * kSamples + (l.x + i)];
  };
  const float v000 = at(0, 0, 0), v100 = at(1, 0, 0), v010 = at(0, 1, 0), v110 = at(1, 1, 0);
  const float v001 = at(0, 0, 1), v101 = at(1, 0, 1), v011 = at(0, 1, 1), v111 = at(1, 1, 1);
  // along x, then y, then z; the gradient from the same differences
  const float a00 = v000 + f.x * (v100 - v000), a10 = v010 + f.x * (v110 - v010);
  const float a01 = v001 + f.x * (v101 - v001), a11 = v011 + f.x * (v111 - v011);
  const float b0 = a00 + f.y * (a10 - a00), b1 = a01 + f.y * (a11 - a01);
  phi = b0 + f.z * (b1 - b0);
  const float gx0 = (v100 - v000) + f.y * ((v110 - v010) - (v100 - v000));
  const float gx1 = (v101 - v001) + f.y * ((v111 - v011) - (v101 - v001));
  glm::vec3 g(gx0 + f.z * (gx1 - gx0), (a10 - a00) + f.z * ((a11 - a01) - (a10 - a00)), b1 - b0);
  const float len = glm::length(g);
  normal = len > 0.0f ? g / len : glm::vec3(0.0f, 1.0f, 0.0f);
  return true;
}

}  // namespace loosehair
