// Blocked pair loops for the solver's stages.
//
// A pair loop (particle i against its neighbours or connections j) runs over
// blocks of consecutive particles in three phases:
//  1. gather: each pair's inputs are copied into contiguous columns
//     (x_j - x_i, v_j, t_j, ... one float column each);
//  2. compute: each pair's term is computed element-wise over the columns,
//     in loops without branches that the compiler vectorises;
//  3. reduce: each particle sums its pairs' terms in list order.
// Element-wise IEEE arithmetic (no contraction, no fast-math) gives the same
// bits vectorised or not, and the sums keep the list order, so the result
// does not depend on the vector width or the thread count (method.md §5
// Determinism). Nor on which thread takes which block: each thread takes one
// contiguous range of blocks with about equal pairs
// (NeighborGrid::pairBalancedPart), the same part of the hair in every step
// (solver.cpp, the note on work sharing); the work per block varies where the
// hair bunches, and equal numbers of blocks once left one thread idle.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

/// Particles per block: enough pairs for long vector loops, few enough that
/// a block's columns stay in the first-level caches.
inline constexpr std::size_t kPairBlock = 64;

// The element-wise compute phase of a pair loop is compiled for several
// x86-64 levels (AVX-512, AVX2, baseline SSE2) and the loader picks the best
// one the CPU has (GCC function multiversioning, an ifunc). The arithmetic is
// the same IEEE operations in every version (no contraction, no fast-math;
// vector sqrt and division are correctly rounded), so every version gives
// the same bits: the golden state hashes, made with the baseline, check it.
// -DLOOSEHAIR_MULTIVERSION=OFF builds the baseline alone.
#if defined(LOOSEHAIR_MULTIVERSION) && defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    defined(__linux__)
#define LOOSEHAIR_PAIR_KERNEL __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define LOOSEHAIR_PAIR_KERNEL
#endif

/// Float columns of one block's pairs, reused from block to block. One per
/// thread (see threadColumns()).
class PairColumns {
 public:
  /// Room for `pairs` rows in `columns` columns (contents are not kept).
  void reserve(std::size_t pairs, int columns) {
    // 64-byte rows, and an odd number of them from one column to the next:
    // column c then starts in cache set c * stride / 16 (mod the set
    // count), all different for the 17 columns, where an even count, say
    // 1024 floats, a 64-particle block's pairs at 200k particles, put every
    // column in the same set of the first-level cache and made the
    // hair-hair pass 1.7x slower (README).
    std::size_t stride = (pairs + 15) & ~std::size_t{15};
    if ((stride / 16) % 2 == 0) stride += 16;
    if (stride > stride_ || columns > columns_) {
      stride_ = std::max(stride, stride_);
      columns_ = std::max(columns, columns_);
      data_.assign(stride_ * static_cast<std::size_t>(columns_) + 16, 0.0f);
    }
  }
  float* operator[](int c) { return data_.data() + static_cast<std::size_t>(c) * stride_; }
  /// Floats from one column to the next.
  std::size_t stride() const { return stride_; }

 private:
  std::vector<float> data_;
  std::size_t stride_ = 0;
  int columns_ = 0;
};

/// The calling thread's columns (team threads keep theirs across steps).
inline PairColumns& threadColumns() {
  static thread_local PairColumns columns;
  return columns;
}

/// Slices per work item of a connection pass over ConnectionSlices (64
/// particles, as kPairBlock).
inline constexpr std::size_t kSliceChunk = 4;

/// A connection pass's columns for one run of slices: per entry (the
/// partners' gathered values) and per lane (the owners' values and sums).
class SliceColumns {
 public:
  void reserve(std::size_t entries, int entry_columns, std::size_t lanes, int lane_columns) {
    entries_.reserve(entries, entry_columns);
    lanes_.reserve(lanes, lane_columns);
  }
  float* entry(int c) { return entries_[c]; }
  float* lane(int c) { return lanes_[c]; }
  std::size_t entryStride() const { return entries_.stride(); }
  std::size_t laneStride() const { return lanes_.stride(); }

 private:
  PairColumns entries_, lanes_;
};

inline SliceColumns& threadSliceColumns() {
  static thread_local SliceColumns columns;
  return columns;
}

}  // namespace loosehair
