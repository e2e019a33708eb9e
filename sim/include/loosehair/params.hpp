// Simulation parameters of the loosely-connected-particle hair solver.
// Every field has a default, a unit and the docs/method.md section it belongs to.
// Coefficients that the paper writes as raw multipliers of the SPH kernel
// (collision, friction, air friction) are given here as rates in 1/s so that
// they do not depend on the smoothing length, the particle mass or the step;
// the solver converts them once at initialisation (see Solver).
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <string>
#include <vector>

namespace loosehair {

struct SimParams {
  // ---- time (method.md §5 "Integration") -------------------------------------
  /// Length of one solver step (unit: s). Symplectic Euler is stable while
  /// dt < 2/sqrt(sum_j alpha_ij k_ij / m_i); Solver::stableTimeStep() reports it.
  double time_step = 1.0e-3;

  // ---- smoothing lengths (method.md §1) -------------------------------------
  /// Connection smoothing length h1 (unit: m): pairs closer than 2*h1 at
  /// initialisation become connections; W(r, h1) is the spring's looseness.
  float h1 = 0.024f;
  /// Interaction smoothing length h2 (unit: m): density and hair-hair forces
  /// between current neighbours closer than 2*h2. Must be smaller than h1.
  float h2 = 0.011f;

  // ---- connections (method.md §3.1) -----------------------------------------
  /// Alignment threshold a0 (dimensionless, 0..1): pairs with a_ij < a0 are
  /// never connected.
  float alignment_threshold = 0.5f;
  /// Target number of connections per particle Nn.
  int target_connections = 12;

  // ---- loose springs (method.md §3.2) ---------------------------------------
  /// Tensile (Young's) modulus E of the hair medium (unit: Pa). It also sets
  /// how stiffly the hair volume resists shear and bending: at 5e4 (method.md §9)
  /// a 25 cm hair turns with a shaken head like a solid; at 1e3 it trails
  /// visibly. Stretch is held by the tethers and the strain limit instead.
  float youngs_modulus = 1.0e3f;
  /// Density d of the hair material, keratin (unit: kg/m^3). Sets the
  /// cross-section A_i = (m_i/d)^(2/3) that a particle stands for.
  float material_density = 1300.0f;
  /// Upper bound of a side's rescaling factor a_r,i / a_t,i as a multiple of
  /// its value in the rest state (dimensionless, >= 1). Stops a nearly free
  /// last connection from becoming infinitely stiff.
  float stiffness_clamp = 4.0f;
  /// Spring damping gamma (unit: s): the damping force along a connection is
  /// gamma * alpha_ij k_ij * (relative velocity along the pair).
  float spring_damping = 2.0e-4f;

  /// Take the springs implicitly (docs/design.md "Implicit springs"): a
  /// linearised backward-Euler solve for the velocity change, stable for
  /// any time step, so the step is set by accuracy instead of by the
  /// stiffest spring. Off: symplectic Euler, as in the paper.
  bool implicit_springs = true;
  /// Residual at which the implicit spring solve stops, relative to the
  /// right-hand side's (dimensionless, preconditioned norm); the solve
  /// starts from the last step's answer. Looser, the error it leaves is
  /// carried into the next step by that start and keeps hair rocking at
  /// its taut tethers on a still head (docs/design.md, "Implicit springs").
  float implicit_tolerance = 5.0e-4f;
  /// Most conjugate-gradient iterations of the implicit spring solve a step.
  int implicit_iterations = 50;

  // ---- strain limit (method.md §5, §9) ---------------------------------------
  /// Move over-stretched active connections back to (1 + max_strain) l_ij
  /// after each step (Jacobi, roots immovable).
  bool strain_limit = true;
  /// Largest strain an active connection may keep after a step (dimensionless).
  /// Much below 1% the limit and the explicit springs fight each step and the
  /// corrections turn into velocity noise at the tips.
  float max_strain = 0.01f;
  /// Jacobi iterations of the strain limit per step.
  /// Each pass also adds shear stiffness to the hair volume.
  int strain_limit_iterations = 2;

