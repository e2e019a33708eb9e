// Fixed-radius neighbour search on a voxel grid (method.md §1 step 1), cell size
// = the search radius, linear in N.
//
// Two layouts, chosen per build:
//  - dense: when the points' bounding box has at most 16N cells, points
//    are counting-sorted by linear cell index (x fastest), so the three
//    x-neighbouring cells of a row are one contiguous range and a cell's
//    neighbourhood is 9 ranges read straight from an array;
//  - hashed: otherwise (a particle flung far away, a huge box), points are
//    radix-sorted by the Morton code of their cell and the 27 neighbouring
//    cells are found in an open-addressing hash table.
// Either way memory is O(N) whatever the bounding box.
//
// Neighbour order is stable: neighbouring cells are visited in a fixed order
// (dz, dy, dx from -1 to 1) and the points of a cell in index order. It does
// not depend on the thread count.
#pragma once

#include <glm/vec3.hpp>

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace loosehair {

class NeighborGrid {
 public:
  /// What the lists hold: the points' indices, or their positions in the
  /// search order (searchOrder()[k] is the point at position k). A pair loop
  /// that works in the search order (the points sorted by cell) reads its
  /// partners' data from a few nearby ranges, however far the points have
  /// moved from their initial order.
  enum class ListIndex { Point, SearchOrder };

  /// Finds, for every point i, every other point j with |x_i - x_j| < radius.
  /// The cell size is `radius` (2*h2 for the solver). Non-finite points get
  /// no neighbours (and send the build to the hashed layout).
  void build(std::span<const glm::vec3> x, float radius, int threads, ListIndex index = ListIndex::Point);

  /// Neighbours of point i (without i itself), in stable order, as point
  /// indices (after a build with ListIndex::Point).
  std::span<const std::uint32_t> neighbors(std::size_t i) const {
    assert(rank_.size() == count_.size() && "neighbors(i) needs a ListIndex::Point build");
    return list(rank_[i]);
  }
  /// The list of the point at position k of the search order, as the
  /// build's ListIndex says. The lists lie in memory in this order (chunk
  /// by chunk), so a loop over k reads them in sequence.
  std::span<const std::uint32_t> list(std::size_t k) const { return {begin_[k], count_[k]}; }
  std::size_t pointCount() const { return count_.size(); }
  /// The points in the order in which the search made their lists.
  std::span<const std::uint32_t> searchOrder() const { return {order_.data(), count_.size()}; }
  /// Number of ordered pairs (each unordered pair counts twice).
  std::size_t pairCount() const;
  /// Points of the search order are listed in chunks of kChunk.
  static constexpr std::size_t kChunk = 512;
  /// Parts of the search order start at multiples of kPartGrain (a divisor
  /// of kChunk).
  static constexpr std::size_t kPartGrain = 64;
  static_assert(kChunk % kPartGrain == 0);
  /// Part `part` of `parts` of the search order, for sharing a loop over its
  /// lists among threads: positions [first, second), contiguous, starting
  /// at multiples of kPartGrain, each with as near its share of the pairs
  /// as such starts allow. The parts of 0..parts-1 cover every position once.
  std::pair<std::size_t, std::size_t> pairBalancedPart(int part, int parts) const;
  /// Occupied cells of the last build.
  std::size_t cellCount() const { return occupied_cells_; }
  /// True if the last build used the dense layout.
  bool usedDenseLayout() const { return dense_; }

  /// Whether the candidate test may use AVX-512 (16 candidates at once)
  /// where the CPU has it; on by default. Both paths accept the same pairs
  /// in the same order (the tests compare them).
  static void setWideSearch(bool on);
  static bool wideSearchAvailable();

  /// The Morton key of the cell holding point p for a cell size 1/inv_cell.
  static std::uint64_t cellKey(const glm::vec3& p, float inv_cell);

 private:
  bool chooseDenseLayout(std::span<const glm::vec3> x, int threads);
  void sortDense(std::span<const glm::vec3> x, int threads);
  void sortHashed(std::span<const glm::vec3> x);
  void gatherSorted(std::span<const glm::vec3> x, int threads);
  void buildCellTable();
  /// Writes the neighbours of sorted point k among the given ranges to out
  /// (room for every candidate plus kRangeSlack per range) and returns their number.
  std::size_t collect(std::size_t k, const std::uint32_t* range_begin, const std::uint32_t* range_end, int nr, float r2,
                      bool point_index, std::uint32_t* out) const;
  std::uint32_t findCell(std::uint64_t key) const;
  /// Point ranges [begin, end) in sorted order of the cells around `cell`,
  /// the cell of sorted point k.
  int neighborRanges(std::uint64_t cell, std::size_t k, std::uint32_t* begin, std::uint32_t* end) const;

  float radius_ = 0, inv_cell_ = 0;
  bool dense_ = false;
  bool wide_ = false;  // the AVX-512 candidate test
  std::size_t occupied_cells_ = 0;
  // dense layout: cell (ix, iy, iz) has index (iz * ny + iy) * nx + ix
  std::int64_t origin_[3] = {0, 0, 0};
  std::int64_t dims_[3] = {0, 0, 0};
  std::vector<std::uint32_t> scan_blocks_;  // sortDense's per-thread block sums
  std::vector<std::uint32_t> dense_start_;  // [0, cells]: offsets into order_ (+1 spare)
  // both layouts: the cell of each sorted point (dense index or Morton key)
  std::vector<std::uint64_t> keys_, keys_tmp_;
  std::vector<std::uint32_t> order_, order_tmp_;
  std::vector<glm::vec3> sorted_x_;
  std::vector<float> sorted_cx_, sorted_cy_, sorted_cz_;  // padded by 4
  std::vector<std::uint64_t> cell_key_;
  std::vector<std::uint32_t> cell_start_;  // cellCount()+1 offsets into order_
  std::vector<std::uint32_t> table_;       // hash slot -> cell index + 1 (0: empty)
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;

  std::vector<std::vector<std::uint32_t>> buffers_;  // one per thread
  // per position k in the search order
  std::vector<const std::uint32_t*> begin_;
  std::vector<std::uint32_t> count_;
  std::vector<std::uint32_t> offset_;  // into the owning thread's buffer
  // per chunk c of kChunk positions: the pairs of chunks [0, c] (for
  // pairBalancedPart), and the build's total
  std::vector<std::size_t> chunk_pairs_end_;
  std::size_t pair_count_ = 0;
  std::vector<std::uint32_t> rank_;  // point i is at position rank_[i] (ListIndex::Point)
};

}  // namespace loosehair
