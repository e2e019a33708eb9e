#include "loosehair/params.hpp"

#include "parallel.hpp"

#include <cmath>
#include <numbers>
#include <cstdio>
#include <string>

namespace loosehair {
namespace {

// whole numbers in full (a thread count of 1000000, not 1e+06)
std::string num(double v) {
  char buf[64];
  if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 1e15)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

class Checker {
 public:
  explicit Checker(std::vector<std::string>& out) : out_(out) {}

  bool finite(const char* name, double v) {
    if (std::isfinite(v)) return true;
    out_.push_back(std::string(name) + " = " + num(v) + " is not a finite number");
    return false;
  }
  void positive(const char* name, double v, const char* unit) {
    if (finite(name, v) && !(v > 0))
      out_.push_back(std::string(name) + " = " + num(v) + " must be positive (" + unit + ")");
  }
  void nonNegative(const char* name, double v, const char* unit) {
    if (finite(name, v) && v < 0)
      out_.push_back(std::string(name) + " = " + num(v) + " must not be negative (" + unit + ")");
  }
  void range(const char* name, double v, double lo, double hi) {
    if (finite(name, v) && (v < lo || v > hi))
      out_.push_back(std::string(name) + " = " + num(v) + " must lie in [" + num(lo) + ", " +
                     num(hi) + "]");
  }
  void fail(const std::string& msg) { out_.push_back(msg); }

 private:
  std::vector<std::string>& out_;
};

}  // namespace

std::vector<std::string> validate(const SimParams& p) {
  std::vector<std::string> problems;
  Checker c(problems);
  c.positive("time_step", p.time_step, "s");
  if (std::isfinite(p.time_step) && p.time_step > 0.1)
    c.fail("time_step = " + num(p.time_step) + " is larger than 0.1 s; hair needs steps of about 1 ms");
  c.positive("h1", p.h1, "m");
  c.positive("h2", p.h2, "m");
  if (std::isfinite(p.h1) && std::isfinite(p.h2) && p.h1 > 0 && p.h2 > 0 && !(p.h2 < p.h1))
    c.fail("h2 = " + num(p.h2) + " must be smaller than h1 = " + num(p.h1) + " (m)");
  c.range("alignment_threshold", p.alignment_threshold, 0.0, 1.0);
  c.range("target_connections", p.target_connections, 1, 256);
  c.positive("youngs_modulus", p.youngs_modulus, "Pa");
  c.positive("material_density", p.material_density, "kg/m^3");
  c.range("stiffness_clamp", p.stiffness_clamp, 1.0, 1.0e6);
  c.nonNegative("spring_damping", p.spring_damping, "s");
  c.range("implicit_tolerance", p.implicit_tolerance, 1e-8, 1.0);
  c.range("implicit_iterations", p.implicit_iterations, 1, 10000);
  c.range("max_strain", p.max_strain, 0.0, 0.5);
  c.range("tether_slack", p.tether_slack, 0.0, 1.0);
  c.range("strain_limit_iterations", p.strain_limit_iterations, 0, 1000);
  c.nonNegative("pressure_stiffness", p.pressure_stiffness, "m^2/s^2");
  c.positive("rest_density_scale", p.rest_density_scale, "dimensionless");
  c.nonNegative("collision_rate", p.collision_rate, "1/s");
  c.nonNegative("friction_rate", p.friction_rate, "1/s");
  c.nonNegative("air_drag", p.air_drag, "1/s");
  // Explicit velocity-decay terms overshoot once rate * dt approaches 1.
  for (const DecayRate& r : decayRates(p))
    if (std::isfinite(r.rate) && std::isfinite(p.time_step) && r.rate * p.time_step > kMaxDecayPerStep)
      c.fail(std::string(r.name) + " = " + num(r.rate) + " 1/s is too large for time_step = " +
             num(p.time_step) + " s (rate * time_step must stay below " + num(kMaxDecayPerStep) + ")");
  c.finite("gravity.x", p.gravity.x);
  c.finite("gravity.y", p.gravity.y);
  c.finite("gravity.z", p.gravity.z);
  c.nonNegative("body_friction", p.body_friction, "dimensionless");
  c.nonNegative("contact_thickness", p.contact_thickness, "m");
  c.range("shape_keeping", p.shape_keeping, 0.0, 100.0);
  // the hold is a spring of angular frequency 2 pi f; symplectic Euler is
  // stable below omega dt = 2, and accurate well below it
  if (std::isfinite(p.shape_keeping) && std::isfinite(p.time_step) &&
      2.0 * std::numbers::pi * p.shape_keeping * p.time_step > kMaxHoldPhasePerStep)
    c.fail("shape_keeping = " + num(p.shape_keeping) + " Hz is too strong for time_step = " + num(p.time_step) +
           " s (2 pi shape_keeping time_step must stay below " + num(kMaxHoldPhasePerStep) + ")");
  c.range("threads", p.threads, 0, parallel::kMaxThreads);
  return problems;
}

}  // namespace loosehair
