// Every solver parameter (SimParams) described once: its scene-file name,
// unit, a useful range for a control, a one-line explanation, and whether a
// running solver takes a change of it (Solver::setParams) or it needs a new
// solver ("applies on restart"). The viewer's panel is built from it; the
// solver checks changes against it.
#pragma once

#include "loosehair/params.hpp"

#include <span>

namespace loosehair {

struct ParamInfo {
  enum class Kind { Real, Integer, Switch };
  const char* name;     // the SimParams field (gravity.y for a component); the scene
                        // file's "solver" object uses the same names, but for
                        // time_step (from "substeps") and threads (--threads)
  const char* unit;     // "" when dimensionless
  Kind kind;
  double lo, hi;        // a useful range for a control (always within validate()'s)
  bool logarithmic;     // a control should step in ratios, not differences
  bool live;            // Solver::setParams takes it
  const char* help;     // one line
  double (*get)(const SimParams&);
  void (*set)(SimParams&, double);
};

/// The table, in the order of SimParams.
std::span<const ParamInfo> paramTable();

/// The entry called `name`, or nullptr.
const ParamInfo* findParam(const char* name);

}  // namespace loosehair
