// What the connection passes of the step share (the spring forces, the
// strain limit, the hair directions): the connections in the slice layout
// with their per-entry constants, the work items each thread takes, and the
// spring coefficient and pair factor every pass computes alike, so that
// each gets the same bits.
#pragma once

#include "solver/connection_slices.hpp"
#include "solver/kernel.hpp"
#include "solver/pair_columns.hpp"
#include "util/parallel.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace loosehair {

// Per-step spring quantities. Per connection entry only what a later pass
// cannot recompute from the positions: the connection passes stream these
// arrays every step, and at 100k particles (1.2 M entries) their memory
// traffic, not their arithmetic, bounds the step. |x_ij| and k_ij are
// recomputed where they are needed, from the same expressions, so they have
// the same bits in every pass.

// The connections in the solver's slice layout (connection_slices.hpp) with
// the per-entry constants of the connection passes.
struct SlicedConnections {
  ConnectionSlices layout;
  std::vector<float> rest;      // l_ij
  std::vector<float> strength;  // c_ij
  std::vector<float> cos_rest;  // of theta_ij (the pass takes sin from it: restSine)
};

/// A connection set laid out for the passes (padding entries hold finite
/// values that the passes mask out).
inline SlicedConnections sliceForPasses(const ConnectionSet& c) {
  SlicedConnections sl;
  sl.layout = sliceConnections(c, kSliceWindow);
  sl.rest = sl.layout.arrange(c.rest_length, 1.0f);
  sl.strength = sl.layout.arrange(c.strength, 0.0f);
  sl.cos_rest = sl.layout.arrange(c.cos_rest, 1.0f);
  return sl;
}

using Index = std::int64_t;

// alpha_ij (eq. 14) of an entry from the owner's factor on the entry's side
// and the partner's factor on the other side: j on i's tip side means i on
// j's root side. `own_weight` is 1/2 for a pair of hair particles; a root
// particle is part of the head, so a pair with a root takes the hair
// particle's factor alone (own_weight 1 if the partner is a root, 0 if the
// owner is), and the hair keeps its modulus where it is attached (a root's
// tip side gathers many connections and would halve it).
inline float pairFactor(float own, float other, float own_weight) {
  return own_weight * own + (1.0f - own_weight) * other;
}
// The `own_weight` of an entry from whether its owner and partner are roots.
inline float ownWeight(bool owner_root, bool partner_root) { return partner_root ? 1.0f : owner_root ? 0.0f : 0.5f; }
// A root's side factors are weighted by 0 in every alpha_ij it enters (there
// are no root-root connections), so the spring pass's records carry this
// marker in their place and the entries find their roots from it; 0 * -1 is
// -0 where 0 * a_root was +0, and x + -0 = x + +0 for every x >= 0 (a
// factor), so alpha_ij keeps its bits.
inline constexpr float kRootFactor = -1.0f;

// Work items of the connection passes: chunks of kSliceChunk slices,
// handed out by whole sorting windows of the slice layout (its particles'
// lanes are shuffled by degree), so that no two threads write results of
// particles that share a cache line.
inline constexpr int kWindowChunks = static_cast<int>(kSliceWindow / (ConnectionSlices::kLanes * kSliceChunk));
static_assert(kWindowChunks * ConnectionSlices::kLanes * kSliceChunk == kSliceWindow);

// How the work is shared among threads. Every pass gives each thread one
// contiguous range: the per-particle loops an equal range of particle
// indices (parallel::share), the connection passes about the same
// range cut at whole windows with about equal work (workItemPart), the
// neighbour search an equal range of the search order, density and
// hair-hair about the same range with about equal pairs
// (NeighborGrid::pairBalancedPart). The two
// orders hold about the same part of the hair (both follow space). So a
// thread works on the same particles in every pass and step, and finds
// their data still in its own caches; with dynamic schedules the next pass
// gave about half of them to the other thread. On the 2-core test machine
// the cores do not seem to share a last-level cache: 16 MB written by one
// thread is read back by it at 56-66 GB/s and by the other at 38 GB/s.
// There two threads at 200k particles took 33.9-35.6 ms a step with dynamic
// schedules and 30.1-34.3 with these (identical steps, lowest of 3, the
// lower 7 of 10 alternations); on the head-shake scene at 100k both take
// 23-24 ms. (Splitting the neighbour search by the last build's pairs too
// made it slower, 7.3-7.9 against 6.7-7.1 ms: its work goes more with the
// points than with the pairs.) The results do not depend on the split:
// every work item writes its own particles' sums, each added in a fixed
// order.

