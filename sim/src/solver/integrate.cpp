// Integration (method.md §5): symplectic Euler, with the inelastic,
// frictional body contact applied to the new velocity and speculative
// contacts.
#include "solver/integrate.hpp"

#include "solver/body_query.hpp"
#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- integrate: symplectic Euler with the inelastic, frictional body contact
// applied to the new velocity (method.md §5 body collisions) -------------------------
std::size_t integrate(const IntegrateSettings& settings, const BodyQuery& bodies, const IntegrateParticles& p,
                      std::span<const glm::vec3> spring_dv, StepContext& ctx, int threads) {
  const std::size_t n = p.position.size();
  const float dt = ctx.dt;
  const auto& x = p.position;
  const auto& v = p.velocity;
  const auto& m = p.mass;
  const auto& root = p.is_root;
  const float thickness = settings.contact_thickness, mu = settings.body_friction;
  const bool implicit = !spring_dv.empty();
  const float reach = thickness + kSpeculativeSpeed * dt;
  // the strain limit's first records, (x, 1/m), made here in the same pass
  ctx.strain_records[0].resize(n);
  glm::vec4* strain_record = ctx.strain_records[0].data();
  const float* inv_mass = p.inverse_mass.data();
  // phi - error is a lower bound of the distance
  const float rough_error = bodies.roughError();
  float* clearance = ctx.body_clearance.data();
  glm::vec3* integrated_position = ctx.integrated_position.data();
  std::size_t contacts = 0;
  std::atomic<std::size_t> contacts_sum{0};
  parallel::run(threads, [&] {
    std::size_t contacts_part = 0;
    const auto [first, last] = parallel::share(static_cast<std::size_t>((n + kBodyBlock - 1) / kBodyBlock));
    for (std::size_t bb = first; bb < last; ++bb) {
      const std::size_t b = bb * kBodyBlock;
      const std::size_t e = std::min(n, b + kBodyBlock);
      glm::vec3 surface[kBodyBlock], body_normal[kBodyBlock];
      float body_phi[kBodyBlock];
      // the velocity response tolerates the grid's error; the projection
      // after the constraints keeps particles out of the exact surface.
      // Beyond the contact thickness, as far as a particle at
      // kSpeculativeSpeed gets in a step: speculative contacts.
      bodies.nearest(&x[b], e - b, body_phi, body_normal, surface, reach, true);
      for (std::size_t i = b; i < e; ++i) {
        if (root[i]) {
          strain_record[i] = glm::vec4(x[i], inv_mass[i]);
          continue;
        }
        glm::vec3 vi = v[i] + (implicit ? spring_dv[i] : (dt / m[i]) * ctx.force[i]);
        if (body_phi[i - b] >= thickness && body_phi[i - b] < reach) {
          // Speculative: a particle that would go through the contact
          // layer into the body within this step only reaches the layer
          // (the step's penetration, which the projection afterwards turns
          // into an outward push and the tether's excess, stays small at
          // any step).
          const glm::vec3 nrm = body_normal[i - b];
          const float vn = glm::dot(vi - surface[i - b], nrm);
          const float allowed = -(body_phi[i - b] - thickness) / dt;
          if (vn < allowed) vi += (allowed - vn) * nrm;
        }
        if (body_phi[i - b] < thickness) {
          // The response acts on the velocity relative to the body's surface.
          const glm::vec3 us = surface[i - b];
          const glm::vec3 nrm = body_normal[i - b];
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
        clearance[i] = body_phi[i - b] - rough_error - dt * glm::length(vi);
        strain_record[i] = glm::vec4(x[i], inv_mass[i]);
      }
    }
    contacts_sum += contacts_part;
  });
  contacts = contacts_sum.load();

  return contacts;
}

}  // namespace loosehair
