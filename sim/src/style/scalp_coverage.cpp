#include "loosehair/scalp_coverage.hpp"

#include "util/point_hash.hpp"
#include "util/random.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace loosehair {

ScalpCoverage scalpCoverage(const HeadModel& head, const std::vector<glm::vec3>& roots, float radius,
                            std::size_t samples) {
  if (!(radius > 0.0f && radius <= 0.1f))
    throw std::invalid_argument("scalpCoverage: radius " + std::to_string(radius) + " m is not in (0, 0.1]");
  if (samples == 0) throw std::invalid_argument("scalpCoverage: no samples");
  const ScalpTriangles& s = head.scalpTriangles();
  ScalpCoverage out;
  double total = 0.0;
  for (double a : s.areas) total += a;
  if (!(total > 0.0) || s.triangles.empty()) return out;
  PointHash near(radius);
  for (const glm::vec3& r : roots) near.add(r);
  // stratified by area: sample k at cumulative area (k + u) / samples, a
  // random point of the triangle there (a fixed stream: the same points)
  Random rng(0x5ca1bULL);
  std::size_t tri = 0, covered = 0;
  double before = 0.0;
  for (std::size_t k = 0; k < samples; ++k) {
    const double at = (static_cast<double>(k) + rng.uniform()) / static_cast<double>(samples) * total;
    while (tri + 1 < s.triangles.size() && before + s.areas[tri] < at) before += s.areas[tri++];
    const auto t = s.triangles[tri];
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    const glm::vec3 p = static_cast<float>(1.0 - r1) * s.positions[t.x] +
                        static_cast<float>(r1 * (1.0 - r2)) * s.positions[t.y] +
                        static_cast<float>(r1 * r2) * s.positions[t.z];
    if (near.anyNearer(p, radius)) {
      ++covered;
    } else {
      out.bare.push_back(p);
    }
  }
  out.samples = samples;
  out.covered = static_cast<double>(covered) / static_cast<double>(samples);
  return out;
}

}  // namespace loosehair
