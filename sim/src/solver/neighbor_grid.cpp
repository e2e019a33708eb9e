#include "solver/neighbor_grid.hpp"

#include "util/parallel.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define LOOSEHAIR_HAVE_AVX512_PATH 1
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>

namespace loosehair {
namespace {

constexpr int kCoordBits = 21;
constexpr std::int64_t kCoordBias = std::int64_t{1} << (kCoordBits - 1);
constexpr std::int64_t kCoordMax = (std::int64_t{1} << kCoordBits) - 1;

// Cell coordinate along one axis, biased to [0, 2^21). Far or non-finite
// values are clamped into the outermost cells: neighbours are decided by
// distance, so clamping costs speed for such points, never correctness.
std::int64_t cellCoord(float v, float inv_cell) {
  double c = std::floor(static_cast<double>(v) * static_cast<double>(inv_cell)) + static_cast<double>(kCoordBias);
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
  return spreadBits(static_cast<std::uint64_t>(cx)) | (spreadBits(static_cast<std::uint64_t>(cy)) << 1) |
         (spreadBits(static_cast<std::uint64_t>(cz)) << 2);
}

std::uint64_t hashKey(std::uint64_t key, int shift) { return (key * 0x9e3779b97f4a7c15ULL) >> shift; }

// Room the candidate test may write past a range's accepted entries.
constexpr std::size_t kRangeSlack = 16;

#if defined(LOOSEHAIR_HAVE_AVX512_PATH)
bool cpuHasAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

// The candidate test 16 points at a time. The squared distance is the same
// sequence of IEEE operations as in the 4-wide path, ((dx dx + dy dy) + dz dz),
// so both accept the same pairs; compressing the accepted lanes keeps their
// order. The compress goes to a register and all 16 lanes are stored (a
// compressing store to memory is slow on some CPUs); the caller leaves
// kRangeSlack entries of room.
__attribute__((target("avx512f"))) std::size_t collect16(std::size_t k, const std::uint32_t* range_begin,
                                                         const std::uint32_t* range_end, int nr, float r2,
                                                         const float* __restrict cx, const float* __restrict cy,
                                                         const float* __restrict cz,
                                                         const std::uint32_t* __restrict order,
                                                         std::uint32_t* __restrict out) {
  // order == nullptr: the lists hold positions in the search order
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512 xi = _mm512_set1_ps(cx[k]), yi = _mm512_set1_ps(cy[k]), zi = _mm512_set1_ps(cz[k]);
  const __m512 rr = _mm512_set1_ps(r2);
  std::size_t found = 0;
  for (int r = 0; r < nr; ++r) {
    const std::uint32_t qb = range_begin[r], qe = range_end[r];
    for (std::uint32_t q = qb; q < qe; q += 16) {
      const std::uint32_t left = qe - q;
      __mmask16 inside = left >= 16 ? __mmask16(0xffff) : __mmask16((1u << left) - 1u);
      if (k >= q && k < q + 16) inside = __mmask16(inside & ~(1u << (k - q)));
      const __m512 dx = _mm512_sub_ps(_mm512_maskz_loadu_ps(inside, cx + q), xi);
      const __m512 dy = _mm512_sub_ps(_mm512_maskz_loadu_ps(inside, cy + q), yi);
      const __m512 dz = _mm512_sub_ps(_mm512_maskz_loadu_ps(inside, cz + q), zi);
      const __m512 d2 =
          _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)), _mm512_mul_ps(dz, dz));
      const __mmask16 hit = _mm512_mask_cmp_ps_mask(inside, d2, rr, _CMP_LT_OQ);
      const __m512i idx = order ? _mm512_maskz_loadu_epi32(inside, order + q)
                                : _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(q)), iota);
      _mm512_storeu_si512(out + found, _mm512_maskz_compress_epi32(hit, idx));
      found += static_cast<std::size_t>(__builtin_popcount(hit));
    }
  }
  return found;
}
#else
bool cpuHasAvx512() { return false; }
#endif

std::atomic<bool> wide_search_enabled{true};

}  // namespace

void NeighborGrid::setWideSearch(bool on) { wide_search_enabled.store(on); }

bool NeighborGrid::wideSearchAvailable() {
  static const bool available = cpuHasAvx512();
  return available;
}

std::uint64_t NeighborGrid::cellKey(const glm::vec3& p, float inv_cell) {
  return mortonKey(cellCoord(p.x, inv_cell), cellCoord(p.y, inv_cell), cellCoord(p.z, inv_cell));
}

void NeighborGrid::sortHashed(std::span<const glm::vec3> x) {
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
  gatherSorted(x, 1);
}

