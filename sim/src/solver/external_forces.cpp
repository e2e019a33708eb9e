// External forces in the head frame (method.md §5): gravity, air drag, the
// head's inertial forces and shape keeping.
#include "solver/external_forces.hpp"

#include "util/parallel.hpp"
#include "solver/shape_keeping.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

namespace loosehair {

void addExternalForces(const ExternalSettings& settings, const HeadKinematics& head, const ExternalParticles& p,
                       const ShapeKeeping* shape, std::span<glm::vec3> force, int threads) {
  const std::size_t n = p.position.size();
  const auto& x = p.position;
  const auto& v = p.velocity;
  const auto& m = p.mass;
  const auto& root = p.is_root;
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 gravity(rt * glm::dvec3(settings.gravity));
  const glm::vec3 frame_accel(rt * head.acceleration);  // R^T c''
  const glm::vec3 frame_vel(rt * head.velocity);        // R^T c'
  const glm::vec3 omega(head.angular_velocity), alpha(head.angular_acceleration);
  const float drag = settings.air_drag;
  parallel::forEach(threads, n, [&](std::size_t i) {
    if (root[i]) return;
    const glm::vec3 r = x[i], u = v[i];
    const glm::vec3 inertial =
        frame_accel + glm::cross(alpha, r) + 2.0f * glm::cross(omega, u) + glm::cross(omega, glm::cross(omega, r));
    const glm::vec3 world_velocity = u + glm::cross(omega, r) + frame_vel;
    glm::vec3 a = gravity - inertial - drag * world_velocity;
    if (shape) a += shape->acceleration(i, r);
    force[i] += m[i] * a;
  });
}

}  // namespace loosehair
