// Letting the physics finish a style (issue 44): the style's hair is grown
// as a scene would grow it, simulated on a still head for a while with the
// plain LCP physics (gravity, the head and torso, hair-hair, the ties; no
// shape keeping), and each wisp's key strand is read back where its hair
// came to lie. A rough sketch of a style becomes hair lying on the head.
//
//   std::vector<std::vector<glm::vec3>> keys = settledKeyStrands(style);
//   editor.setKeyStrands(keys);  // one undo step
#pragma once

#include "loosehair/style.hpp"

#include <glm/vec3.hpp>

#include <vector>

namespace loosehair {

struct SettleOptions {
  /// Simulated time (s, in (0, 10]).
  double seconds = 1.5;
  /// Particles the hair is grown with (200..20000): fewer settle sooner.
  int particles = 3000;
  /// Solver threads (0: the solver's choice; the result does not depend on it).
  int threads = 0;
};

/// Each wisp's key strand after the settle: each control point where the
/// hair carried the point of the key strand it was (render strands' carry,
/// StrandField), 3 mm out of the head and torso, the root where it was.
/// A span whose spline would pass into the head gets the carried point
/// halfway along it as a new control point, so the result always passes
/// checkStyle; otherwise as many control points as before. Throws
/// StyleError for a style without wisps or out-of-range options, and what
/// growing the scene throws (SceneError) for a style that cannot be grown.
std::vector<std::vector<glm::vec3>> settledKeyStrands(const Style& style, const SettleOptions& options = {});

}  // namespace loosehair
