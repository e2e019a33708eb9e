// Integration (method.md §5): symplectic Euler, with the inelastic,
// frictional body contact applied to the new velocity and speculative
// contacts.
#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- integrate: symplectic Euler with the inelastic, frictional body contact
// applied to the new velocity (method.md §5 body collisions) -------------------------
std::size_t Solver::integrate(StepContext& ctx, const std::vector<BodyFrame>& frames,
                              const HeadKinematics& head) {
  const std::size_t n = particles_.size();
  const float dt = ctx.dt;
  auto& x = particles_.position;
  auto& v = particles_.velocity;
  const auto& m = particles_.mass;
  const auto& root = particles_.is_root;
  const float thickness = params_.contact_thickness, mu = params_.body_friction;
  const bool implicit = params_.implicit_springs;
  const float reach = thickness + kSpeculativeSpeed * dt;
  // the strain limit's first records, (x, 1/m), made here in the same pass
  ctx.strain_records[0].resize(n);
  glm::vec4* strain_record = ctx.strain_records[0].data();
  const float* inv_mass = inverse_mass_.data();
  // the rough answers' worst error over the bodies asked: phi - error is a
  // lower bound of the distance (Body::roughError); a body without such a
  // bound leaves every particle to be asked
  auto error = [](const Body& body) { return body.roughError() < 0.0f ? INFINITY : body.roughError(); };
  float rough_error = error(*head_);
  for (const BodyFrame& f : frames) rough_error = std::max(rough_error, error(*f.body));
  float* clearance = ctx.body_clearance.data();
  glm::vec3* integrated_position = ctx.integrated_position.data();
  std::size_t contacts = 0;
  std::atomic<std::size_t> contacts_sum{0};
  parallel::run(threads_, [&] {
    std::size_t contacts_part = 0;
    const auto [first, last] =
        parallel::share(static_cast<std::size_t>((n + kBodyBlock - 1) / kBodyBlock));
    for (std::size_t bb = first; bb < last; ++bb) {
      const std::size_t b = bb * kBodyBlock;
      const std::size_t e = std::min(n, b + kBodyBlock);
      glm::vec3 surface[kBodyBlock];
      // the velocity response tolerates the grid's error; the projection
      // after the constraints keeps particles out of the exact surface.
      // Beyond the contact thickness, as far as a particle at
      // kSpeculativeSpeed gets in a step: speculative contacts.
      queryBodies(frames, head, &x[b], e - b, &body_phi_[b], &body_normal_[b], surface, reach, true);
      for (std::size_t i = b; i < e; ++i) {
        if (root[i]) {
          strain_record[i] = glm::vec4(x[i], inv_mass[i]);
          continue;
        }
        glm::vec3 vi = v[i] + (implicit ? spring_dv_[i] : (dt / m[i]) * ctx.force[i]);
        if (body_phi_[i] >= thickness && body_phi_[i] < reach) {
          // Speculative: a particle that would go through the contact
          // layer into the body within this step only reaches the layer
          // (the step's penetration, which the projection afterwards turns
          // into an outward push and the tether's excess, stays small at
          // any step).
          const glm::vec3 nrm = body_normal_[i];
          const float vn = glm::dot(vi - surface[i - b], nrm);
          const float allowed = -(body_phi_[i] - thickness) / dt;
          if (vn < allowed) vi += (allowed - vn) * nrm;
        }
        if (body_phi_[i] < thickness) {
          // The response acts on the velocity relative to the body's surface.
          const glm::vec3 us = surface[i - b];
          const glm::vec3 nrm = body_normal_[i];
          const glm::vec3 vr = vi - us;
          const float vn = glm::dot(vr, nrm);
          if (vn < 0.0f) {
            ++contacts_part;
            glm::vec3 vt = vr - vn * nrm;  // inelastic: normal approach removed
            const float vt_len = glm::length(vt);
            const float slip = vt_len - mu * (-vn);  // Coulomb: |dv_t| <= mu |dv_n|
            vi = us + (slip > 0.0f ? vt * (slip / vt_len) : glm::vec3(0.0f));
          }
        }
        v[i] = vi;
        x[i] += dt * vi;
        integrated_position[i] = x[i];
        // phi is 1-Lipschitz: the step moved the particle dt |v| at most
        clearance[i] = body_phi_[i] - rough_error - dt * glm::length(vi);
        strain_record[i] = glm::vec4(x[i], inv_mass[i]);
      }
    }
    contacts_sum += contacts_part;
  });
  contacts = contacts_sum.load();

  return contacts;
}

}  // namespace loosehair