void NeighborGrid::gatherSorted(std::span<const glm::vec3> x, int threads) {
  const std::size_t n = x.size();
  sorted_x_.resize(n);
  // Coordinates also as padded columns for the 4-wide distance test; the
  // padding is never accepted (lanes past a range's end are masked).
  for (auto* col : {&sorted_cx_, &sorted_cy_, &sorted_cz_}) col->resize(n + 4, 0.0f);
  order_.resize(n + 4, 0);
  parallel::forEach(threads, n, [&](std::size_t k) {
    const glm::vec3 p = x[order_[k]];
    sorted_x_[k] = p;
    sorted_cx_[k] = p.x;
    sorted_cy_[k] = p.y;
    sorted_cz_[k] = p.z;
  });
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

bool NeighborGrid::chooseDenseLayout(std::span<const glm::vec3> x, int threads) {
  const std::size_t n = x.size();
  if (n == 0) return false;
  // Bounds of the coordinates (min and max are exact, so the reduction does
  // not depend on the thread count); floor is monotonic, so the cells of
  // the bounds bound the cells.
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  bool finite = true;
  std::mutex merge;
  parallel::run(threads, [&] {
    float tlo[3] = {INFINITY, INFINITY, INFINITY}, thi[3] = {-INFINITY, -INFINITY, -INFINITY};
    bool tfinite = true;
    const auto [first, last] = parallel::share(n);
    for (std::size_t i = first; i < last; ++i) {
      const glm::vec3 p = x[i];
      tfinite = tfinite && std::isfinite(p.x + p.y + p.z);
      for (int a = 0; a < 3; ++a) {
        tlo[a] = std::min(tlo[a], p[a]);
        thi[a] = std::max(thi[a], p[a]);
      }
    }
    const std::lock_guard<std::mutex> lock(merge);
    finite = finite && tfinite;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], tlo[a]);
      hi[a] = std::max(hi[a], thi[a]);
    }
  });
  if (!finite) return false;
  constexpr double kLimit = 1e15;  // keeps the cell coordinates in int64
  // At most 16 cells a point (64 bytes of offsets): memory stays O(N)
  // whatever the box. Hair is a thin shell, so its box is mostly empty.
  const double budget = 16.0 * static_cast<double>(n) + 4096.0;
  double cells = 1;
  for (int a = 0; a < 3; ++a) {
    const double c0 = std::floor(static_cast<double>(lo[a]) * inv_cell_);
    const double c1 = std::floor(static_cast<double>(hi[a]) * inv_cell_);
    if (!(std::abs(c0) < kLimit) || !(std::abs(c1) < kLimit)) return false;
    origin_[a] = static_cast<std::int64_t>(c0);
    dims_[a] = static_cast<std::int64_t>(c1) - origin_[a] + 1;
    cells *= static_cast<double>(dims_[a]);
  }
  return cells <= budget;
}

