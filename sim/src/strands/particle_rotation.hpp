// The rotation part of a particle neighbourhood's deformation (shape
// matching), for the strands the particles carry.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace loosehair {

/// The rotation R maximising trace(R^T A) (the rotation of A's polar
/// decomposition where det A > 0), by the iteration of Müller, Bender,
/// Chentanez and Macklin ("A Robust Method to Extract the Rotational Part
/// of Deformations", 2016), started from the shortest-arc rotation taking
/// `rest_dir` to `dir` (both unit), so the answer depends on A and the
/// directions only, not on any earlier frame. A = R S with S symmetric
/// positive definite gives R to rounding. Where the iteration has not
/// settled after its cap (an ill-conditioned A), the SVD's polar rotation
/// is taken when it aligns better.
glm::mat3 rotationPart(const glm::mat3& a, glm::vec3 rest_dir, glm::vec3 dir);

}  // namespace loosehair
