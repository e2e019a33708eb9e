// A fine, sparse distance field near a mesh body's surface, for the render
// strands (issue "the real picture at interactive rates"): most strand
// points lie on the scalp, within the coarse grid's error of the surface,
// where each needed an exact triangle query (70 % of a strand frame). The
// body is rigid in its own frame, so the exact signed distance can be
// sampled once on a fine lattice and interpolated.
//
// The lattice is built lazily in bricks of kBrickCells^3 cells where points
// are asked about, so only the part of the body the hair touches costs
// anything. Each lattice value is the body's exact signed distance at that
// corner, whichever thread builds it and whenever, so the answers have the
// same bits for any thread count and any order of queries. Two threads that
// build the same brick at once compute the same values; one of them
// publishes it and the other's copy is dropped.
//
// Error: the trilinear interpolant is a convex combination of the corners'
// exact values and the distance is 1-Lipschitz, so it is within the
// weighted mean distance to the corners, at most sqrt(3)/2 of a voxel (at
// the cell's centre). Its gradient is the normal.
#pragma once

#include <glm/ext/vector_int3.hpp>
#include <glm/vec3.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

namespace loosehair {

class FineBand {
 public:
  /// The exact signed distance at a lattice point; `hint` (in and out) a
  /// triangle to start the search from, -1 if none.
  using Exact = std::function<float(const glm::vec3& p, std::int32_t& hint)>;

  /// A lattice of voxel size `voxel` (m) over the box [lower, upper].
  FineBand(const glm::vec3& lower, const glm::vec3& upper, float voxel, Exact exact);
  ~FineBand();
  FineBand(const FineBand&) = delete;
  FineBand& operator=(const FineBand&) = delete;

  /// The interpolated signed distance at p and its unit gradient. False
  /// where p is outside the box or not finite (the caller asks exactly).
  bool sample(const glm::vec3& p, float& phi, glm::vec3& normal) const;

  float voxel() const { return voxel_; }
  /// How far a sample may lie from the exact distance (m).
  float error() const { return error_; }
  /// Bricks built so far.
  std::size_t bricks() const { return built_.load(std::memory_order_relaxed); }

  static constexpr int kBrickCells = 8;            // cells a brick edge
  static constexpr int kSuperBricks = 8;           // bricks a super-brick edge

 private:
  static constexpr int kSamples = kBrickCells + 1;  // lattice points a brick edge
  struct Brick {
    float value[kSamples * kSamples * kSamples];
  };
  struct Super {
    std::atomic<Brick*> brick[kSuperBricks * kSuperBricks * kSuperBricks] = {};
  };
  const Brick& brick(const glm::ivec3& b) const;
  Brick* build(const glm::ivec3& b) const;

  glm::vec3 lower_;
  float voxel_, inv_voxel_, error_;
  glm::ivec3 cells_;    // cells along each axis
  glm::ivec3 supers_;   // super-bricks along each axis
  Exact exact_;
  std::unique_ptr<std::atomic<Super*>[]> table_;
  mutable std::atomic<std::size_t> built_{0};
};

}  // namespace loosehair
