// Rotation-minimising frames along a polyline (Bloomenthal 1990), computed
// by the double-reflection method of Wang, Jüttler, Zheng and Liu (2008):
// each frame is carried to the next point by a reflection in the bisecting
// plane of the chord, then by a second reflection that takes the reflected
// tangent onto the next tangent. The frames do not twist about the curve
// and, unlike the Frenet frame, do not flip where the curvature vanishes.
// Member strands express their offsets in these frames (method.md §6.2).
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace loosehair {

struct CurveFrame {
  glm::vec3 tangent, normal, binormal;  // orthonormal, binormal = tangent x normal
};

/// Unit tangents of a polyline (central differences; one-sided at the ends).
std::vector<glm::vec3> polylineTangents(const std::vector<glm::vec3>& points);

/// Frames at every point of `points` (at least 2, no two consecutive equal).
/// The first frame's normal is `reference` made orthogonal to the first
/// tangent (any orthogonal direction if `reference` is parallel to it).
std::vector<CurveFrame> rotationMinimizingFrames(const std::vector<glm::vec3>& points, glm::vec3 reference);

}  // namespace loosehair
