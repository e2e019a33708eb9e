// The implicit spring solve of the step (implicit_springs.hpp): its input
// from the spring pass and the forces, its velocity change the next start.
#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- implicit springs: the velocity change of the step (implicit_springs.hpp)
void Solver::solveSpringsImplicitly(const Scratch& s, const std::vector<glm::vec3>& force, float dt) {
  if (!implicit_) implicit_ = std::make_unique<ImplicitSprings>();
  ImplicitSprings::Input in;
  in.layout = &sliced_->layout;
  in.weight = s.weight.data();
  in.unit_x = s.unit_x.data();
  in.unit_y = s.unit_y.data();
  in.unit_z = s.unit_z.data();
  in.pull = s.pull.data();
  in.force = force.data();
  in.mass = particles_.mass.data();
  in.is_root = particles_.is_root.data();
  in.particles = particles_.size();
  in.dt = dt;
  in.gamma = params_.spring_damping;
  in.tolerance = params_.implicit_tolerance;
  in.max_iterations = params_.implicit_iterations;
  // warm start from the last step's answer (kept in snapshots)
  if (spring_dv_.size() == particles_.size()) in.guess = spring_dv_.data();
  const ImplicitSpringReport rep = implicit_->solve(in, threads_, spring_dv_);
  stats_.spring_iterations = rep.iterations;
  stats_.spring_residual = rep.residual;
}

}  // namespace loosehair
