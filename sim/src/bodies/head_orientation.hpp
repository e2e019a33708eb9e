// Plausibility of a head mesh's placement in the simulator's frame (+Y up,
// face towards +Z), for warnings that tell a user which setting to change.
#pragma once

#include "loosehair/mesh.hpp"

#include <string>
#include <vector>

namespace loosehair {

/// Warnings (each naming `field` and the setting to change) when the mesh
/// looks as if it lies on its side (deeper or wider than tall by a quarter:
/// a head is taller than deep, a bust taller than deep) or stands upside
/// down (a flat top as wide as a neck or a bust's base instead of a dome).
std::vector<std::string> headOrientationWarnings(const TriangleMesh& mesh, const std::string& field);

}  // namespace loosehair
