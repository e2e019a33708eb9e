// The implicit spring solve of the step (implicit_springs.hpp): its input
// from the spring pass and the forces, its velocity change the next start.
#include "solver/implicit_spring_step.hpp"

#include "solver/connection_passes.hpp"
#include "solver/spring_scratch.hpp"

namespace loosehair {

ImplicitSpringReport solveImplicitSpringStep(const ImplicitStepSettings& settings, const SlicedConnections& sliced,
                                             const SpringScratch& s, std::span<const glm::vec3> force,
                                             std::span<const float> mass, std::span<const std::uint8_t> is_root,
                                             float dt, ImplicitSprings& solver, std::vector<glm::vec3>& velocity_change,
                                             int threads) {
  ImplicitSprings::Input in;
  in.layout = &sliced.layout;
  in.weight = s.weight.data();
  in.unit_x = s.unit_x.data();
  in.unit_y = s.unit_y.data();
  in.unit_z = s.unit_z.data();
  in.pull = s.pull.data();
  in.force = force.data();
  in.mass = mass.data();
  in.is_root = is_root.data();
  in.particles = mass.size();
  in.dt = dt;
  in.gamma = settings.damping;
  in.tolerance = settings.tolerance;
  in.max_iterations = settings.max_iterations;
  // warm start from the last step's answer
  if (velocity_change.size() == mass.size()) in.guess = velocity_change.data();
  return solver.solve(in, threads, velocity_change);
}

}  // namespace loosehair
