// A closed mesh as a collision body (method.md §5 body collisions): the baked
// grid answers far from the surface; where it leaves a contact in doubt
// (the trilinear interpolant of a 1-Lipschitz function is within sqrt(3)
// voxels of it), the exact distance to the triangles decides.
#include "loosehair/body.hpp"

#include "mesh/exact_distance.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace loosehair {

MeshBody::MeshBody(const TriangleMesh& mesh, std::shared_ptr<const GridSdfBody> grid) : grid_(std::move(grid)) {
  if (!grid_) throw std::invalid_argument("MeshBody: no grid");
  exact_ = std::make_unique<ExactDistance>(mesh);
  // sqrt(3/4) voxel for the interpolation, as much for the values' excess
  // over the distance (the bake keeps it below GridSdfBody::kFarAllowance)
  static_assert(GridSdfBody::kFarAllowance < 0.8660254f);
  grid_error_ = 1.7321f * grid_->voxelSize() * 1.001f + 1e-7f;
  lower_ = glm::vec3(INFINITY);
  upper_ = glm::vec3(-INFINITY);
  for (const glm::vec3& v : mesh.vertices) {
    lower_ = glm::min(lower_, v);
    upper_ = glm::max(upper_, v);
  }
}

bool MeshBody::bounds(glm::vec3& lower, glm::vec3& upper) const {
  if (!(lower_.x <= upper_.x)) return false;
  lower = lower_;
  upper = upper_;
  return true;
}

MeshBody::~MeshBody() = default;

void MeshBody::refine(const glm::vec3* p, std::size_t n, float limit, float deep, float* phi, glm::vec3* normal,
                      std::int32_t* hint) const {
  for (std::size_t k = 0; k < n; ++k) {
    const float g = phi[k];
    if (!(g < limit + grid_error_)) {
      // The true distance is at least g - error >= limit: a lower bound.
      phi[k] = std::max(limit, g - grid_error_);
      continue;
    }
    if (!(g > -deep)) continue;  // far inside: the grid's push comes first
    if (!std::isfinite(p[k].x + p[k].y + p[k].z)) continue;
    const GridSdfBody::Cell cell = grid_->cell(p[k]);
    if (cell.lower >= limit) {  // the corners prove it
      phi[k] = std::max(phi[k] - grid_error_, cell.lower);
      continue;
    }
    // The nearest triangles of the cell's corners, and the point's own from
    // its last query (it moved little since), make the search's ball small
    // from the start.
    std::int32_t seeds[GridSdfBody::Cell::kMaxTriangles + 1];
    int count = 0;
    if (hint && hint[k] >= 0) seeds[count++] = hint[k];
    for (int c = 0; c < cell.triangles; ++c) seeds[count++] = cell.triangle[c];
    ExactDistance::Nearest near;
    if (!exact_->nearest(p[k], std::fabs(g) + grid_error_, seeds, count, near) &&
        !exact_->nearest(p[k], std::numeric_limits<float>::infinity(), seeds, count, near))
      continue;
    if (hint) hint[k] = static_cast<std::int32_t>(near.triangle);
    phi[k] = near.signed_distance;
    normal[k] = near.normal;
    // Far enough from the surface the grid's sign (from flooding the
    // outside) is certain; it wins where a few misoriented triangles would
    // mislead the pseudo-normal.
    if (std::fabs(g) > grid_error_ && (g < 0.0f) != (phi[k] < 0.0f)) {
      phi[k] = -phi[k];
      normal[k] = -normal[k];
    }
  }
}

void MeshBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const {
  grid_->signedDistance(p, n, phi, normal);
  // Exact within two grid errors of the surface; beyond, the grid's value
  // (within its error) stands.
  const float band = 2.0f * grid_error_;
  for (std::size_t k = 0; k < n; ++k) {
    if (!(std::fabs(phi[k]) < band)) continue;
    refine(&p[k], 1, std::numeric_limits<float>::max(), band, &phi[k], &normal[k]);
  }
}

void MeshBody::signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                                   glm::vec3* normal) const {
  signedDistanceBelowHinted(p, n, limit, phi, normal, nullptr);
}

void MeshBody::signedDistanceBelowHinted(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal,
                                         std::int32_t* hint) const {
  if (!(limit < std::numeric_limits<float>::max())) {
    signedDistance(p, n, phi, normal);
    return;
  }
  grid_->signedDistanceBelow(p, n, limit + grid_error_, phi, normal);
  refine(p, n, limit, std::numeric_limits<float>::infinity(), phi, normal, hint);
}

void MeshBody::roughDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal) const {
  grid_->signedDistanceBelow(p, n, limit, phi, normal);
}

}  // namespace loosehair
