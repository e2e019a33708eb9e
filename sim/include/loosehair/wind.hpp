// Wind (method.md §5): air in a box around the head that enters upwind with the
// wind velocity and leaves downwind, kept incompressible, with viscosity and
// drag forces exchanged with the hair, equal and opposite. Two models of the
// air: a grid (the default; sim/src/wind/air_grid.hpp, docs/design.md "Air on a
// grid") and, as in the paper, SPH air particles (sim/src/wind/air.hpp):
//
//   f_hair_i += dw W(|x_ia|, h_air) (v_a - v_i),   f_air_a -= the same.
#pragma once

#include <glm/vec3.hpp>

#include <string>
#include <utility>
#include <vector>

namespace loosehair {

/// How the air is simulated.
enum class AirModel {
  /// A fixed grid over the box (MAC faces, semi-Lagrangian advection, an
  /// exact pressure projection): no sound speed and no particle pairs.
  Grid,
  /// SPH air particles emitted upwind (the paper's model).
  Particles,
};

struct WindParams {
  AirModel model = AirModel::Grid;
  /// Direction the wind blows towards (world, normalised when used).
  glm::vec3 direction{0.0f, 0.0f, -1.0f};
  /// Wind speed far upwind (m/s), times the gust profile.
  float speed = 3.0f;
  /// Gusts: (time s, multiplier) keys, piecewise linear, held before the
  /// first and after the last; empty means a constant multiplier of 1.
  std::vector<std::pair<double, float>> profile;
  /// The air box (world): centre and size along the wind, vertically (world
  /// +Y made perpendicular to the wind) and across (m). Air enters through
  /// the upwind face and is removed when it leaves the box.
  glm::vec3 box_center{0.0f, -0.1f, 0.0f};
  glm::vec3 box_size{0.7f, 0.8f, 0.6f};
  /// Spacing of the emitted air particles (m); h_air = h_scale * spacing.
  /// On the grid: the cell size.
  float spacing = 0.03f;
  float h_scale = 1.0f;
  /// Density of air (kg/m^3): sets the mass of an air particle.
  float density = 1.2f;
  /// Jacobi rounds a step of the density projection that keeps the air
  /// near rest density without a sound speed (sim/src/wind/air_projection.cpp);
  /// 0 = weakly compressible air with the sound speed below, whose stable
  /// step is about 6x shorter (25 substeps a frame on the wind scene
  /// against 4).
  int projection_iterations = 3;
  /// Speed of sound (m/s): of the weakly compressible air, P = c^2 (rho -
  /// rho0); of the projected air, its compliance 1 / (c dt)^2. 0 = twice
  /// the largest wind speed.
  float sound_speed = 0.0f;
  /// Air viscosity as the rate at which neighbouring air velocities even
  /// out (1/s).
  float viscosity_rate = 5.0f;
  /// Hair-air drag as the rate at which a hair particle's velocity relative
  /// to the surrounding air decays (1/s). The air feels the opposite force,
  /// so dense hair slows the air. Pair forces are limited so that no
  /// particle's relative velocity is overshot in one step.
  float drag_rate = 20.0f;
};

/// Every problem with `w`, one sentence each naming the field and value.
std::vector<std::string> validate(const WindParams& w);
/// Throws std::invalid_argument listing every problem of `w`.
void requireValid(const WindParams& w);

/// Wind speed upwind at time t (m/s), gusts included.
float windSpeedAt(const WindParams& w, double t);
/// Largest speed the gust profile reaches (m/s).
float windMaxSpeed(const WindParams& w);

/// The box's axes (world): along the wind, up (world +Y made perpendicular
/// to the wind, or +X for a vertical wind) and across.
struct WindAxes {
  glm::vec3 wind, up, side;
};
WindAxes windAxes(const WindParams& w);

}  // namespace loosehair
