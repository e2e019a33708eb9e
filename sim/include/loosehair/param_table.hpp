// Every solver parameter (SimParams) declared once: its scene-file name,
// unit, the one range of values it may take, a one-line explanation,
// whether a running solver takes a change of it (Solver::setParams) or it
// needs a new solver ("applies on restart"), whether a scene file sets it
// and whether it enters the scene fingerprint. validate(), the scene
// reader, the viewer's panel and scripts, the snapshot fingerprint and the
// parameter reference in data/scenes/README.md all come from this table.
#pragma once

#include "loosehair/params.hpp"

#include <span>
#include <string>

namespace loosehair {

struct ParamInfo {
  enum class Kind { Real, Integer, Switch };
  /// How the scene fingerprint (snapshots) takes it: always, never (the
  /// step and the thread count, which change no physics the snapshot does
  /// not carry), or only when it is switched on (solver.cpp's fingerprint
  /// names those).
  enum class Print { Always, Never, WhenOn };
  const char* name;  // the SimParams field (gravity.y for a component)
  const char* unit;  // "" when dimensionless
  Kind kind;
  double lo, hi;     // the values it may take: [lo, hi], or (lo, hi] when lo_open
  bool lo_open;      // lo itself is not allowed
  bool logarithmic;  // a control steps in ratios, not differences
  bool live;         // Solver::setParams takes it
  bool in_scene;     // a scene file's "solver" object sets it under this name
  Print print;       // the scene fingerprint
  const char* help;  // one line
  double (*get)(const SimParams&);
  void (*set)(SimParams&, double);

  /// The default (SimParams{}).
  double defaultValue() const { return get(SimParams{}); }
  /// Empty if `v` is a value this parameter may take, else why not, as
  /// "must lie in [lo, hi]" (a finite number, in range, whole for an
  /// integer, 0 or 1 for a switch).
  std::string check(double v) const;
};

/// The table, in the order of SimParams.
std::span<const ParamInfo> paramTable();

/// The entry called `name`, or nullptr.
const ParamInfo* findParam(const char* name);

/// The parameter reference as a Markdown table (data/scenes/README.md
/// holds it between its "solver parameters" markers).
std::string paramReferenceMarkdown();

}  // namespace loosehair
