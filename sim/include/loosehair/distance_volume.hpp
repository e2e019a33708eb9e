// A body's signed distance sampled on a regular grid around it, for the
// strands' push out of the bodies on the GPU (interpolated trilinearly by
// render/shaders/strand_carry.comp). Exact at the grid's
// points near the surface, a lower bound farther out, the body's own fast
// approximation deep inside.
#pragma once

#include "loosehair/body.hpp"

#include <glm/ext/vector_int3.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace loosehair {

struct DistanceVolumeOptions {
  /// Grid spacing (m); coarser where the body is too large for max_points.
  float voxel = 0.002f;
  /// Grid points along the longest side at most (8..1024).
  int max_points = 192;
  /// Points nearer the surface than this many voxels hold the exact signed
  /// distance (>= 2: a point within a voxel's diagonal of the surface then
  /// interpolates exact values only).
  float exact_voxels = 3.0f;
};

struct DistanceVolume {
  glm::vec3 lower{0.0f};  // where value (0, 0, 0) sits (body frame)
  float voxel = 0.0f;     // grid spacing (m)
  glm::ivec3 dims{0};
  std::vector<float> values;  // x fastest, then y, then z (m, negative inside)
  float exact_band = 0.0f;    // values below this are exact (m)

  glm::vec3 upper() const { return lower + voxel * glm::vec3(dims - 1); }
  float at(int i, int j, int k) const {
    return values[(static_cast<std::size_t>(k) * static_cast<std::size_t>(dims.y) + static_cast<std::size_t>(j)) *
                      static_cast<std::size_t>(dims.x) +
                  static_cast<std::size_t>(i)];
  }
  /// The trilinear interpolant at p (clamped to the grid's box), as
  /// render/shaders/strand_carry.comp interpolates it.
  float sample(const glm::vec3& p) const;
};

/// `body`'s signed distance on a grid over its bounds (Body::bounds) and a
/// margin, sampled on `threads` threads (the same values for any count).
/// Throws std::invalid_argument if the body has no bounds or the options
/// are out of range.
DistanceVolume sampleDistanceVolume(const Body& body, const DistanceVolumeOptions& options = {}, int threads = 1);

}  // namespace loosehair
