// Wisp regions on the scalp (method.md §6.2): which scalp triangles a region
// touches, for sampling roots over it by area.
#pragma once

#include "loosehair/style.hpp"

#include <vector>

namespace loosehair {

/// The scalp triangles that hold part of the region: its own triangles,
/// and those with a corner or centre inside one of its polygons or holding
/// a polygon corner. Sorted.
std::vector<std::uint32_t> regionTriangles(const WispRegion& region, const HeadModel& head);

/// Whether uv is inside the polygon (even-odd rule).
bool polygonContains(const std::vector<glm::vec2>& polygon, glm::vec2 uv);

}  // namespace loosehair
