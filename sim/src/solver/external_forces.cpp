// External forces in the head frame (method.md §5): gravity, air drag, the
// head's inertial forces and shape keeping.
#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- external forces in the head frame (method.md §5) ----------------------------
void Solver::addExternalForces(std::vector<glm::vec3>& force) {
  const std::size_t n = particles_.size();
  const auto& x = particles_.position;
  const auto& v = particles_.velocity;
  const auto& m = particles_.mass;
  const auto& root = particles_.is_root;
  const HeadKinematics head = trajectory_.kinematics(time_);
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 gravity(rt * glm::dvec3(params_.gravity));
  const glm::vec3 frame_accel(rt * head.acceleration);  // R^T c''
  const glm::vec3 frame_vel(rt * head.velocity);        // R^T c'
  const glm::vec3 omega(head.angular_velocity), alpha(head.angular_acceleration);
  const float drag = params_.air_drag;
  const ShapeKeeping* shape = shape_.get();
  parallel::forEach(threads_, static_cast<std::size_t>(n), [&](std::size_t i) {
    if (root[i]) return;
    const glm::vec3 r = x[i], u = v[i];
    const glm::vec3 inertial = frame_accel + glm::cross(alpha, r) + 2.0f * glm::cross(omega, u) +
                               glm::cross(omega, glm::cross(omega, r));
    const glm::vec3 world_velocity = u + glm::cross(omega, r) + frame_vel;
    glm::vec3 a = gravity - inertial - drag * world_velocity;
    if (shape) a += shape->acceleration(i, r);
    force[i] += m[i] * a;
  });
}

}  // namespace loosehair