  /// Tether every hair particle to its root point: |x_i - r_i| <= (1 +
  /// tether_slack) s_i after each step (a long-range attachment; our
  /// addition). It keeps the no-stretch promise for any stiffness E.
  bool tether = true;
  /// With the tethers, the hair chain: every particle kept near a partner
  /// or other hair of its root region nearer the root, so that no clump
  /// comes loose under fast motion (sim/src/solver/hair_chain.hpp).
  bool hair_chain = true;
  /// Allowed excess of |x_i - r_i| over s_i (dimensionless).
  float tether_slack = 0.01f;

  // ---- hair-hair interactions (method.md §4) --------------------------------
  /// One switch for pressure, collision and friction between hair particles.
  bool hair_hair = true;
  /// Pressure coefficient k_a in P = k_a (rho - rho0) (unit: m^2/s^2, a
  /// squared speed of sound).
  float pressure_stiffness = 0.05f;
  /// Rest density rho0 as a multiple of the median initial hair density
  /// (dimensionless): below 1 the hair is repulsive, above 1 cohesive.
  float rest_density_scale = 1.0f;
  /// Inelastic hair-hair collision (eq. 17) as the rate at which the
  /// approaching normal relative velocity is removed (unit: 1/s).
  float collision_rate = 20.0f;
  /// Hair-hair friction (eq. 18) as the rate at which the tangential relative
  /// velocity of approaching pairs is removed (unit: 1/s).
  float friction_rate = 10.0f;

  // ---- external forces (method.md §5) ---------------------------------------
  /// Gravity in world coordinates (unit: m/s^2).
  glm::vec3 gravity{0.0f, -9.81f, 0.0f};
  /// Air friction -d_air v as a rate: each particle's world velocity decays
  /// at this rate (unit: 1/s).
  float air_drag = 1.0f;
  /// Coulomb friction coefficient mu between hair and body (dimensionless).
  float body_friction = 0.3f;
  /// Particles closer to the body than this feel the contact response
  /// (unit: m).
  float contact_thickness = 0.002f;

  // ---- shape keeping (our addition; docs/design.md "Shape keeping") ----
  /// Holds a styled shape (method.md §6.2): each hair particle is pulled towards
  /// its initial position in the head frame with the acceleration
  /// (2 pi f)^2 (x0 - x), and the initial state is pre-stressed so that it
  /// is at rest under gravity and the internal forces it starts with. f is
  /// this value (unit: Hz): the natural frequency of the hold, independent
  /// of particle count and time step. 0 (the default) is plain LCP.
  /// 2 pi f time_step must stay below kMaxHoldPhasePerStep.
  float shape_keeping = 0.0f;

  // ---- execution -------------------------------------------------------
  /// Worker threads: 0 (the default) lets the solver choose between all the
  /// cores the process may use and one, whichever it measures to be faster
  /// (one while other programs keep the cores busy); T > 0 is exactly T.
  /// Results do not depend on it.
  int threads = 0;
};

/// The largest 2 pi f dt a shape-keeping hold may have (symplectic Euler is
/// stable below 2; this keeps it accurate).
inline constexpr double kMaxHoldPhasePerStep = 0.5;

/// The largest rate * dt an explicit velocity-decay term may have (it
/// overshoots once the product approaches 1).
inline constexpr double kMaxDecayPerStep = 0.25;

/// The explicit velocity-decay rates (1/s), by field name: each is held to
/// kMaxDecayPerStep by validate() and by the automatic step.
struct DecayRate {
  const char* name;
  float rate;
};
inline std::array<DecayRate, 3> decayRates(const SimParams& p) {
  return {{{"collision_rate", p.collision_rate}, {"friction_rate", p.friction_rate}, {"air_drag", p.air_drag}}};
}

/// Every problem with `p`, one sentence each naming the parameter and its
/// value; empty when the parameters are usable.
std::vector<std::string> validate(const SimParams& p);

}  // namespace loosehair
