#include "loosehair/params.hpp"
#include "loosehair/param_table.hpp"

#include "util/parallel.hpp"

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
  void fail(const std::string& msg) { out_.push_back(msg); }

 private:
  std::vector<std::string>& out_;
};

}  // namespace

std::vector<std::string> validate(const SimParams& p) {
  std::vector<std::string> problems;
  Checker c(problems);
  // each value against its one range (param_table.cpp)
  for (const ParamInfo& info : paramTable()) {
    const double v = info.get(p);
    if (std::string why = info.check(v); !why.empty()) {
      if (std::string(info.name) == "time_step" && std::isfinite(v) && v > info.hi)
        why = "is larger than 0.1 s; hair needs steps of about 1 ms";
      c.fail(std::string(info.name) + " = " + num(v) + " " + why);
    }
  }
  if (std::isfinite(p.h1) && std::isfinite(p.h2) && p.h1 > 0 && p.h2 > 0 && !(p.h2 < p.h1))
    c.fail("h2 = " + num(p.h2) + " must be smaller than h1 = " + num(p.h1) + " (m)");
  // Explicit velocity-decay terms overshoot once rate * dt approaches 1.
  for (const DecayRate& r : decayRates(p))
    if (std::isfinite(r.rate) && std::isfinite(p.time_step) && r.rate * p.time_step > kMaxDecayPerStep)
      c.fail(std::string(r.name) + " = " + num(r.rate) + " 1/s is too large for time_step = " + num(p.time_step) +
             " s (rate * time_step must stay below " + num(kMaxDecayPerStep) + ")");
  // the hold is a spring of angular frequency 2 pi f; symplectic Euler is
  // stable below omega dt = 2, and accurate well below it
  if (std::isfinite(p.shape_keeping) && std::isfinite(p.time_step) &&
      2.0 * std::numbers::pi * p.shape_keeping * p.time_step > kMaxHoldPhasePerStep)
    c.fail("shape_keeping = " + num(p.shape_keeping) + " Hz is too strong for time_step = " + num(p.time_step) +
           " s (2 pi shape_keeping time_step must stay below " + num(kMaxHoldPhasePerStep) + ")");
  return problems;
}

}  // namespace loosehair
