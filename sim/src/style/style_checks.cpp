// checkStyle: a style against its head (method.md §6.2), every problem named by
// its field.
#include "loosehair/style.hpp"
#include "style/hair_tie.hpp"

#include <glm/geometric.hpp>

#include <cstdio>

namespace loosehair {
namespace {

std::string mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f mm", metres * 1e3);
  return buf;
}
std::string point(glm::vec3 p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.4f, %.4f, %.4f]", p.x, p.y, p.z);
  return buf;
}

}  // namespace

void checkStyle(const Style& style, const HeadModel& head) {
  const std::string& src = style.source;
  const std::size_t tri_count = head.scalpTriangles().triangles.size();
  for (std::size_t i = 0; i < style.wisps.size(); ++i) {
    const Wisp& w = style.wisps[i];
    const std::string field = src + ": wisps[" + std::to_string(i) + "]";
    for (std::uint32_t t : w.region.triangles)
      if (t >= tri_count)
        throw StyleError(field + ".region.triangles: triangle " + std::to_string(t) + " is off the scalp, which has " +
                         std::to_string(tri_count) + " triangles");
    if (w.region.empty() || !(regionArea(w.region, head) > 0.0))
      throw StyleError(field + ".region: covers no part of the scalp");
    if (w.key_strand.size() < 2) throw StyleError(field + ".key_strand: needs at least two control points");
    const glm::vec3 root = head.scalpPoint(regionRoot(w.region, head));
    const float off = glm::length(w.key_strand[0] - root);
    if (!(off <= 0.01f))
      throw StyleError(field + ".key_strand[0]: the root " + point(w.key_strand[0]) + " is " + mm(off) +
                       " from the region's root on the scalp " + point(root) +
                       "; the first control point must be the root (within 10 mm)");
    for (std::size_t k = 1; k < w.key_strand.size(); ++k) {
      const float phi = head.headDistance(w.key_strand[k]);
      if (phi < -1e-3f)
        throw StyleError(field + ".key_strand[" + std::to_string(k) + "]: " + point(w.key_strand[k]) + " lies " +
                         mm(-phi) + " inside the head");
    }
    const int per = 8;
    const std::vector<glm::vec3> dense = sampleKeyStrand(w.key_strand, per);
    for (std::size_t j = static_cast<std::size_t>(per / 2); j < dense.size(); ++j) {
      const float phi = head.headDistance(dense[j]);
      if (phi < -3e-3f) {
        const std::size_t k = j / per;
        throw StyleError(field + ".key_strand: the spline between control points " + std::to_string(k) + " and " +
                         std::to_string(k + 1) + " passes " + mm(-phi) + " inside the head");
      }
    }
  }
  for (std::size_t j = 0; j < style.ties.size(); ++j) {
    const HairTie& t = style.ties[j];
    if (!tieHoldsAKeyStrand(style, t))
      throw StyleError(src + ": ties[" + std::to_string(j) +
                       "]: no wisp's key strand passes through the ring (centre " + point(t.center) + ", radius " +
                       mm(t.radius) + ")");
    if (head.headDistance(t.center) < t.radius)
      throw StyleError(src + ": ties[" + std::to_string(j) + "].center: the ring " + point(t.center) +
                       " reaches into the head");
  }
}

}  // namespace loosehair
