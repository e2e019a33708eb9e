// The solver parameters' one declaration (param_table.hpp).
#include "loosehair/param_table.hpp"

#include "util/parallel.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace loosehair {
namespace {

using K = ParamInfo::Kind;
using P = ParamInfo::Print;

#define LH_REAL(field)                                             \
  [](const SimParams& p) { return static_cast<double>(p.field); }, \
      [](SimParams& p, double v) { p.field = static_cast<decltype(p.field)>(v); }
#define LH_SWITCH(field) \
  [](const SimParams& p) { return p.field ? 1.0 : 0.0; }, [](SimParams& p, double v) { p.field = v != 0.0; }

// The ranges hold every value that can make sense; the panel steps through
// them (in ratios where `logarithmic`), validate() and the scene file
// refuse anything outside. Columns: name, unit, kind, lo, hi, lo_open,
// logarithmic, live, in_scene, print, help.
const ParamInfo kTable[] = {
    {"time_step", "s", K::Real, 0.0, 0.1, true, true, false, false, P::Never,
     "length of one solver step; the scene's frame is a whole number of them (set by \"substeps\")",
     LH_REAL(time_step)},
    {"h1", "m", K::Real, 0.0, 10.0, true, true, false, true, P::Always,
     "connection smoothing length: pairs closer than 2 h1 at the start get connected (\"auto\" in a scene: from "
     "the sampling)",
     LH_REAL(h1)},
    {"h2", "m", K::Real, 0.0, 10.0, true, true, false, true, P::Always,
     "interaction smoothing length: density and hair-hair forces within 2 h2; below h1 (\"auto\" in a scene)",
     LH_REAL(h2)},
    {"alignment_threshold", "", K::Real, 0.0, 1.0, false, false, false, true, P::Always,
     "pairs whose hair directions align less than this are never connected", LH_REAL(alignment_threshold)},
    {"target_connections", "", K::Integer, 1, 256, false, false, false, true, P::Always,
     "connections a particle aims for", LH_REAL(target_connections)},
    {"youngs_modulus", "Pa", K::Real, 0.0, 1e12, true, true, true, true, P::Always,
     "tensile modulus of the hair volume: higher turns the hair with the head like a solid", LH_REAL(youngs_modulus)},
    {"material_density", "kg/m^3", K::Real, 1.0, 1e5, false, true, false, true, P::Always,
     "density of the hair material (keratin: 1300); sets the cross-section a particle stands for",
     LH_REAL(material_density)},
    {"stiffness_clamp", "", K::Real, 1.0, 1e6, false, true, true, true, P::Always,
     "largest rescaling of a side's springs as a multiple of its rest value", LH_REAL(stiffness_clamp)},
    {"spring_damping", "s", K::Real, 0.0, 1.0, false, false, true, true, P::Always,
     "damping of the relative velocity along a connection", LH_REAL(spring_damping)},
    {"implicit_springs", "", K::Switch, 0, 1, false, false, true, true, P::WhenOn,
     "solve the springs implicitly (backward Euler): stable for any time step", LH_SWITCH(implicit_springs)},
    {"implicit_tolerance", "", K::Real, 1e-8, 1.0, false, true, true, true, P::WhenOn,
     "residual at which the implicit spring solve stops, relative to its right-hand side's",
     LH_REAL(implicit_tolerance)},
    {"implicit_iterations", "", K::Integer, 1, 10000, false, true, true, true, P::WhenOn,
     "most conjugate-gradient iterations of the implicit spring solve a step", LH_REAL(implicit_iterations)},
    {"strain_limit", "", K::Switch, 0, 1, false, false, true, true, P::Always,
     "move over-stretched connections back after each step", LH_SWITCH(strain_limit)},
    {"max_strain", "", K::Real, 0.0, 0.5, false, false, true, true, P::Always,
     "largest stretch a connection keeps after a step", LH_REAL(max_strain)},
    {"strain_limit_iterations", "", K::Integer, 0, 1000, false, false, true, true, P::Always,
     "Jacobi rounds of the strain limit a step", LH_REAL(strain_limit_iterations)},
    {"tether", "", K::Switch, 0, 1, false, false, true, true, P::Always,
     "keep every particle within its arc length of its root", LH_SWITCH(tether)},
    {"hair_chain", "", K::Switch, 0, 1, false, false, true, true, P::WhenOn,
     "with the tethers, keep every particle near hair of its root region nearer its root: no clump comes loose",
     LH_SWITCH(hair_chain)},
    {"tether_slack", "", K::Real, 0.0, 1.0, false, false, true, true, P::Always,
     "allowed excess over the arc length of the tether", LH_REAL(tether_slack)},
    {"hair_hair", "", K::Switch, 0, 1, false, false, true, true, P::Always,
     "pressure, collision and friction between hair particles", LH_SWITCH(hair_hair)},
    {"pressure_stiffness", "m^2/s^2", K::Real, 0.0, 1e6, false, true, true, true, P::Always,
     "hair-hair pressure: how hard the hair resists being packed", LH_REAL(pressure_stiffness)},
    {"rest_density_scale", "", K::Real, 0.0, 100.0, true, true, true, true, P::Always,
     "rest density over the starting median: below 1 the hair repels itself, above 1 it clumps",
     LH_REAL(rest_density_scale)},
    {"collision_rate", "1/s", K::Real, 0.0, 1e6, false, true, true, true, P::Always,
     "how fast approaching hair particles lose their normal relative speed", LH_REAL(collision_rate)},
    {"friction_rate", "1/s", K::Real, 0.0, 1e6, false, true, true, true, P::Always,
     "how fast approaching hair particles lose their sliding relative speed", LH_REAL(friction_rate)},
    {"gravity.x", "m/s^2", K::Real, -1e3, 1e3, false, false, true, false, P::Always,
     "gravity, world x (a scene's \"gravity\": [x, y, z])", LH_REAL(gravity.x)},
    {"gravity.y", "m/s^2", K::Real, -1e3, 1e3, false, false, true, false, P::Always, "gravity, world y (up)",
     LH_REAL(gravity.y)},
    {"gravity.z", "m/s^2", K::Real, -1e3, 1e3, false, false, true, false, P::Always, "gravity, world z",
     LH_REAL(gravity.z)},
    {"air_drag", "1/s", K::Real, 0.0, 1e6, false, true, true, true, P::Always,
     "how fast the air slows the hair's world velocity", LH_REAL(air_drag)},
    {"body_friction", "", K::Real, 0.0, 100.0, false, false, true, true, P::Always,
     "Coulomb friction between hair and head or torso", LH_REAL(body_friction)},
    {"contact_thickness", "m", K::Real, 0.0, 1.0, false, true, true, true, P::Always,
     "distance from the body where contact begins", LH_REAL(contact_thickness)},
    {"shape_keeping", "Hz", K::Real, 0.0, 100.0, false, false, true, true, P::WhenOn,
     "how firmly a style holds its shape (natural frequency); 0 is plain LCP; off to on applies on restart",
     LH_REAL(shape_keeping)},
    {"threads", "", K::Integer, 0, parallel::kMaxThreads, false, false, true, false, P::Never,
     "worker threads, 0 = the solver's choice (--threads); results do not change", LH_REAL(threads)},
};

#undef LH_REAL
#undef LH_SWITCH

// whole numbers in full up to a million (a range of [1, 100000], not 1e+05)
std::string num(double v) {
  char buf[64];
  if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) <= 1e6)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string rangeText(const ParamInfo& p) {
  if (p.kind == K::Switch) return "true or false";
  std::string r(p.lo_open ? "(" : "[");
  r += num(p.lo);
  r += ", ";
  r += num(p.hi);
  r += "]";
  return r;
}

}  // namespace

