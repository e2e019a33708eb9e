// Per-frame particle dumps as binary little-endian PLY, readable by ordinary
// point-cloud tools. Properties (world coordinates):
//   float x y z     position
//   float nx ny nz  hair direction
//   float vx vy vz  velocity
//   float u v s     scalp coordinates and arc length
//   float rx ry rz  root point f^-1(u, v)
//   uchar root      1 for root particles
//   float density   SPH density (kg/m^3)
#pragma once

#include <string>

namespace loosehair {

class Solver;

/// Writes the solver's current state to `path`. The file is written to a
/// temporary name beside it and renamed, so it is complete or absent.
/// Throws std::runtime_error naming the file on failure.
void writeParticlePly(const std::string& path, const Solver& solver);

/// Writes the wind's air particles (world coordinates): float x y z,
/// float vx vy vz, float density. Same guarantees as writeParticlePly.
void writeAirPly(const std::string& path, const Solver& solver);

}  // namespace loosehair
