// The air without a sound speed (issue 18; docs/design.md "Air without a
// sound speed"): instead of a weakly compressible pressure P = c^2 (rho - rho0),
// whose stable step shrinks with the artificial sound speed c, the air's
// positions are projected towards rest density each step, position-based
// fluids style (Macklin and Müller 2013), by Jacobi rounds on the
// constraints
//
//   C_a = rho_a / rho0 - 1,   rho_a = m sum_b W(|x_a - x_b|, h_air) (+ the faces),
//
//   lambda_a = -C_a / (|grad_a C_a|^2 + sum_b |grad_b C_a|^2 + eps),
//   dx_a     = (m / rho0) sum_b (lambda_a + lambda_b) grad W(x_a - x_b),
//
// and the velocities take the correction over the step (v += dx / dt), so
// the projection is the pressure impulse. Pairs move equal and opposite
// (the bracket is symmetric and grad W odd), so the air's momentum is kept.
// It runs on the neighbour lists of findNeighbors (the corrections are a
// small part of h_air). Thinned air (C < 0) pulls, as a wake fills. The
// constraint's compliance comes from the sound speed (XPBD): at short steps
// the air is as soft as the weakly compressible one, at long ones nearly
// incompressible, stable at any step.
#include "wind/air.hpp"

#include "solver/kernel.hpp"
#include "util/parallel.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

void AirSystem::projectDensity(float dt, int threads) {
  const std::size_t na = x_.size();
  if (na == 0 || !(dt > 0.0f)) return;
  const CubicKernel k(h_);
  const float scale = mass_ / rest_density_;  // m / rho0
  const float eps = kProjectionRelax * rest_denominator_;
  // compliance of the constraint from the sound speed, over the step
  // squared: the weakly compressible air's stiffness, m c^2 / 2 C^2 of
  // energy a particle, taken implicitly (XPBD): soft at short steps, as the
  // explicit air, and stable at any step
  const float compliance = 1.0f / (sound_speed_ * sound_speed_ * dt * dt);
  lambda_.resize(na);
  lambda_sum_.assign(na, 0.0f);
  shift_.resize(na);
  start_.assign(x_.begin(), x_.end());
  for (int it = 0; it < p_.projection_iterations; ++it) {
    parallel::forEach(threads, na, [&](std::size_t a) {
      // Air within a kernel support of a face has its density from the
      // table of the missing air, right only on average: it takes no
      // constraint of its own (it is shifted by its neighbours' only), so the
      // faces neither push nor hold and every shift is a pair's.
      if (nearFace(a, k.support())) {
        lambda_[a] = 0.0f;
        return;
      }
      // density (as densityAt) and the constraint's gradients in one pass
      float rho = mass_ * k.W(0.0f) + faceDensity(a);
      glm::vec3 grad_a(0.0f);
      float sum2 = 0.0f;
      for (std::uint32_t b : grid_.neighbors(a)) {
        const glm::vec3 d = x_[a] - x_[b];
        const float r = glm::length(d);
        rho += mass_ * k.W(r);
        const glm::vec3 g = scale * k.gradW(d, r);
        grad_a += g;
        sum2 += glm::dot(g, g);
      }
      const float c = rho / rest_density_ - 1.0f;
      const float d_lambda = (-c - compliance * lambda_sum_[a]) / (glm::dot(grad_a, grad_a) + sum2 + compliance + eps);
      lambda_[a] = d_lambda;
      lambda_sum_[a] += d_lambda;
    });
    parallel::forEach(threads, na, [&](std::size_t a) {
      glm::vec3 dx(0.0f);
      const float la = lambda_[a];
      for (std::uint32_t b : grid_.neighbors(a)) {
        // a pair of air at the faces (both without a constraint) adds
        // exactly nothing: skipped (the same bits)
        const float lab = la + lambda_[b];
        if (lab == 0.0f) continue;
        const glm::vec3 d = x_[a] - x_[b];
        dx += lab * k.gradW(d, glm::length(d));
      }
      shift_[a] = scale * dx;
    });
    parallel::forEach(threads, na, [&](std::size_t a) { x_[a] += shift_[a]; });
  }
  const float inv_dt = 1.0f / dt;
  parallel::forEach(threads, na, [&](std::size_t a) { v_[a] += (x_[a] - start_[a]) * inv_dt; });
}

void AirSystem::initProjection() {
  // |grad_a C_a|^2 + sum_b |grad_b C_a|^2 on the emission lattice (a
  // lattice is symmetric, so grad_a C_a = 0 there): the scale of the
  // constraint's stiffness, which sets the relaxation eps.
  const CubicKernel k(h_);
  const float scale = mass_ / rest_density_;
  const int reach = static_cast<int>(std::ceil(2.0f * h_ / p_.spacing));
  double sum2 = 0;
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        if (x == 0 && y == 0 && z == 0) continue;
        const glm::vec3 d = p_.spacing * glm::vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        const float r = glm::length(d);
        if (!(r < k.support())) continue;
        const glm::vec3 g = scale * k.gradW(d, r);
        sum2 += glm::dot(g, g);
      }
  rest_denominator_ = static_cast<float>(sum2);
}

}  // namespace loosehair