// One work item of a connection pass: slices [s0, s1) of the layout, their
// entries from q0 on, their lanes from s0 * 16 on (`used` of them hold a
// particle) and each slice's row count; `readable` entries of the layout's
// per-entry columns follow q0 (for the gathers' look-ahead).
struct SliceRun {
  static constexpr std::size_t L = ConnectionSlices::kLanes;
  std::size_t s0, s1, q0, entries, lanes, used, readable;
  std::uint32_t rows[kSliceChunk];
  SliceRun(const ConnectionSlices& cs, Index chunk)
      : s0(static_cast<std::size_t>(chunk) * kSliceChunk),
        s1(std::min(cs.sliceCount(), s0 + kSliceChunk)),
        q0(std::size_t{cs.row_begin[s0]} * L),
        entries(std::size_t{cs.row_begin[s1]} * L - q0),
        lanes((s1 - s0) * L),
        used(std::min(lanes, cs.particle_count - s0 * L)),
        readable(cs.entryCount() - q0) {
    for (std::size_t k = s0; k < s1; ++k) rows[k - s0] = cs.row_begin[k + 1] - cs.row_begin[k];
  }
  static Index count(const ConnectionSlices& cs) {
    return static_cast<Index>((cs.sliceCount() + kSliceChunk - 1) / kSliceChunk);
  }
  // Sorting windows: groups of kWindowChunks work items.
  static Index windows(const ConnectionSlices& cs) { return (count(cs) + kWindowChunks - 1) / kWindowChunks; }
  // The gathers' look-ahead (connection_slices.hpp) from an array of the
  // partners' records of `record_bytes`: prefetching pays only where the
  // array does not stay in a core's L2 (1-2 MB on current x86 CPUs) through
  // the pass; at 10k particles it cost 3-11% of the strain and direction
  // passes (three alternations).
  std::size_t gatherAhead(std::size_t record_bytes) const {
    constexpr std::size_t kCachedRecordBytes = std::size_t{1} << 20;
    return record_bytes > kCachedRecordBytes ? readable : 0;
  }
  // Asks for the next work item's part of per-entry columns of 4-byte
  // values (given by their starts) to be brought into L2 while this item
  // gathers and computes: its entries follow this item's, and the hardware
  // would otherwise find each column's stream anew at every item.
  template <class... Column>
  void prefetchNext(const Column*... column) const {
    static_assert(((sizeof(Column) == 4) && ...));
    const std::size_t next = std::min(readable - entries, entries);  // next item: about as long
    for (std::size_t b = 0; b < next * 4; b += 64)
      (__builtin_prefetch(reinterpret_cast<const char*>(column + q0 + entries) + b, 0, 2), ...);
  }
};

// The work items [first, second) of part `part` of `parts`: contiguous,
// starting at whole sorting windows, with about equal work. The work of a
// slice is counted as its entries plus kLaneWork a lane (the owner's gather
// and its results); each part starts at the window boundary nearest its
// share, the lower one on a tie. (Equal numbers of windows are not equal
// work: on the bundled mesh-head scenes, 6k particles in 24 windows, they
// gave one thread 53.9% of the entries and lanes; this split 50.5%.)
inline constexpr std::size_t kLaneWork = 2;
inline std::pair<Index, Index> workItemPart(const ConnectionSlices& cs, int part, int parts) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const Index chunks = SliceRun::count(cs), windows = SliceRun::windows(cs);
  const auto boundary = [&](Index w) {  // the first work item of window w
    return std::min(chunks, w * kWindowChunks);
  };
  const auto work = [&](Index w) {  // the work of windows [0, w)
    const std::size_t s = std::min(cs.sliceCount(), static_cast<std::size_t>(boundary(w)) * kSliceChunk);
    return (std::size_t{cs.row_begin.empty() ? 0u : cs.row_begin[s]} + kLaneWork * s) * L;
  };
  const auto start = [&](int p) -> Index {
    if (p <= 0) return 0;
    if (p >= parts) return chunks;
    const auto scale = static_cast<std::size_t>(parts);
    const std::size_t target = work(windows) * static_cast<std::size_t>(p);  // times `parts`
    Index lo = 0, hi = windows;  // the last window w with work(w) * parts <= target
    while (hi - lo > 1) {
      const Index w = (lo + hi) / 2;
      if (work(w) * scale <= target)
        lo = w;
      else
        hi = w;
    }
    const std::size_t below = target - work(lo) * scale;
    const bool next_nearer = lo < windows && work(lo + 1) * scale - target < below;
    return boundary(next_nearer ? lo + 1 : lo);
  };
  return {start(part), start(part + 1)};
}

// Runs body(run) for each work item of the calling thread's part
// (workItemPart): the same in every pass and step (the note on work sharing
// above). Called by every thread of a parallel region; ends with a barrier.
template <class Body>
void forOwnWorkItems(const ConnectionSlices& cs, Body&& body) {
  const auto [first, second] = workItemPart(cs, parallel::threadIndex(), parallel::threadCount());
  for (Index cc = first; cc < second; ++cc) body(SliceRun(cs, cc));
  parallel::barrier();
}

// k_ij = c_ij W(r, h1) (eq. 7), W written as CubicKernel::W: one expression
// for every pass that needs k_ij, so that each recomputes the same bits.
struct SpringKernel {
  float inv_h, norm_w;  // W(r, h1): 1/h1, 1/(4 pi h1^3)
  explicit SpringKernel(const CubicKernel& k1) : inv_h(1.0f / k1.h()), norm_w(k1.W(0.0f) / 4.0f) {}
};
inline float springCoefficient(float strength, float r, float inv_h, float norm_w) {
  return strength * cubicW(r, inv_h, norm_w);
}

}  // namespace loosehair
