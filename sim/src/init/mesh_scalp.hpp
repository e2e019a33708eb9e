// The scalp of a head mesh (method.md §6.1): the part of the surface inside four
// Catmull-Rom curves (front, right, back, left), mapped to the unit square by
// a piecewise-linear harmonic map with the four curves on its four sides:
//
//   front: v = 0, u from 0 (left temple) to 1 (right temple)
//   right: u = 1, v from 0 to 1 (nape)
//   back:  v = 1, u from 1 to 0
//   left:  u = 0, v from 1 to 0
//
// Seen from outside the head the curves run counter-clockwise around the
// scalp. Control points may lie near the surface; they are projected onto it.
#pragma once

#include "init/scalp_surface.hpp"
#include "loosehair/body.hpp"
#include "loosehair/mesh.hpp"

#include <array>
#include <string>
#include <vector>

namespace loosehair {

/// Control points of the four trimming curves, in the order above; curve k
/// ends where curve k+1 starts (its first point is the shared corner).
struct ScalpCurves {
  std::array<std::vector<glm::vec3>, 4> control;
};

/// Curves for any head in the simulator's frame (+Y up, face towards +Z): a
/// hairline over the forehead and the temples, above and behind the ears and
/// across the nape, placed relative to the cranium found in the mesh.
ScalpCurves automaticScalpCurves(const TriangleMesh& head, const Body& head_sdf);

/// What building the map found (for tests and messages).
struct ScalpReport {
  std::size_t triangles = 0, vertices = 0, boundary_vertices = 0;
  std::size_t flipped = 0;          // triangles with non-positive area in (u, v)
  bool mean_value_weights = false;  // cotangent weights flipped triangles; fell back
  double area = 0;                  // m^2
};

class MeshScalp final : public ScalpSurface {
 public:
  /// Trims `head` by the curves and solves the harmonic map. Throws
  /// MeshError (naming `source`) if the curves do not enclose a disc.
  MeshScalp(const TriangleMesh& head, const Body& head_sdf, const ScalpCurves& curves, const std::string& source);

  glm::vec3 point(glm::vec2 uv) const override;
  glm::vec3 normal(glm::vec2 uv) const override;
  glm::vec2 sampleByArea(Random& rng) const override;
  double area() const override { return report_.area; }

  const ScalpReport& report() const { return report_; }
  /// The trimmed scalp: 3-D positions, (u, v) per vertex, triangles.
  const std::vector<glm::vec3>& positions() const { return pos_; }
  const std::vector<glm::vec2>& uvs() const { return uv_; }
  const std::vector<glm::u32vec3>& triangles() const { return tri_; }
  /// Indices of the boundary vertices, in loop order starting at the
  /// front-left corner.
  const std::vector<std::uint32_t>& boundary() const { return boundary_; }
  /// The dense polyline of the trimming curves on the surface.
  const std::vector<glm::vec3>& curvePolyline() const { return polyline_; }

 private:
  void takeSubmesh(const TriangleMesh& head, const std::vector<glm::vec3>& vnormal, const std::vector<char>& in,
                   const std::vector<std::uint32_t>& loop);
  std::vector<char> mapBoundary(const std::vector<std::uint32_t>& loop, const std::array<std::size_t, 4>& corner_at);
  template <class Fail>
  void mapInterior(const std::vector<char>& fixed, const Fail& fail);
  void buildSampling();
  /// Triangle containing uv (or the nearest one) and its barycentrics.
  std::uint32_t locate(glm::vec2 uv, glm::vec3& bary) const;

  std::vector<glm::vec3> pos_, nrm_;
  std::vector<glm::vec2> uv_;
  std::vector<glm::u32vec3> tri_;
  std::vector<std::uint32_t> boundary_;
  std::vector<glm::vec3> polyline_;
  std::vector<double> area_cdf_;
  int buckets_ = 1;
  std::vector<std::uint32_t> bucket_start_, bucket_items_;
  ScalpReport report_;
};

/// Catmull-Rom spline through `points` (at least 2), `per_segment` samples
/// per span, end tangents by reflection. Includes both end points.
std::vector<glm::vec3> catmullRom(const std::vector<glm::vec3>& points, int per_segment);

/// Moves p onto the zero set of the body's distance (a few Newton steps).
glm::vec3 projectToSurface(const Body& body, glm::vec3 p);

}  // namespace loosehair
