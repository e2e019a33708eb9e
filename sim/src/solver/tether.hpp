// Tethers (long-range attachments; our addition to method.md §5's strain limit):
// a particle may be no further from its own root point than its arc length
// allows, |x_i - r_i| <= (1 + slack) s_i. This is the no-stretch promise
// itself, enforced per particle in O(N) without adding shear stiffness, so
// the springs can be soft enough for the hair to bend and swing.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair::tether {

/// How far out of a body a pushed particle is put (m), so that rounding
/// does not leave it a hair's breadth inside.
inline constexpr float kSkin = 1e-6f;

/// A pushed-out particle farther from its root than (1 + slack) s_i +
/// kTrappedExcess L (L the longest hair's arc length) is caught where the
/// tether and the body disagree (Solver::freeTrappedHair). In units of L,
/// as the no-stretch promise is: an excess relative to s_i freed particles
/// next to their roots a fraction of a millimetre beyond reach, which the
/// springs threw back every few steps.
inline constexpr float kTrappedExcess = 0.005f;

/// x moved along the line to `root` until it is within `reach` of it.
inline glm::vec3 within(const glm::vec3& x, const glm::vec3& root, float reach) {
  const glm::vec3 d = x - root;
  const float dist = glm::length(d);
  return dist > reach ? root + (reach / dist) * d : x;
}

/// A particle pushed out of a body onto its surface (outward normal n) where
/// the straight line to its root runs through the body: the tether pulls it
/// in and the body pushes it back, so neither is met (hair caught under the
/// flat bottom of a bust stretched by 2.3%). What both allow is a move in the
/// surface's tangent plane towards the root: far enough to come within
/// reach, if the plane comes that near, but no further than the tether
/// itself would have moved the particle (|x - root| - reach), so the slide
/// adds no more speed than the tether does. Unbounded, the few-centimetre
/// moves it would take at once threw particles off the body.
inline glm::vec3 slideAlongSurface(const glm::vec3& x, const glm::vec3& n, const glm::vec3& root, float reach) {
  const glm::vec3 to_root = root - x;
  const float d2 = glm::dot(to_root, to_root);
  const float over2 = d2 - reach * reach;
  if (!(over2 > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 e = to_root - glm::dot(to_root, n) * n;  // towards the root in the plane
  const float a = glm::length(e);
  if (!(a > 0.0f)) return glm::vec3(0.0f);
  // x + t e/a is within reach for t >= a - sqrt(a^2 - over2); no nearer than t = a
  const float t = a * a > over2 ? a - std::sqrt(a * a - over2) : a;
  return (std::min(t, std::sqrt(d2) - reach) / a) * e;
}

/// The farthest point from `from` towards `to` on the segment between them
/// that is within `reach` of `root`, as the fraction t in [0, 1] of the way
/// (`from` must be within reach; -1 when it is not).
inline float farthestWithin(const glm::vec3& from, const glm::vec3& to, const glm::vec3& root, float reach) {
  const glm::vec3 a = from - root, d = to - from;
  const float c = glm::dot(a, a) - reach * reach;
  if (!(c <= 0.0f)) return -1.0f;
  const float dd = glm::dot(d, d);
  if (!(dd > 0.0f)) return 0.0f;
  // |a + t d|^2 = reach^2: dd t^2 + 2 (a.d) t + c = 0, c <= 0, so one root >= 0
  const float b = glm::dot(a, d);
  const float t = (-b + std::sqrt(std::max(0.0f, b * b - dd * c))) / dd;
  return std::clamp(t, 0.0f, 1.0f);
}

}  // namespace loosehair::tether
