// Loading a style's wisps onto another head by (u, v) (method.md §6.2).
#include "loosehair/style.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {
namespace {

// Over this much of a key strand (m) its shape turns from the new root's
// frame to the head frame.
constexpr float kRootBlend = 0.05f;

// Pushes p out of the head and torso of `head` to at least `gap`.
glm::vec3 keepOff(const HeadModel& head, glm::vec3 p, float gap) {
  for (int round = 0; round < 4; ++round) {
    bool moved = false;
    for (const Body* b : {head.head().get(), head.torso().get()}) {
      if (!b) continue;
      float phi;
      glm::vec3 n;
      b->signedDistance(&p, 1, &phi, &n);
      if (phi < gap) {
        p += (gap - phi) * n;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return p;
}

float bodyDistance(const HeadModel& head, glm::vec3 p) {
  float best = INFINITY;
  for (const Body* b : {head.head().get(), head.torso().get()}) {
    if (!b) continue;
    float phi;
    glm::vec3 n;
    b->signedDistance(&p, 1, &phi, &n);
    best = std::min(best, phi);
  }
  return best;
}

// A key strand on another head: it leaves the new root as it left the old
// one (in the root's frame), and further along it hangs as it did in the
// head frame (long hair falls under gravity whatever the head's shape; kept
// in the root frame alone, a 40 cm strand from a differently tilted root
// would stand off the head). Segment lengths are kept; the strand drapes
// over the new head, keeping the clearance it had (1 to 15 mm).
std::vector<glm::vec3> retargetKeyStrand(const std::vector<glm::vec3>& c, const HeadModel& from, glm::vec2 from_uv,
                                         const HeadModel& to, glm::vec2 to_uv) {
  if (c.empty()) return {};
  const glm::quat turn = glm::quat_cast(rootFrame(to, to_uv) * glm::transpose(rootFrame(from, from_uv)));
  const glm::quat none(1.0f, 0.0f, 0.0f, 0.0f);
  std::vector<glm::vec3> out{to.scalpPoint(to_uv)};
  float s = 0;
  for (std::size_t k = 1; k < c.size(); ++k) {
    const glm::vec3 d = c[k] - c[k - 1];
    const float len = glm::length(d);
    const float mid = s + 0.5f * len;
    s += len;
    const float w = std::clamp(mid / kRootBlend, 0.0f, 1.0f);
    const glm::quat r = glm::slerp(turn, none, w * w * (3.0f - 2.0f * w));
    const float gap = std::clamp(bodyDistance(from, c[k]), 1e-3f, 0.015f);
    glm::vec3 p = keepOff(to, out.back() + r * d, gap);
    // keep the segment's length after the push
    const glm::vec3 e = p - out.back();
    if (glm::length(e) > 1e-9f) p = out.back() + len * glm::normalize(e);
    out.push_back(p);
  }
  return out;
}

}  // namespace

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
    w.key_strand = retargetKeyStrand(w.key_strand, from, old_root, to, regionRoot(w.region, to));
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
