#include "neighbor_grid.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace loosehair {
namespace {

constexpr int kCoordBits = 21;
constexpr std::int64_t kCoordBias = std::int64_t{1} << (kCoordBits - 1);
constexpr std::int64_t kCoordMax = (std::int64_t{1} << kCoordBits) - 1;

// Cell coordinate along one axis, biased to [0, 2^21). Far or non-finite
// values are clamped into the outermost cells: neighbours are decided by
// distance, so clamping costs speed for such points, never correctness.
std::int64_t cellCoord(float v, float inv_cell) {
  double c = std::floor(static_cast<double>(v) * static_cast<double>(inv_cell)) +
             static_cast<double>(kCoordBias);
  if (!(c >= 0.0)) c = 0.0;  // also NaN
  if (!(c <= static_cast<double>(kCoordMax))) c = static_cast<double>(kCoordMax);
  return static_cast<std::int64_t>(c);
}

std::uint64_t spreadBits(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | (v << 32)) & 0x1f00000000ffffULL;
  v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
  v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
  v = (v | (v << 2)) & 0x1249249249249249ULL;
  return v;
}

std::uint64_t mortonKey(std::int64_t cx, std::int64_t cy, std::int64_t cz) {
  return spreadBits(static_cast<std::uint64_t>(cx)) |
         (spreadBits(static_cast<std::uint64_t>(cy)) << 1) |
         (spreadBits(static_cast<std::uint64_t>(cz)) << 2);
}

std::uint64_t hashKey(std::uint64_t key, int shift) {
  return (key * 0x9e3779b97f4a7c15ULL) >> shift;
}

}  // namespace

std::uint64_t NeighborGrid::cellKey(const glm::vec3& p, float inv_cell) {
  return mortonKey(cellCoord(p.x, inv_cell), cellCoord(p.y, inv_cell), cellCoord(p.z, inv_cell));
}

void NeighborGrid::sortByCell(std::span<const glm::vec3> x) {
  const std::size_t n = x.size();
  keys_.resize(n);
  keys_tmp_.resize(n);
  order_.resize(n);
  order_tmp_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    keys_[i] = cellKey(x[i], inv_cell_);
    order_[i] = static_cast<std::uint32_t>(i);
  }
  // LSD radix sort, 8 bits a pass; stable, so equal keys keep index order.
  // Passes in which every key has the same digit are skipped: hair occupies a
  // small box, so the high digits are usually all equal.
  std::array<std::uint32_t, 256> count{};
  for (int shift = 0; shift < 64; shift += 8) {
    count.fill(0);
    for (std::size_t i = 0; i < n; ++i) ++count[(keys_[i] >> shift) & 0xff];
    if (n == 0 || count[(keys_[0] >> shift) & 0xff] == n) continue;
    std::uint32_t sum = 0;
    for (auto& c : count) {
      const std::uint32_t c0 = c;
      c = sum;
      sum += c0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t dst = count[(keys_[i] >> shift) & 0xff]++;
      keys_tmp_[dst] = keys_[i];
      order_tmp_[dst] = order_[i];
    }
    keys_.swap(keys_tmp_);
    order_.swap(order_tmp_);
  }
  sorted_x_.resize(n);
  for (std::size_t k = 0; k < n; ++k) sorted_x_[k] = x[order_[k]];
}

void NeighborGrid::buildCellTable() {
  const std::size_t n = keys_.size();
  cell_key_.clear();
  cell_start_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || keys_[k] != keys_[k - 1]) {
      cell_key_.push_back(keys_[k]);
      cell_start_.push_back(static_cast<std::uint32_t>(k));
    }
  }
  cell_start_.push_back(static_cast<std::uint32_t>(n));

  int bits = 4;
  while ((std::size_t{1} << bits) < 2 * cell_key_.size()) ++bits;
  table_.assign(std::size_t{1} << bits, 0);
  table_mask_ = (std::uint64_t{1} << bits) - 1;
  table_shift_ = 64 - bits;
  for (std::size_t c = 0; c < cell_key_.size(); ++c) {
    std::uint64_t slot = hashKey(cell_key_[c], table_shift_);
    while (table_[slot] != 0) slot = (slot + 1) & table_mask_;
    table_[slot] = static_cast<std::uint32_t>(c + 1);
  }
}

