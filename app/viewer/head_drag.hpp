// Moving the head with the mouse (issue: interactive viewer): a drag turns
// the head about the base of its neck, or (with Shift) moves it in the
// plane of the screen; the result is the pose the live head heads for.
#pragma once

#include "loosehair/live_head.hpp"
#include "loosehair/mesh.hpp"
#include "loosehair/render/renderer.hpp"

namespace loosehair::viewer {

/// The pivot a head turns about: the middle of the bottom of its mesh (the
/// base of the neck on a head-and-neck mesh, the bottom of a sphere), head
/// frame.
glm::dvec3 neckPivot(const TriangleMesh& head);

class HeadDrag {
 public:
  explicit HeadDrag(glm::dvec3 pivot) : pivot_(pivot) {}
  /// A mouse move of (dx, dy) pixels while dragging, seen from `camera`:
  /// turns (yaw from dx, pitch from dy, 0.3 degrees a pixel, within +-80
  /// degrees) or, with `move`, shifts the head in the screen plane (1 mm a
  /// pixel, within 0.3 m).
  void drag(double dx, double dy, bool move, const render::Camera& camera);
  void reset();
  HeadKeyframe pose() const { return turnAbout(pivot_, euler_deg_, offset_); }
  const glm::dvec3& pivot() const { return pivot_; }
  /// A new head (another scene): the pivot moves, the pose is reset.
  void setPivot(glm::dvec3 pivot) {
    pivot_ = pivot;
    reset();
  }
  const glm::dvec3& eulerDeg() const { return euler_deg_; }

 private:
  glm::dvec3 pivot_;
  glm::dvec3 euler_deg_{0.0}, offset_{0.0};
};

}  // namespace loosehair::viewer