void NeighborGrid::sortDense(std::span<const glm::vec3> x, int threads) {
  const std::size_t n = x.size();
  const std::size_t cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
  keys_.resize(n);
  order_.resize(n);
  parallel::forEach(threads, n, [&](std::size_t i) {
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = static_cast<std::int64_t>(std::floor(static_cast<double>(x[i][a]) * inv_cell_)) - origin_[a];
    keys_[i] = static_cast<std::uint64_t>((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
  });
  // Counting sort, stable: points of a cell stay in index order. The work is
  // split by cells, one block of cells a thread: each block zeroes, counts,
  // scans and scatters its own cells (the cells outnumber the points, up to
  // 16 a point), every thread reading all the keys in index order, so the
  // order within a cell is the index order whatever the thread count. Cell
  // c's count goes to start[c + 2]; after the inclusive scan start[c + 1] is
  // cell c's start, and the scatter advances it to cell c's end, which is
  // cell c + 1's start: start[c] is then cell c's start for every c <=
  // cells, with no separate fill array. A block's scatter advances
  // start[c0 + 1 .. c1], which no other block touches.
  dense_start_.resize(cells + 2);
  keys_tmp_.resize(n);
  std::uint32_t* start = dense_start_.data();
  const std::uint64_t* key = keys_.data();
  const int blocks = threads;
  std::vector<std::uint32_t>& block_total = scan_blocks_;
  block_total.assign(static_cast<std::size_t>(blocks) + 1, 0);
  auto block_range = [&](int b) {
    return std::pair<std::uint64_t, std::uint64_t>{(cells * static_cast<std::uint64_t>(b)) / blocks,
                                                   (cells * static_cast<std::uint64_t>(b + 1)) / blocks};
  };
  std::atomic<std::size_t> occupied{0};
  start[0] = start[1] = 0;
  parallel::run(threads, [&] {
    // block b goes to thread b (a team smaller than `threads` takes several)
    const int first = parallel::threadIndex(), step = parallel::threadCount();
    for (int b = first; b < blocks; b += step) {
      const auto [c0, c1] = block_range(b);
      std::fill(start + c0 + 2, start + c1 + 2, 0u);
      for (std::size_t i = 0; i < n; ++i)
        if (key[i] - c0 < c1 - c0) ++start[key[i] + 2];
      std::uint32_t sum = 0;
      std::size_t filled = 0;
      for (std::uint64_t c = c0 + 2; c < c1 + 2; ++c) {
        filled += start[c] > 0 ? 1 : 0;
        sum += start[c];
      }
      block_total[static_cast<std::size_t>(b) + 1] = sum;
      occupied += filled;
    }
    parallel::barrier();
    if (first == 0)
      for (int k = 0; k < blocks; ++k) block_total[k + 1] += block_total[k];
    parallel::barrier();
    for (int b = first; b < blocks; b += step) {
      const auto [c0, c1] = block_range(b);
      std::uint32_t sum = block_total[static_cast<std::size_t>(b)];
      for (std::uint64_t c = c0 + 2; c < c1 + 2; ++c) {
        sum += start[c];
        start[c] = sum;  // the end of cell c - 2, the start of cell c - 1
      }
    }
    parallel::barrier();  // every block's starts are in place
    for (int b = first; b < blocks; b += step) {
      const auto [c0, c1] = block_range(b);
      for (std::size_t i = 0; i < n; ++i) {
        if (key[i] - c0 >= c1 - c0) continue;
        const std::uint32_t dst = start[key[i] + 1]++;
        order_[dst] = static_cast<std::uint32_t>(i);
        keys_tmp_[dst] = key[i];
      }
    }
  });
  occupied_cells_ = occupied.load();
  keys_.swap(keys_tmp_);
  gatherSorted(x, threads);
}

int NeighborGrid::neighborRanges(std::uint64_t cell, std::size_t k, std::uint32_t* begin, std::uint32_t* end) const {
  int nr = 0;
  if (dense_) {
    const std::int64_t nx = dims_[0], ny = dims_[1], nz = dims_[2];
    // The cell's coordinates from one of its points (the expression of
    // sortDense), cheaper than dividing the index.
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = static_cast<std::int64_t>(std::floor(static_cast<double>(sorted_x_[k][a]) * inv_cell_)) - origin_[a];
    const std::int64_t cx = c[0], cy = c[1], cz = c[2];
    const std::int64_t x0 = std::max<std::int64_t>(cx - 1, 0), x1 = std::min(cx + 1, nx - 1);
    for (std::int64_t z = cz - 1; z <= cz + 1; ++z) {
      if (z < 0 || z >= nz) continue;
      for (std::int64_t y = cy - 1; y <= cy + 1; ++y) {
        if (y < 0 || y >= ny) continue;
        // the row's cells x0..x1 are one contiguous range of points
        const std::int64_t row = (z * ny + y) * nx;
        // kept by advancing the count: in a thin shell of hair many rows
        // are empty, and a branch on it is hard to predict
        begin[nr] = dense_start_[static_cast<std::size_t>(row + x0)];
        end[nr] = dense_start_[static_cast<std::size_t>(row + x1 + 1)];
        nr += begin[nr] < end[nr] ? 1 : 0;
      }
    }
    return nr;
  }
  const std::uint32_t c = findCell(cell);
  const glm::vec3 p0 = sorted_x_[cell_start_[c]];  // any point of the cell
  const std::int64_t cx = cellCoord(p0.x, inv_cell_), cy = cellCoord(p0.y, inv_cell_), cz = cellCoord(p0.z, inv_cell_);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::int64_t ax = cx + dx, ay = cy + dy, az = cz + dz;
        if (ax < 0 || ay < 0 || az < 0 || ax > kCoordMax || ay > kCoordMax || az > kCoordMax) continue;
        const std::uint32_t nc = findCell(mortonKey(ax, ay, az));
        if (nc == UINT32_MAX) continue;
        begin[nr] = cell_start_[nc];
        end[nr] = cell_start_[nc + 1];
        ++nr;
      }
  return nr;
}

std::size_t NeighborGrid::collect(std::size_t k, const std::uint32_t* range_begin, const std::uint32_t* range_end,
                                  int nr, float r2, bool point_index, std::uint32_t* __restrict out) const {
  // Every candidate is written and kept by advancing the count: no
  // unpredictable branch per pair. The distance is computed in the same
  // order of operations in both paths, so they accept the same pairs.
  std::size_t found = 0;
#if defined(LOOSEHAIR_HAVE_AVX512_PATH)
  if (wide_)
    return collect16(k, range_begin, range_end, nr, r2, sorted_cx_.data(), sorted_cy_.data(), sorted_cz_.data(),
                     point_index ? order_.data() : nullptr, out);
#endif
  // the index written for sorted point q: the point's, or q itself
  const std::uint32_t* __restrict order = point_index ? order_.data() : nullptr;
#if defined(__SSE2__)
  const float* __restrict cx = sorted_cx_.data();
  const float* __restrict cy = sorted_cy_.data();
  const float* __restrict cz = sorted_cz_.data();
  const __m128 xi = _mm_set1_ps(cx[k]), yi = _mm_set1_ps(cy[k]), zi = _mm_set1_ps(cz[k]);
  const __m128 rr = _mm_set1_ps(r2);
  const __m128i self = _mm_set1_epi32(static_cast<int>(k));
  const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
  for (int r = 0; r < nr; ++r) {
    const std::uint32_t qb = range_begin[r], qe = range_end[r];
    for (std::uint32_t q = qb; q < qe; q += 4) {
      const __m128 dx = _mm_sub_ps(_mm_loadu_ps(cx + q), xi);
      const __m128 dy = _mm_sub_ps(_mm_loadu_ps(cy + q), yi);
      const __m128 dz = _mm_sub_ps(_mm_loadu_ps(cz + q), zi);
      const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
      const __m128i idx = _mm_add_epi32(_mm_set1_epi32(static_cast<int>(q)), lane);
      // lanes inside the range (idx < qe, as signed: indices stay below 2^31)
      const __m128i inside = _mm_cmplt_epi32(idx, _mm_set1_epi32(static_cast<int>(qe)));
      const __m128i not_self = _mm_andnot_si128(_mm_cmpeq_epi32(idx, self), inside);
      const int mask = _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(d2, rr), _mm_castsi128_ps(not_self)));
      out[found] = order ? order[q] : q;
      found += static_cast<std::size_t>(mask & 1);
      out[found] = order ? order[q + 1] : q + 1;
      found += static_cast<std::size_t>((mask >> 1) & 1);
      out[found] = order ? order[q + 2] : q + 2;
      found += static_cast<std::size_t>((mask >> 2) & 1);
      out[found] = order ? order[q + 3] : q + 3;
      found += static_cast<std::size_t>((mask >> 3) & 1);
    }
  }
