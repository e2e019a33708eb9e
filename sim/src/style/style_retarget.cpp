// Loading a style's wisps onto another head by (u, v) (SPEC §6.2).
#include "loosehair/style.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

namespace loosehair {

Style retargetStyle(const Style& style, const HeadModel& from, const HeadModel& to) {
  Style out = style;
  out.head = to.desc();
  const ScalpTriangles& s = from.scalpTriangles();
  for (Wisp& w : out.wisps) {
    const glm::vec2 old_root = regionRoot(w.region, from);
    WispRegion region;
    region.polygons = w.region.polygons;
    for (std::uint32_t t : w.region.triangles) {
      if (t >= s.triangles.size()) continue;
      const auto tr = s.triangles[t];
      region.polygons.push_back({s.uvs[tr.x], s.uvs[tr.y], s.uvs[tr.z]});
    }
    w.region = std::move(region);
    w.key_strand = reRootKeyStrand(w.key_strand, from, old_root, to, regionRoot(w.region, to));
  }
  for (HairTie& t : out.ties) {
    const glm::vec2 uv = from.nearestScalpUv(t.center);
    const glm::mat3 a = rootFrame(from, uv), b = rootFrame(to, uv);
    t.center = to.scalpPoint(uv) + b * (glm::transpose(a) * (t.center - from.scalpPoint(uv)));
    t.axis = glm::normalize(b * (glm::transpose(a) * t.axis));
  }
  return out;
}

}  // namespace loosehair
