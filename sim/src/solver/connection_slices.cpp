#include "solver/connection_slices.hpp"

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <numeric>

namespace loosehair {

ConnectionSlices sliceConnections(const ConnectionSet& c, std::size_t window) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  ConnectionSlices out;
  const std::size_t n = c.particleCount();
  out.particle_count = n;
  const std::size_t slices = (n + L - 1) / L;
  window = std::max<std::size_t>(L, window / L * L);

  // lanes: degree-sorted within each window (ties keep the index order)
  std::vector<std::uint32_t> lane(n);
  std::iota(lane.begin(), lane.end(), 0u);
  for (std::size_t w = 0; w < n; w += window) {
    const auto first = lane.begin() + static_cast<std::ptrdiff_t>(w);
    const auto last = lane.begin() + static_cast<std::ptrdiff_t>(std::min(n, w + window));
    std::stable_sort(first, last, [&](std::uint32_t a, std::uint32_t b) { return c.degree(a) > c.degree(b); });
  }
  out.owner.resize(slices * L);
  out.degree.assign(slices * L, 0.0f);
  out.root_degree.assign(slices * L, 0.0f);
  out.row_begin.assign(slices + 1, 0);
  for (std::size_t s = 0; s < slices; ++s) {
    std::uint32_t rows = 0;
    for (std::size_t p = 0; p < L; ++p) {
      const std::size_t k = s * L + p;
      if (k < n) {
        const std::uint32_t i = lane[k];
        out.owner[k] = i;
        out.degree[k] = static_cast<float>(c.degree(i));
        out.root_degree[k] = static_cast<float>(c.tipBegin(i) - c.begin(i));
        rows = std::max(rows, c.degree(i));
      } else {
        out.owner[k] = lane[n - 1];  // a real particle; degree 0 masks it out
      }
    }
    out.row_begin[s + 1] = out.row_begin[s] + rows;
  }
  const std::size_t entries = out.entryCount();
  out.entry.assign(entries, ConnectionSlices::kPadding);
  out.partner.resize(entries);
  for (std::size_t s = 0; s < slices; ++s)
    for (std::size_t p = 0; p < L; ++p) {
      const std::size_t k = s * L + p;
      const std::uint32_t i = out.owner[k];
      const std::uint32_t deg = k < n ? c.degree(i) : 0;
      for (std::uint32_t r = out.row_begin[s]; r < out.row_begin[s + 1]; ++r) {
        const std::size_t slot = static_cast<std::size_t>(r) * L + p;
        const std::uint32_t row = r - out.row_begin[s];
        if (row < deg) {
          out.entry[slot] = c.begin(i) + row;
          out.partner[slot] = c.partner[c.begin(i) + row];
        } else {
          out.partner[slot] = i;
        }
      }
    }
  return out;
}

namespace {
// Runs copy(k) for k = 0, step, ... < count, first prefetching (with
// prefetch(k + kGatherAhead)) while entry k + kGatherAhead + step - 1 is
// readable.
template <class Prefetch, class Copy>
inline void gatherLoop(std::size_t count, std::size_t readable, std::size_t step, Prefetch prefetch, Copy copy) {
  const std::size_t ahead = readable > kGatherAhead ? readable - kGatherAhead : 0;
  const std::size_t split = std::min(count, ahead) / step * step;
  std::size_t k = 0;
  for (; k < split; k += step) {
    for (std::size_t a = 0; a < step; ++a) prefetch(k + kGatherAhead + a);
    copy(k);
  }
  for (; k < count; k += step) copy(k);
}
}  // namespace

void gatherRows3(const float* a, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* ox,
                 float* oy, float* oz) {
  // Scalar loads: on the AMD Zen CPU this was measured on, the AVX-512
  // gather instruction took 1.8 ns an entry against 0.9 for this loop
  // (100k particles, x not in the core's caches).
  gatherLoop(
      count, readable, 1, [&](std::size_t k) { __builtin_prefetch(a + 3 * std::size_t{idx[k]}); },
      [&](std::size_t k) {
        const float* p = a + 3 * std::size_t{idx[k]};
        ox[k] = p[0];
        oy[k] = p[1];
        oz[k] = p[2];
      });
}

#if defined(__SSE2__)
namespace {
// The 4 floats at each of p[0..3], transposed: o[c][k + lane] = p[lane][c].
inline void transposeRecords(const float* const p[4], float* const o[4], std::size_t k) {
  __m128 c0 = _mm_loadu_ps(p[0]), c1 = _mm_loadu_ps(p[1]), c2 = _mm_loadu_ps(p[2]), c3 = _mm_loadu_ps(p[3]);
  _MM_TRANSPOSE4_PS(c0, c1, c2, c3);
  _mm_storeu_ps(o[0] + k, c0);
  _mm_storeu_ps(o[1] + k, c1);
  _mm_storeu_ps(o[2] + k, c2);
  _mm_storeu_ps(o[3] + k, c3);
}
}  // namespace
#endif

void gatherRecords(const float* rec, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* o0,
                   float* o1, float* o2, float* o3) {
  float* const o[4] = {o0, o1, o2, o3};
  auto prefetch = [&](std::size_t k) { __builtin_prefetch(rec + 4 * std::size_t{idx[k]}); };
#if defined(__SSE2__)
  // count is a multiple of 16
  gatherLoop(count, readable, 4, prefetch, [&](std::size_t k) {
    const float* const p[4] = {rec + 4 * std::size_t{idx[k]}, rec + 4 * std::size_t{idx[k + 1]},
                               rec + 4 * std::size_t{idx[k + 2]}, rec + 4 * std::size_t{idx[k + 3]}};
    transposeRecords(p, o, k);
  });
#else
  gatherLoop(count, readable, 1, prefetch, [&](std::size_t k) {
    const float* p = rec + 4 * std::size_t{idx[k]};
    for (std::size_t c = 0; c < 4; ++c) o[c][k] = p[c];
  });
#endif
}

void gatherRecordPairs(const float* rec, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* out,
                       std::size_t column_stride) {
  float* o[8];
  for (std::size_t c = 0; c < 8; ++c) o[c] = out + c * column_stride;
  auto prefetch = [&](std::size_t k) { __builtin_prefetch(rec + 8 * std::size_t{idx[k]}); };
#if defined(__SSE2__)
  // count is a multiple of 16
  gatherLoop(count, readable, 4, prefetch, [&](std::size_t k) {
    const float* const first[4] = {rec + 8 * std::size_t{idx[k]}, rec + 8 * std::size_t{idx[k + 1]},
                                   rec + 8 * std::size_t{idx[k + 2]}, rec + 8 * std::size_t{idx[k + 3]}};
    const float* const second[4] = {first[0] + 4, first[1] + 4, first[2] + 4, first[3] + 4};
    transposeRecords(first, o, k);
    transposeRecords(second, o + 4, k);
  });
#else
  gatherLoop(count, readable, 1, prefetch, [&](std::size_t k) {
    const float* p = rec + 8 * std::size_t{idx[k]};
    for (std::size_t c = 0; c < 8; ++c) o[c][k] = p[c];
  });
#endif
}

}  // namespace loosehair
