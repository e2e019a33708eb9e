// Fixed-radius neighbour search on a hashed voxel grid (SPEC §1 step 1).
//
// Points are sorted by the Morton code of their cell (radix sort, stable, so
// ties keep index order); occupied cells are found in an open-addressing hash
// table. Memory is O(N) whatever the bounding box: a particle flung far away
// costs one more occupied cell, not a larger grid. Build time is O(N) for a
// bounded number of points per cell.
//
// Neighbour order is stable: for each point, the neighbour cells are visited
// in a fixed order (dz, dy, dx from -1 to 1) and the points of a cell in
// index order. It does not depend on the thread count.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

class NeighborGrid {
 public:
  /// Finds, for every point i, every other point j with |x_i - x_j| < radius.
  /// The cell size is `radius` (2*h2 for the solver). Non-finite points get
  /// no neighbours.
  void build(std::span<const glm::vec3> x, float radius, int threads);

  /// Neighbours of point i (without i itself), in stable order.
  std::span<const std::uint32_t> neighbors(std::size_t i) const {
    return {begin_[i], count_[i]};
  }
  std::size_t pointCount() const { return count_.size(); }
  /// Number of ordered pairs (each unordered pair counts twice).
  std::size_t pairCount() const;
  std::size_t cellCount() const { return cell_key_.size(); }

  /// The Morton key of the cell holding point p for a cell size 1/inv_cell.
  static std::uint64_t cellKey(const glm::vec3& p, float inv_cell);

 private:
  void sortByCell(std::span<const glm::vec3> x);
  void buildCellTable();
  std::uint32_t findCell(std::uint64_t key) const;

  float radius_ = 0, inv_cell_ = 0;
  std::vector<std::uint64_t> keys_, keys_tmp_;
  std::vector<std::uint32_t> order_, order_tmp_;
  std::vector<glm::vec3> sorted_x_;
  std::vector<std::uint64_t> cell_key_;
  std::vector<std::uint32_t> cell_start_;  // cellCount()+1 offsets into order_
  std::vector<std::uint32_t> table_;       // hash slot -> cell index + 1 (0: empty)
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;

  std::vector<std::vector<std::uint32_t>> buffers_;  // one per thread
  std::vector<const std::uint32_t*> begin_;
  std::vector<std::uint32_t> count_;
  std::vector<std::uint32_t> offset_;  // into the owning thread's buffer
};

}  // namespace loosehair
