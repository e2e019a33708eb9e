// Hair ties (our addition to method.md §6.2): where a key strand passes through a
// tie's ring, and which points a tie holds.
#pragma once

#include "loosehair/style.hpp"

#include <optional>
#include <vector>

namespace loosehair {

struct TieCrossing {
  float arc_length;     // along the polyline, where it crosses the ring's plane (m)
  glm::vec3 point;      // the crossing point
  float axis_distance;  // its distance from the ring's axis (m)
};

/// The first crossing of the polyline through the tie's ring (its plane,
/// within the ring's radius), if any.
std::optional<TieCrossing> crossTie(const std::vector<glm::vec3>& polyline, const HairTie& tie);

/// Whether any of the style's key strands (their splines) passes through the
/// tie's ring: a tie that holds none is refused (StyleEditor::addTie,
/// checkStyle).
bool tieHoldsAKeyStrand(const Style& style, const HairTie& tie);

/// Whether a point lies inside the ring: within its radius of the axis and
/// half its width of the ring's plane.
bool insideTie(const HairTie& tie, glm::vec3 p);

}  // namespace loosehair