#else
  const glm::vec3* __restrict sx = sorted_x_.data();
  const glm::vec3 xi = sx[k];
  for (int r = 0; r < nr; ++r) {
    const std::uint32_t qb = range_begin[r], qe = range_end[r];
    for (std::uint32_t q = qb; q < qe; ++q) {
      const glm::vec3 d = sx[q] - xi;
      out[found] = order ? order[q] : q;
      found += static_cast<std::size_t>((d.x * d.x + d.y * d.y + d.z * d.z < r2) & (q != k));
    }
  }
#endif
  return found;
}

void NeighborGrid::build(std::span<const glm::vec3> x, float radius, int threads, ListIndex index) {
  const std::size_t n = x.size();
  radius_ = radius;
  inv_cell_ = 1.0f / radius;
  threads = std::max(1, threads);
  wide_ = wide_search_enabled.load() && wideSearchAvailable();
  dense_ = chooseDenseLayout(x, threads);
  if (dense_) {
    sortDense(x, threads);
  } else {
    sortHashed(x);
    buildCellTable();
    occupied_cells_ = cell_key_.size();
  }
  begin_.resize(n);
  count_.resize(n);
  offset_.resize(n);
  const bool point_index = index == ListIndex::Point;
  if (point_index) {
    rank_.resize(n);
    for (std::size_t k = 0; k < n; ++k) rank_[order_[k]] = static_cast<std::uint32_t>(k);
  } else {
    rank_.clear();  // neighbors(i) is for point-index lists only
  }
  // never shrunk: the automatic thread count switches between 1 and all, and a
  // shrink would free the other threads' buffers each time
  if (buffers_.size() < static_cast<std::size_t>(threads)) buffers_.resize(threads);
  const float r2 = radius * radius;

  // Chunks of sorted points, an equal contiguous range of them a thread,
  // each thread appending to its own buffer: the solver's density and
  // hair-hair passes split the search order about the same way (by pairs,
  // pairBalancedPart), so a thread mostly reads the lists it wrote, from its
  // own caches (Solver, the note above kWindowChunks). A point's list does
  // not depend on which thread makes it.
  const std::int64_t chunks = static_cast<std::int64_t>((n + kChunk - 1) / kChunk);
  chunk_pairs_end_.resize(static_cast<std::size_t>(chunks));
  parallel::run(threads, [&] {
    std::vector<std::uint32_t>& buf = buffers_[static_cast<std::size_t>(parallel::threadIndex())];
    std::size_t used = 0;
    std::array<std::uint32_t, 27> range_begin{}, range_end{};
    const auto [first, last] = parallel::share(static_cast<std::size_t>(chunks));
    for (std::size_t c = first; c < last; ++c) {
      const auto chunk = static_cast<std::int64_t>(c);
      const std::size_t k0 = static_cast<std::size_t>(chunk) * kChunk, k1 = std::min(n, k0 + kChunk);
      int nr = 0;
      std::size_t candidates = 0;
      for (std::size_t k = k0; k < k1; ++k) {
        // the cell's ranges are looked up once for all of its points
        if (k == k0 || keys_[k] != keys_[k - 1]) {
          nr = neighborRanges(keys_[k], k, range_begin.data(), range_end.data());
          candidates = 0;
          for (int r = 0; r < nr; ++r) candidates += range_end[r] - range_begin[r] + kRangeSlack;
        }
        // Room for every candidate, so the loop below writes each one and
        // keeps it by advancing the count: no unpredictable branch per pair.
        if (buf.size() < used + candidates) buf.resize(2 * (used + candidates));
        const std::size_t found =
            collect(k, range_begin.data(), range_end.data(), nr, r2, point_index, buf.data() + used);
        offset_[k] = static_cast<std::uint32_t>(used);
        count_[k] = static_cast<std::uint32_t>(found);
        used += found;
      }
      chunk_pairs_end_[static_cast<std::size_t>(chunk)] = used - offset_[k0];  // this chunk's
    }
    // The buffer no longer grows: turn offsets into pointers.
    for (std::size_t k = first * kChunk, k1 = std::min(n, last * kChunk); k < k1; ++k)
      begin_[k] = buf.data() + offset_[k];
  });
  // the chunks' pairs, summed up (a few hundred chunks at 200k points)
  std::size_t total = 0;
  for (std::size_t& c : chunk_pairs_end_) c = total += c;
  pair_count_ = total;
}