std::string ParamInfo::check(double v) const {
  if (!std::isfinite(v)) return "is not a finite number";
  if (kind == K::Switch) return v == 0.0 || v == 1.0 ? "" : "must be 0 or 1 (off or on)";
  if (kind == K::Integer && v != std::trunc(v)) return "must be a whole number in " + rangeText(*this);
  // most fields are floats: a bound given in decimal may round past the
  // stored value (1e-8 becomes 9.99999994e-9), so a value within the bounds
  // rounded to float is within them
  const auto below = [](double a, double b) { return a < b && static_cast<float>(a) < static_cast<float>(b); };
  if (below(v, lo) || below(hi, v) || (lo_open && !(static_cast<float>(v) > static_cast<float>(lo)))) {
    if (lo_open && lo == 0.0 && v <= 0.0)
      return std::string("must be positive") + (*unit ? " (" : "") + unit + (*unit ? ")" : "");
    return "must lie in " + rangeText(*this);
  }
  return "";
}

std::span<const ParamInfo> paramTable() { return kTable; }

const ParamInfo* findParam(const char* name) {
  for (const ParamInfo& p : kTable)
    if (std::strcmp(p.name, name) == 0) return &p;
  return nullptr;
}

std::string paramReferenceMarkdown() {
  std::string out =
      "| parameter | unit | default | values | changes live | help |\n"
      "| --- | --- | --- | --- | --- | --- |\n";
  for (const ParamInfo& p : kTable) {
    std::string row = "| `";
    if (p.in_scene) row += "solver.";
    row += p.name;
    row += "` | ";
    row += *p.unit ? p.unit : "-";
    row += " | ";
    const double d = p.defaultValue();
    row += p.kind == K::Switch ? (d != 0.0 ? "true" : "false") : num(d);
    row += " | ";
    row += rangeText(p);
    row += " | ";
    row += p.live ? "yes" : "on restart";
    row += " | ";
    row += p.help;
    row += " |\n";
    out += row;
  }
  return out;
}

}  // namespace loosehair
