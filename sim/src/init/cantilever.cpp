#include "init/cantilever.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

namespace {
// Height a strand may gain off the surface per unit of arc length while it
// reaches its clearance (method.md §6.1 leaves the first pieces' path open). The
// scene's pieces are at most half a Poisson radius and, where that radius
// sets their number (hair longer than 4 radii; shorter hair gets 8 pieces),
// more than 0.44 of it; its clearance is a quarter of that radius unless
// the contact thickness is more. So with 0.6 the first piece still
// reaches the clearance wherever the radius sets both (the bundled scenes
// at their counts keep their initial state). The rule bites on hair
// shorter than about 3 radii, and where the contact thickness sets the
// clearance: from 10k-15k particles on the bundled head, and at 50k-100k,
// where the pieces are shorter than the clearance, it keeps the first
// pieces from standing the crown's strands straight up.
constexpr float kRise = 0.6f;
}  // namespace

CantileverStrand::CantileverStrand(glm::vec3 root, glm::vec3 dir, glm::vec3 g, float length, float stiffness,
                                   const Body* body, float clearance, float layering, int segments, float needed)
    : length_(length) {
  segments = std::max(1, segments);
  ds_ = length / static_cast<float>(segments);
  // position(s) and tangent(s) read points up to floor(s / ds) + 2
  int grown = segments;
  if (needed >= 0.0f && needed / ds_ < static_cast<float>(segments))
    grown = std::min(segments, static_cast<int>(needed / ds_) + 3);
  g = glm::normalize(g);
  dir = glm::normalize(dir);
  points_.reserve(static_cast<std::size_t>(grown) + 1);
  points_.push_back(root);
  glm::vec3 p = root, tau = dir;
  for (int k = 0; k < grown; ++k) {
    const float s = (static_cast<float>(k) + 0.5f) * ds_;
    const float cos_psi = std::clamp(glm::dot(tau, g), -1.0f, 1.0f);
    const float psi = std::acos(cos_psi);
    const float sin_psi = std::sin(psi);
    const float kappa = (length - s) * (length - s) * sin_psi / (2.0f * stiffness);
    const float turn = std::min(kappa * ds_, psi);
    glm::vec3 towards = g - cos_psi * tau;
    const float tl = glm::length(towards);
    if (tl > 1e-6f && turn > 0.0f) {
      towards /= tl;
      tau = glm::normalize(std::cos(turn) * tau + std::sin(turn) * towards);
    }
    glm::vec3 next = p + ds_ * tau;
    if (body) {
      // The clearance is reached over an arc length of its own (at most
      // kRise of height per unit of arc), not at the first piece: pieces
      // shorter than the clearance (high particle counts) would otherwise be
      // pushed out along the normal and, at the crown, stand straight up.
      const float end = s + 0.5f * ds_;
      const float keep_out = std::min(clearance, kRise * end) + layering * end;
      for (int pass = 0; pass < 3; ++pass) {
        float phi;
        glm::vec3 n;
        // exact below the clearance: several centimetres out, beyond a
        // mesh's narrow band, its grid's normal was any direction (straight
        // up beside a jaw), and turned long strands back up into loops
        body->signedDistanceBelow(&next, 1, keep_out, &phi, &n);
        if (phi >= keep_out) break;
        next += (keep_out - phi) * n;
        tau = glm::normalize(next - p);
        next = p + ds_ * tau;
      }
    }
    points_.push_back(next);
    p = next;
  }
}

glm::vec3 CantileverStrand::position(float s) const {
  const float q = std::clamp(s / ds_, 0.0f, static_cast<float>(points_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(q), points_.size() - 2);
  const float f = q - static_cast<float>(k);
  return points_[k] + f * (points_[k + 1] - points_[k]);
}

glm::vec3 CantileverStrand::tangent(float s) const {
  const float q = std::clamp(s / ds_, 0.0f, static_cast<float>(points_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(q), points_.size() - 2);
  // Blend the two segment directions around s for a continuous tangent.
  const glm::vec3 a = glm::normalize(points_[k + 1] - points_[k]);
  const std::size_t k2 = std::min(k + 1, points_.size() - 2);
  const glm::vec3 b = glm::normalize(points_[k2 + 1] - points_[k2]);
  const float f = q - static_cast<float>(k);
  const glm::vec3 t = (1.0f - f) * a + f * b;
  const float len = glm::length(t);
  return len > 1e-6f ? t / len : a;
}

}  // namespace loosehair
