// Shape keeping (our addition for styles, method.md §6.2; docs/design.md): LCP
// has no bending stiffness, so a styled shape sags under gravity. Each hair
// particle is pulled towards its initial (styled) position x0 in the head
// frame, and the initial state is pre-stressed to equilibrium: the force it
// starts with (gravity in the head frame plus the springs and hair-hair
// forces of the initial state) is cancelled by a constant acceleration b in
// the head frame, so the styled state is at rest and the hold only acts on
// what moves the hair away from it (head motion, wind, contact):
//
//   a_i += omega^2 (x0_i - x_i) + b_i,   omega = 2 pi f,   b_i = -F0_i / m_i
//
// f (Hz) is the natural frequency of the hold, a property of the hair, not of
// the sampling or the step; it may differ between particles (the hair a tie
// pulls taut is held harder). Off (f = 0), the solver is plain LCP.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace loosehair {

inline float holdRate(double hz) { return static_cast<float>(4.0 * std::numbers::pi * std::numbers::pi * hz * hz); }

struct ShapeKeeping {
  float base_hz;                     // the solver's strength (Hz)
  std::vector<float> hold_hz;        // per-particle holds (ties), Hz; 0 = none
  std::vector<float> omega2;         // (2 pi max(base, hold_i))^2 (1/s^2)
  std::vector<glm::vec3> target;     // x0_i, head frame (m)
  std::vector<glm::vec3> prestress;  // b_i (m/s^2)

  /// `initial_force` is F0 (N), `gravity_head` gravity in the head frame at
  /// the start (m/s^2). Roots get no term.
  ShapeKeeping(float hz, const std::vector<glm::vec3>& position, const std::vector<float>& mass,
               const std::vector<glm::vec3>& initial_force, glm::vec3 gravity_head)
      : base_hz(hz),
        hold_hz(position.size(), 0.0f),
        omega2(position.size(), holdRate(hz)),
        target(position),
        prestress(position.size()) {
    for (std::size_t i = 0; i < position.size(); ++i) prestress[i] = -(initial_force[i] / mass[i] + gravity_head);
  }

  /// The largest omega_i (rad/s).
  double fastest() const {
    float w2 = 0;
    for (float w : omega2) w2 = std::max(w2, w);
    return std::sqrt(static_cast<double>(w2));
  }
  /// The largest omega_i with the solver's strength `hz` instead (rad/s).
  double fastestWith(float hz) const {
    float f = hz;
    for (float h : hold_hz) f = std::max(f, h);
    return std::sqrt(static_cast<double>(holdRate(f)));
  }
  void setBase(float hz) {
    base_hz = hz;
    for (std::size_t i = 0; i < omega2.size(); ++i) omega2[i] = holdRate(std::max(base_hz, hold_hz[i]));
  }
  void setHolds(const std::vector<float>& hz) {
    for (std::size_t i = 0; i < hz.size(); ++i) hold_hz[i] = std::max(hold_hz[i], hz[i]);
    setBase(base_hz);
  }

  glm::vec3 acceleration(std::size_t i, glm::vec3 x) const { return omega2[i] * (target[i] - x) + prestress[i]; }
};

}  // namespace loosehair
