// The records the density and hair-hair passes gather from (density.cpp,
// hair_hair.cpp). The density pass of a step fills the (x, m) records
// that the hair-hair pass of the same step reuses: they are the step
// context's (StepContext::pair_records), handed from one to the other in
// their signatures.
#pragma once

#include "solver/neighbor_grid.hpp"
#include "solver/pair_columns.hpp"
#include "util/parallel.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace loosehair {

// What the density and hair-hair gathers read of a partner, as 16-byte
// records in the neighbour search's order (record k is particle
// searchOrder()[k], the lists hold these positions): (x, m) for both,
// (v, P/rho^2) and (t, 0) for hair-hair. The search sorts the particles by
// cell, so a particle's partners lie in a few short runs of records, near
// its own, however the hair has moved since it was made. Four partners'
// records are loaded whole and transposed into the columns (4 loads and a
// few shuffles where a scalar gather makes 12 loads and 12 stores).
struct PairRecords {
  std::vector<glm::vec4> xm, vp, tt;
};

// out[k] = (a[i], w[i]), or (a[i], 0) without w, i = ord[k], for k in
// [k0, k1): the calling thread's part of the search order.
inline void fillRecords(std::vector<glm::vec4>& out, const glm::vec3* a, const float* w, const std::uint32_t* ord,
                        std::size_t k0, std::size_t k1) {
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
inline std::pair<std::size_t, std::size_t> pairLoopPart(const NeighborGrid& grid) {
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

}  // namespace loosehair
