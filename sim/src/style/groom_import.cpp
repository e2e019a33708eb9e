// importGroom: one wisp a strand (method.md §6.2 import). Each polyline is
// resampled evenly by arc length into a key strand whose first control
// point is the root moved onto the scalp; its region is a small (u, v)
// square around that root, and its single member (strands 1, offset 0,
// length variation 0) is the key strand itself.
#include "loosehair/groom_import.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace loosehair {
namespace {

// Points at n arc lengths evenly spaced along the polyline.
std::vector<glm::vec3> resample(const std::vector<glm::vec3>& line, std::size_t n) {
  std::vector<float> s(line.size(), 0.0f);
  for (std::size_t j = 1; j < line.size(); ++j) s[j] = s[j - 1] + glm::length(line[j] - line[j - 1]);
  std::vector<glm::vec3> out;
  out.reserve(n);
  std::size_t j = 1;
  for (std::size_t k = 0; k < n; ++k) {
    const float at = s.back() * static_cast<float>(k) / static_cast<float>(n - 1);
    while (j + 1 < line.size() && s[j] < at) ++j;
    const float seg = s[j] - s[j - 1];
    const float t = seg > 0.0f ? std::clamp((at - s[j - 1]) / seg, 0.0f, 1.0f) : 0.0f;
    out.push_back(line[j - 1] + t * (line[j] - line[j - 1]));
  }
  out.back() = line.back();
  return out;
}

}  // namespace

Style importGroom(const Polylines& groom, const HeadDesc& head_desc, const HeadModel& head, const std::string& source,
                  const GroomImportOptions& opt, GroomImportReport* report) {
  if (!(std::isfinite(opt.scale) && opt.scale > 0.0f))
    throw StyleError(source + ": scale " + std::to_string(opt.scale) + " must be finite and positive");
  if (!(std::isfinite(opt.max_root_distance) && opt.max_root_distance > 0.0f))
    throw StyleError(source + ": max_root_distance must be finite and positive");
  if (opt.max_control_points < 2 || opt.max_control_points > 256)
    throw StyleError(source + ": max_control_points " + std::to_string(opt.max_control_points) +
                     " is outside [2, 256]");
  GroomImportReport rep;
  rep.strands_read = groom.size();
  Style style;
  style.source = source;
  style.name = opt.name;
  style.head = head_desc;
  float nearest_far = INFINITY;
  constexpr float kHalf = 0.002f;  // half the side of a root's (u, v) square
  for (std::size_t k = 0; k < groom.size(); ++k) {
    std::vector<glm::vec3> line;
    for (std::uint32_t j = groom.first[k]; j < groom.first[k + 1]; ++j) {
      const glm::vec3 p = opt.scale * groom.points[j];
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        throw StyleError(source + ": strand " + std::to_string(k) + " point " + std::to_string(j - groom.first[k]) +
                         " is not a finite number");
      if (line.empty() || glm::length(p - line.back()) >= kMinControlPointGap) line.push_back(p);
    }
    // what a style file may hold: a strand reaching beyond it is left out
    // (a groom in another unit, say), not written to a style that cannot load
    bool beyond = false;
    for (const glm::vec3& p : line) beyond = beyond || glm::length(p) > kMaxStyleCoordinate;
    if (beyond) {
      ++rep.skipped_beyond;
      continue;
    }
    if (line.size() < 2) {
      ++rep.skipped_short;
      continue;
    }
    float d0 = 0, d1 = 0;
    glm::vec2 uv = head.nearestScalpUv(line.front(), &d0);
    {
      // the root is the end nearer the scalp (the first on a tie within 1 mm)
      const glm::vec2 uv1 = head.nearestScalpUv(line.back(), &d1);
      if (d1 <= opt.max_root_distance && d1 + 1e-3f < d0) {
        std::reverse(line.begin(), line.end());
        uv = uv1;
        d0 = d1;
        ++rep.reversed;
      }
    }
    if (d0 > opt.max_root_distance) {
      ++rep.skipped_far;
      nearest_far = std::min(nearest_far, d0);
      continue;
    }
    rep.largest_root_distance = std::max(rep.largest_root_distance, d0);
    Wisp w;
    char name[32];
    std::snprintf(name, sizeof name, "strand-%zu", k);
    w.name = name;
    const glm::vec2 c = glm::clamp(uv, glm::vec2(kHalf), glm::vec2(1.0f - kHalf));
    w.region.polygons.push_back({c + glm::vec2(-kHalf, -kHalf), c + glm::vec2(kHalf, -kHalf),
                                 c + glm::vec2(kHalf, kHalf), c + glm::vec2(-kHalf, kHalf)});
    line.front() = head.scalpPoint(regionRoot(w.region, head));
    float length = 0;
    for (std::size_t j = 1; j < line.size(); ++j) length += glm::length(line[j] - line[j - 1]);
    const std::size_t n = std::clamp<std::size_t>(
        static_cast<std::size_t>(std::ceil(length / 0.01f)) + 1, 2,
        std::min<std::size_t>(static_cast<std::size_t>(opt.max_control_points), std::max<std::size_t>(line.size(), 2)));
    w.key_strand = resample(line, n);
    constexpr float kClear = 2e-3f;
    for (std::size_t j = 1; j < w.key_strand.size(); ++j) {
      glm::vec3& p = w.key_strand[j];
      for (int pass = 0; pass < 3; ++pass) {
        float phi = 0;
        glm::vec3 nrm(0.0f);
        head.head()->signedDistance(&p, 1, &phi, &nrm);
        if (phi >= kClear) break;
        p += (kClear - phi) * nrm;
      }
    }
    // the root's move and the push may bring control points together: keep
    // them kMinControlPointGap apart, as style files require
    std::vector<glm::vec3> kept{w.key_strand.front()};
    for (std::size_t j = 1; j < w.key_strand.size(); ++j)
      if (glm::length(w.key_strand[j] - kept.back()) >= kMinControlPointGap) kept.push_back(w.key_strand[j]);
    if (kept.size() < 2) {
      ++rep.skipped_short;
      continue;
    }
    // where the resampled spline would cut into the head, its midpoints
    // pushed out become control points (as every edit's are)
    w.key_strand = keyStrandKeptOutside(std::move(kept), head, kClear);
    w.params.strands = 1;
    w.params.offset_radius = 0.0f;
    w.params.length_variation = 0.0f;
    w.params.blend = 0.0f;  // the groom's own strands, not a blend of their neighbours
    w.params.seed = k + 1;
    style.wisps.push_back(std::move(w));
  }
  rep.strands_kept = style.wisps.size();
  if (report) *report = rep;
  if (style.wisps.empty()) {
    char buf[256];
    if (rep.skipped_far > 0)
      std::snprintf(buf, sizeof buf,
                    ": none of its %zu strands has a root within %.1f mm of the scalp (the nearest is %.1f mm away; "
                    "is the groom in another unit or frame?)",
                    rep.strands_read, opt.max_root_distance * 1e3, nearest_far * 1e3);
    else if (rep.skipped_beyond > 0)
      std::snprintf(buf, sizeof buf,
                    ": every strand reaches farther than %.0f m from the head's origin, beyond what a "
                    "style may hold (is the groom in another unit? see --scale)",
                    double(kMaxStyleCoordinate));
    else
      std::snprintf(buf, sizeof buf, ": holds no strand of two or more distinct points");
    throw StyleError(source + buf);
  }
  return style;
}

}  // namespace loosehair
