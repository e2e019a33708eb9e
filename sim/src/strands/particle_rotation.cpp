#include "strands/particle_rotation.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <Eigen/LU>
#include <Eigen/SVD>

#include <cmath>

namespace loosehair {

namespace {

// where the iteration has not settled (rad an iteration at its last)
constexpr float kPolarFallbackAngle = 1e-5f;

glm::quat shortestArc(glm::vec3 from, glm::vec3 to) {
  const float c = glm::dot(from, to);
  if (c < -0.9999f) {  // opposite: half a turn about any axis across `from`
    glm::vec3 axis = glm::cross(from, glm::vec3(1, 0, 0));
    if (glm::dot(axis, axis) < 1e-6f) axis = glm::cross(from, glm::vec3(0, 1, 0));
    return glm::angleAxis(3.14159265f, glm::normalize(axis));
  }
  const glm::vec3 axis = glm::cross(from, to);
  return glm::normalize(glm::quat(1.0f + c, axis.x, axis.y, axis.z));
}

// The turn about the unit axis n that maximises trace(T(theta)^T M):
// trace = cos(theta) (tr M - n.M n) + sin(theta) n.w + n.M n, w the axial
// vector of M - M^T, so theta = atan2(n.w, tr M - n.M n).
glm::quat bestTwist(const glm::mat3& m, glm::vec3 n) {
  const glm::vec3 w(m[1][2] - m[2][1], m[2][0] - m[0][2], m[0][1] - m[1][0]);
  const float tr = m[0][0] + m[1][1] + m[2][2];
  const float sin_part = glm::dot(n, w), cos_part = tr - glm::dot(n, m * n);
  // nothing across the axis (a neighbourhood along the hair only): no turn
  const float scale = std::abs(tr) + glm::length(w);
  if (!(std::abs(sin_part) + std::abs(cos_part) > 1e-5f * scale)) return glm::quat(1, 0, 0, 0);
  return glm::angleAxis(std::atan2(sin_part, cos_part), n);
}

}  // namespace

glm::mat3 rotationPart(const glm::mat3& a, glm::vec3 rest_dir, glm::vec3 dir) {
  // Start: the hair direction carried over, then the best turn about it
  // (for a rigid neighbourhood, A = R S, this is R itself), then refine.
  const glm::quat arc = shortestArc(rest_dir, dir);
  glm::quat q = glm::normalize(arc * bestTwist(glm::transpose(glm::mat3_cast(arc)) * a, rest_dir));
  // trace(R^T A): how well R lines up with A's columns
  auto alignment = [&](const glm::mat3& r) {
    return glm::dot(r[0], a[0]) + glm::dot(r[1], a[1]) + glm::dot(r[2], a[2]);
  };
  constexpr int kMaxIterations = 24;
  float angle = 0.0f;
  for (int it = 0; it < kMaxIterations; ++it) {
    const glm::mat3 r = glm::mat3_cast(q);
    // the torque that turns R towards A's columns, over their alignment
    const glm::vec3 torque = glm::cross(r[0], a[0]) + glm::cross(r[1], a[1]) + glm::cross(r[2], a[2]);
    const float align = std::abs(alignment(r));
    const glm::vec3 omega = torque / (align + 1e-20f);
    angle = glm::length(omega);
    if (!(angle > 1e-7f)) break;
    q = glm::normalize(glm::angleAxis(angle, omega / angle) * q);
  }
  const glm::mat3 iterated = glm::mat3_cast(q);
  // The iteration crawls where A is ill-conditioned: on the bundled hang
  // and head-shake, 6 % of the neighbourhoods still turned by more than
  // 1e-3 rad an iteration at the 24th. There the answer is taken from A's
  // polar decomposition (the rotation nearest A, U diag(1, 1, det) V^T of
  // its SVD) when it aligns better, so it does not depend on the start.
  if (!(angle > kPolarFallbackAngle)) return iterated;
  Eigen::Matrix3f m;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m(r, c) = a[c][r];
  const Eigen::JacobiSVD<Eigen::Matrix3f> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3f u = svd.matrixU();
  const Eigen::Matrix3f v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0f) u.col(2) *= -1.0f;
  const Eigen::Matrix3f polar = u * v.transpose();
  glm::mat3 nearest;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) nearest[c][r] = polar(r, c);
  return alignment(nearest) > alignment(iterated) ? nearest : iterated;
}

}  // namespace loosehair
