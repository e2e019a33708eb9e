#include "loosehair/render/frame.hpp"

#include <glm/geometric.hpp>

namespace loosehair::render {

FrameInput frameFromSolver(const Solver& solver, float spacing) {
  FrameInput f;
  solver.worldPositions(f.position);
  solver.worldDirections(f.direction);
  std::vector<glm::vec3> v;
  solver.worldVelocities(v);
  f.speed.resize(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) f.speed[i] = glm::length(v[i]);
  const auto density = solver.density();
  f.density.assign(density.begin(), density.end());
  const auto& c = solver.connections();
  const float reach2 = 4.0f * solver.params().h1 * solver.params().h1;
  for (std::size_t i = 0; i < c.particleCount(); ++i)
    for (std::uint32_t e = c.begin(i); e < c.end(i); ++e) {
      const std::uint32_t j = c.partner[e];
      if (j <= i) continue;
      const glm::vec3 d = f.position[j] - f.position[i];
      if (glm::dot(d, d) < reach2) f.connections.insert(f.connections.end(), {static_cast<std::uint32_t>(i), j});
    }
  f.spacing = spacing;
  f.head_pose = headToWorld(solver.trajectory().pose(solver.time()));
  return f;
}

glm::mat4 headToWorld(const HeadPose& pose) {
  glm::mat4 m(1.0f);
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) m[col][row] = static_cast<float>(pose.rotation[col][row]);
  m[3] = glm::vec4(glm::vec3(pose.center), 1.0f);
  return m;
}

}  // namespace loosehair::render