std::size_t NeighborGrid::pairCount() const { return pair_count_; }

std::pair<std::size_t, std::size_t> NeighborGrid::pairBalancedPart(int part, int parts) const {
  const std::size_t n = count_.size(), chunks = chunk_pairs_end_.size();
  const auto pairs_before_chunk = [&](std::size_t c) { return c == 0 ? std::size_t{0} : chunk_pairs_end_[c - 1]; };
  // Part p starts at the multiple of kPartGrain (or n) whose pairs before it
  // come nearest to p/parts of all pairs, the lower one on a tie, so that
  // the starts never decrease with p. (At a few thousand points there are
  // only a few chunks: cutting at chunk boundaries gave one thread 76% of
  // the pairs.)
  auto start = [&](int p) -> std::size_t {
    if (p <= 0) return 0;
    if (p >= parts) return n;
    const auto scale = static_cast<std::size_t>(parts);
    const std::size_t target = pair_count_ * static_cast<std::size_t>(p);  // times `parts`
    // the last chunk c with pairs(< c) * parts <= target (chunk 0 has none before it)
    std::size_t lo = 0, hi = chunks;
    while (hi - lo > 1) {
      const std::size_t c = (lo + hi) / 2;
      if (pairs_before_chunk(c) * scale <= target)
        lo = c;
      else
        hi = c;
    }
    // The nearest start lies in chunk lo or at its end: walk its grains.
    const auto distance = [&](std::size_t pairs) {
      const std::size_t a = pairs * scale;
      return a > target ? a - target : target - a;
    };
    std::size_t k = std::min(n, lo * kChunk), pairs = pairs_before_chunk(lo);
    std::size_t best = k, best_distance = distance(pairs);
    const std::size_t end = std::min(n, (lo + 1) * kChunk);
    while (k < end) {
      const std::size_t grain_end = std::min(end, k + kPartGrain);
      for (; k < grain_end; ++k) pairs += count_[k];
      const std::size_t d = distance(pairs);
      if (d < best_distance) {
        best = k;
        best_distance = d;
      }
    }
    return best;
  };
  return {start(part), start(part + 1)};
}

}  // namespace loosehair