std::uint32_t NeighborGrid::findCell(std::uint64_t key) const {
  std::uint64_t slot = hashKey(key, table_shift_);
  while (true) {
    const std::uint32_t c = table_[slot];
    if (c == 0) return UINT32_MAX;
    if (cell_key_[c - 1] == key) return c - 1;
    slot = (slot + 1) & table_mask_;
  }
}

void NeighborGrid::build(std::span<const glm::vec3> x, float radius, int threads) {
  const std::size_t n = x.size();
  radius_ = radius;
  inv_cell_ = 1.0f / radius;
  sortByCell(x);
  buildCellTable();
  begin_.assign(n, nullptr);
  count_.assign(n, 0);
  offset_.assign(n, 0);
  threads = std::max(1, threads);
  if (buffers_.size() != static_cast<std::size_t>(threads)) buffers_.resize(threads);
  const float r2 = radius * radius;
  const std::size_t ncells = cell_key_.size();

#pragma omp parallel num_threads(threads)
  {
    const int tid = omp_get_thread_num();
    const int nth = omp_get_num_threads();
    // Contiguous cell range holding about n/nth points.
    auto boundary = [&](int t) {
      const std::size_t k = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(nth);
      return static_cast<std::size_t>(
          std::lower_bound(cell_start_.begin(), cell_start_.end(), static_cast<std::uint32_t>(k)) -
          cell_start_.begin());
    };
    const std::size_t c0 = boundary(tid), c1 = std::min(boundary(tid + 1), ncells);
    std::vector<std::uint32_t>& buf = buffers_[tid];
    buf.clear();
    std::array<std::uint32_t, 27> range_begin{}, range_end{};

    for (std::size_t c = c0; c < c1; ++c) {
      // Decode the cell coordinates from the first point of the cell.
      const glm::vec3 p0 = sorted_x_[cell_start_[c]];
      const std::int64_t cx = cellCoord(p0.x, inv_cell_), cy = cellCoord(p0.y, inv_cell_),
                         cz = cellCoord(p0.z, inv_cell_);
      int nr = 0;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::int64_t ax = cx + dx, ay = cy + dy, az = cz + dz;
            if (ax < 0 || ay < 0 || az < 0 || ax > kCoordMax || ay > kCoordMax || az > kCoordMax)
              continue;
            const std::uint32_t nc = findCell(mortonKey(ax, ay, az));
            if (nc == UINT32_MAX) continue;
            range_begin[nr] = cell_start_[nc];
            range_end[nr] = cell_start_[nc + 1];
            ++nr;
          }
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const glm::vec3 xi = sorted_x_[k];
        const std::uint32_t i = order_[k];
        const std::size_t start = buf.size();
        for (int r = 0; r < nr; ++r) {
          for (std::uint32_t q = range_begin[r]; q < range_end[r]; ++q) {
            const glm::vec3 d = sorted_x_[q] - xi;
            if (d.x * d.x + d.y * d.y + d.z * d.z < r2 && q != k) buf.push_back(order_[q]);
          }
        }
        offset_[i] = static_cast<std::uint32_t>(start);
        count_[i] = static_cast<std::uint32_t>(buf.size() - start);
      }
    }
    // The buffer no longer grows: turn offsets into pointers.
    for (std::size_t c = c0; c < c1; ++c)
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const std::uint32_t i = order_[k];
        begin_[i] = buf.data() + offset_[i];
      }
  }
}

std::size_t NeighborGrid::pairCount() const {
  std::size_t total = 0;
  for (auto c : count_) total += c;
  return total;
}

}  // namespace loosehair
