// Key strands (method.md §6.2): their Catmull-Rom spline (kept out of the
// head), the three styling directions at a control point, and the local
// frame of a root.
#include "init/mesh_scalp.hpp"
#include "loosehair/strand_brushes.hpp"
#include "loosehair/style.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace loosehair {

std::vector<glm::vec3> sampleKeyStrand(const std::vector<glm::vec3>& control, int per_span) {
  return catmullRom(control, per_span);
}

std::vector<glm::vec3> keyStrandKeptOutside(std::vector<glm::vec3> c, const HeadModel& head, float clearance) {
  constexpr int kPer = 8;          // as checkStyle samples a span
  constexpr float kDip = 0.0029f;  // deeper than this is mended (checkStyle refuses 3 mm)
  constexpr std::size_t kMaxPoints = 4096;
  for (int round = 0; round < 6 && c.size() >= 2 && c.size() < kMaxPoints; ++round) {
    const std::vector<glm::vec3> dense = sampleKeyStrand(c, kPer);
    std::vector<std::size_t> dips;  // spans, in order
    for (std::size_t j = 1; j < dense.size(); ++j) {
      const std::size_t k = std::min((j - 1) / kPer, c.size() - 2);
      if ((dips.empty() || dips.back() != k) && head.headDistance(dense[j]) < -kDip) dips.push_back(k);
    }
    if (dips.empty()) break;
    const std::vector<glm::vec3> halves = sampleKeyStrand(c, 2);  // point 2k + 1: the middle of span k
    for (auto it = dips.rbegin(); it != dips.rend(); ++it)
      c.insert(c.begin() + static_cast<std::ptrdiff_t>(*it + 1), keptOutsideHead(head, halves[2 * *it + 1], clearance));
  }
  return c;
}

glm::mat3 rootFrame(const HeadModel& head, glm::vec2 uv) {
  const glm::vec3 n = head.scalpNormal(uv);
  const glm::vec3 e = head.scalpTangentU(uv);
  return glm::mat3(e, n, glm::cross(e, n));
}

StylingDirections stylingDirections(const Wisp& wisp, std::size_t k, const HeadModel& head) {
  const auto& c = wisp.key_strand;
  const std::size_t n = c.size();
  // the spline's tangent at a control point: (c[k+1] - c[k-1]) / 2, the
  // ends by reflection (as catmullRom does): c[1] - c[0] and c[n-1] - c[n-2]
  glm::vec3 t = k == 0 ? c[1] - c[0] : k + 1 == n ? c[n - 1] - c[n - 2] : 0.5f * (c[k + 1] - c[k - 1]);
  if (glm::length(t) < 1e-12f) t = glm::vec3(0, -1, 0);
  t = glm::normalize(t);
  const glm::vec3 nrm = head.scalpNormal(head.nearestScalpUv(c[k]));
  glm::vec3 b = glm::cross(t, nrm);
  if (glm::length(b) < 1e-6f) {  // the strand runs along the normal: any side direction
    const glm::vec3 a = std::abs(t.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    b = glm::cross(t, a);
  }
  return {t, nrm, glm::normalize(b)};
}

}  // namespace loosehair

namespace loosehair {

std::vector<glm::vec3> reRootKeyStrand(const std::vector<glm::vec3>& control, const HeadModel& from, glm::vec2 from_uv,
                                       const HeadModel& to, glm::vec2 to_uv) {
  const glm::mat3 a = rootFrame(from, from_uv), b = rootFrame(to, to_uv);
  const glm::vec3 origin = control.empty() ? from.scalpPoint(from_uv) : control[0];
  const glm::vec3 target = to.scalpPoint(to_uv);
  std::vector<glm::vec3> out;
  out.reserve(control.size());
  for (const glm::vec3& c : control) out.push_back(target + b * (glm::transpose(a) * (c - origin)));
  if (!out.empty()) out[0] = target;
  return out;
}

}  // namespace loosehair
