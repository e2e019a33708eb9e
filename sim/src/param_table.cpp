#include "loosehair/param_table.hpp"

#include <cstring>

namespace loosehair {
namespace {

using K = ParamInfo::Kind;

#define LH_REAL(field) \
  [](const SimParams& p) { return static_cast<double>(p.field); }, \
  [](SimParams& p, double v) { p.field = static_cast<decltype(p.field)>(v); }
#define LH_SWITCH(field) \
  [](const SimParams& p) { return p.field ? 1.0 : 0.0; }, [](SimParams& p, double v) { p.field = v != 0.0; }

// Ranges are those a user tries in practice; validate() holds the hard limits.
const ParamInfo kTable[] = {
    {"time_step", "s", K::Real, 1e-4, 2e-3, true, false,
     "length of one solver step; the scene's frame is a whole number of them", LH_REAL(time_step)},
    {"h1", "m", K::Real, 0.005, 0.06, true, false,
     "connection smoothing length: pairs closer than 2 h1 at the start get connected", LH_REAL(h1)},
    {"h2", "m", K::Real, 0.002, 0.03, true, false,
     "interaction smoothing length: density and hair-hair forces within 2 h2", LH_REAL(h2)},
    {"alignment_threshold", "", K::Real, 0.0, 1.0, false, false,
     "pairs whose hair directions align less than this are never connected", LH_REAL(alignment_threshold)},
    {"target_connections", "", K::Integer, 2, 40, false, false, "connections a particle aims for",
     LH_REAL(target_connections)},
    {"youngs_modulus", "Pa", K::Real, 1e2, 1e5, true, true,
     "tensile modulus of the hair volume: higher turns the hair with the head like a solid",
     LH_REAL(youngs_modulus)},
    {"material_density", "kg/m^3", K::Real, 500, 3000, false, false,
     "density of keratin; sets the cross-section a particle stands for", LH_REAL(material_density)},
    {"stiffness_clamp", "", K::Real, 1.0, 100.0, true, true,
     "largest rescaling of a side's springs as a multiple of its rest value", LH_REAL(stiffness_clamp)},
    {"spring_damping", "s", K::Real, 0.0, 2e-3, false, true, "damping of the relative velocity along a connection",
     LH_REAL(spring_damping)},
    {"implicit_springs", "", K::Switch, 0, 1, false, true,
     "solve the springs implicitly: stable for any time step", LH_SWITCH(implicit_springs)},
    {"implicit_tolerance", "", K::Real, 1e-5, 1e-1, true, true,
     "relative residual at which the implicit spring solve stops", LH_REAL(implicit_tolerance)},
    {"implicit_iterations", "", K::Integer, 1, 200, false, true,
     "most conjugate-gradient iterations of the implicit spring solve a step", LH_REAL(implicit_iterations)},
    {"strain_limit", "", K::Switch, 0, 1, false, true, "move over-stretched connections back after each step",
     LH_SWITCH(strain_limit)},
    {"max_strain", "", K::Real, 0.0, 0.1, false, true, "largest stretch a connection keeps after a step",
     LH_REAL(max_strain)},
    {"strain_limit_iterations", "", K::Integer, 0, 10, false, true, "Jacobi passes of the strain limit a step",
     LH_REAL(strain_limit_iterations)},
    {"tether", "", K::Switch, 0, 1, false, true, "keep every particle within its arc length of its root",
     LH_SWITCH(tether)},
    {"hair_chain", "", K::Switch, 0, 1, false, true,
     "with the tethers, keep every particle near hair nearer its root: no clump comes loose",
     LH_SWITCH(hair_chain)},
    {"tether_slack", "", K::Real, 0.0, 0.2, false, true, "allowed excess over the arc length of the tether",
     LH_REAL(tether_slack)},
    {"hair_hair", "", K::Switch, 0, 1, false, true, "pressure, collision and friction between hair particles",
     LH_SWITCH(hair_hair)},
    {"pressure_stiffness", "m^2/s^2", K::Real, 0.0, 1.0, false, true,
     "hair-hair pressure: how hard the hair resists being packed", LH_REAL(pressure_stiffness)},
    {"rest_density_scale", "", K::Real, 0.2, 3.0, false, true,
     "rest density over the starting median: below 1 the hair repels itself, above 1 it clumps",
     LH_REAL(rest_density_scale)},
    {"collision_rate", "1/s", K::Real, 0.0, 200.0, false, true,
     "how fast approaching hair particles lose their normal relative speed", LH_REAL(collision_rate)},
    {"friction_rate", "1/s", K::Real, 0.0, 200.0, false, true,
     "how fast approaching hair particles lose their sliding relative speed", LH_REAL(friction_rate)},
    {"gravity.x", "m/s^2", K::Real, -20.0, 20.0, false, true, "gravity, world x", LH_REAL(gravity.x)},
    {"gravity.y", "m/s^2", K::Real, -20.0, 20.0, false, true, "gravity, world y (up)", LH_REAL(gravity.y)},
    {"gravity.z", "m/s^2", K::Real, -20.0, 20.0, false, true, "gravity, world z", LH_REAL(gravity.z)},
    {"air_drag", "1/s", K::Real, 0.0, 50.0, false, true, "how fast the air slows the hair's world velocity",
     LH_REAL(air_drag)},
    {"body_friction", "", K::Real, 0.0, 2.0, false, true, "Coulomb friction between hair and head or torso",
     LH_REAL(body_friction)},
    {"contact_thickness", "m", K::Real, 0.0, 0.01, false, true, "distance from the body where contact begins",
     LH_REAL(contact_thickness)},
    {"shape_keeping", "Hz", K::Real, 0.0, 20.0, false, true,
     "how firmly a style holds its shape (natural frequency); 0 is plain LCP; off to on applies on restart",
     LH_REAL(shape_keeping)},
    {"threads", "", K::Integer, 0, 64, false, true, "worker threads, 0 = the solver's choice; results do not change",
     LH_REAL(threads)},
};

#undef LH_REAL
#undef LH_SWITCH

}  // namespace

std::span<const ParamInfo> paramTable() { return kTable; }

const ParamInfo* findParam(const char* name) {
  for (const ParamInfo& p : kTable)
    if (std::strcmp(p.name, name) == 0) return &p;
  return nullptr;
}

}  // namespace loosehair
