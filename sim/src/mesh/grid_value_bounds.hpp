// The baked grid's far values kept within what the clearance proofs allow
// (method.md §5 body collisions; docs/design.md "Contacts against the exact
// surface").
//
// MeshBody takes the grid's trilinear answer less sqrt(3) voxels as a lower
// bound of the exact distance. The interpolant of the exact distance is
// within sqrt(3/4) voxel of it (the corners' weighted distance from the
// point), so the bound holds while no voxel's value exceeds its exact
// distance by more than the other sqrt(3/4) voxel. The voxels near the
// surface hold the exact distance; farther ones the mesh-to-volume
// conversion's value, the distance to some triangle (never below the
// nearest) or the band's width where the conversion stops, which ends up to
// a voxel short of it on some meshes (the bundled head and torso: 6 and 14
// voxels over 0.8 voxel, the worst 1.00). Here each such value is checked
// against the triangles, and one over the allowance gets its exact signed
// distance and nearest triangle.
#pragma once

#include "mesh/exact_distance.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace loosehair {

struct GridValues {
  glm::vec3 lower{0.0f};            // world position of voxel (0, 0, 0)
  float voxel = 0.0f;               // edge length (m)
  glm::ivec3 dims{0};               // voxels along x, y, z (x fastest)
  std::span<float> value;           // signed distance (m), < 0 inside
  std::span<std::int32_t> nearest;  // nearest triangle, -1 if unknown
};

/// Every voxel with a value of at least `exact_from` (m; the nearer ones are
/// exact already) whose exact signed distance lies more than `allowance` (m)
/// below its value gets the exact signed distance and its nearest triangle
/// (also a voxel outside by its value but inside a part whose surface is
/// nearer than the value less the allowance). Each voxel is independent, so
/// the result does not depend on `threads`. Returns how many changed.
std::size_t boundFarValues(const ExactDistance& exact, const GridValues& grid, float exact_from, float allowance,
                           int threads);

}  // namespace loosehair
