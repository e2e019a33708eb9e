// How much of the scalp a style's hair covers (issue 44): the share of the
// scalp's hair region (its area) that has a strand root within a radius,
// and where it has none (the styling mode's coverage view).
#pragma once

#include "loosehair/head_model.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace loosehair {

struct ScalpCoverage {
  double covered = 0.0;         // share of the sampled area with a root within the radius (0..1)
  std::vector<glm::vec3> bare;  // the sample points with none
  std::size_t samples = 0;
};

/// The scalp sampled evenly by area (`samples` points, the same every call)
/// against the strand `roots` (head frame): a point is covered when a root
/// lies nearer than `radius` (m). Throws std::invalid_argument for a radius not
/// in (0, 0.1] or no samples.
ScalpCoverage scalpCoverage(const HeadModel& head, const std::vector<glm::vec3>& roots, float radius = 0.005f,
                            std::size_t samples = 4000);

}  // namespace loosehair
