#include "loosehair/style_settle.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/strand_field.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <string>

namespace loosehair {

namespace {
// points a span of the key strand carried (the spline passes through the
// control points at multiples of it)
constexpr int kPerSpan = 4;
// p pushed out of the head and the world bodies to the styling clearance
// (a few rounds for the creases where they meet)
constexpr float kClear = 0.003f;  // StyleEditor::kClearance

glm::vec3 keptOutside(const Solver& solver, glm::vec3 p, float clearance = kClear) {
  for (int round = 0; round < 4; ++round) {
    float phi = 0.0f;
    glm::vec3 n(0.0f);
    solver.bodyContacts(std::span<const glm::vec3>(&p, 1), solver.time(), 2.0f * clearance, std::span<float>(&phi, 1),
                        std::span<glm::vec3>(&n, 1));
    if (!(phi < clearance)) break;
    p += (clearance - phi) * n;
  }
  return p;
}

// The spans whose spline passes 2.9 mm or more inside the head or torso
// (checkStyle refuses 3 mm in the head): the index of each span's first
// control point and how deep.
std::vector<std::pair<std::size_t, float>> spansInside(const Solver& solver, const std::vector<glm::vec3>& c) {
  constexpr int kPer = 8;
  const std::vector<glm::vec3> dense = sampleKeyStrand(c, kPer);
  std::vector<float> phi;
  solver.bodyDistance(dense, solver.time(), phi);
  std::vector<std::pair<std::size_t, float>> spans;
  for (std::size_t j = 1; j < dense.size(); ++j) {
    const std::size_t k = std::min((j - 1) / kPer, c.size() - 2);
    if (!(phi[j] < -0.0029f)) continue;
    if (spans.empty() || spans.back().first != k) spans.emplace_back(k, 0.0f);
    spans.back().second = std::max(spans.back().second, -phi[j]);
  }
  return spans;
}

}  // namespace

std::vector<std::vector<glm::vec3>> settledKeyStrands(const Style& style, const SettleOptions& o) {
  if (style.wisps.empty()) throw StyleError("settle: the style has no wisps");
  if (!(o.seconds > 0.0 && o.seconds <= 10.0))
    throw StyleError("settle: seconds must be in (0, 10], got " + std::to_string(o.seconds));
  if (!(o.particles >= 200 && o.particles <= 20000))
    throw StyleError("settle: particles must be in [200, 20000], got " + std::to_string(o.particles));
  if (!(o.threads >= 0 && o.threads <= 1024))
    throw StyleError("settle: threads must be in [0, 1024], got " + std::to_string(o.threads));
  // the style's hair on its own head, still, with the plain physics
  SceneDesc scene;
  static_cast<HeadDesc&>(scene) = style.head;
  scene.source = style.source.empty() ? std::string("the style being edited") : style.source;
  scene.name = style.name;
  scene.hair.style = style.source;
  scene.hair.style_data = std::make_shared<const Style>(style);
  scene.hair.particles = o.particles;
  scene.shape_keeping_auto = false;
  scene.sim.shape_keeping = 0.0f;
  scene.sim.threads = o.threads;
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  // the key strands, carried by the particles as render strands are
  StrandSet keys;
  keys.first.push_back(0);
  for (std::size_t w = 0; w < style.wisps.size(); ++w) {
    const std::vector<glm::vec3> dense = sampleKeyStrand(style.wisps[w].key_strand, kPerSpan);
    keys.points.insert(keys.points.end(), dense.begin(), dense.end());
    keys.first.push_back(static_cast<std::uint32_t>(keys.points.size()));
    keys.wisp.push_back(static_cast<std::uint32_t>(w));
    keys.root_uv.push_back(glm::vec2(0.0f));
  }
  StrandFieldOptions field_options;
  field_options.support = 2.0f * std::max(build.mean_neighbor_distance, 1e-4f);
  const StrandField field(std::move(keys), solver.particles(), field_options, std::max(1, o.threads));
  solver.advance(static_cast<int>(std::ceil(o.seconds / solver.params().time_step)));
  std::vector<glm::vec3> carried;
  field.deform(solver, carried, std::max(1, o.threads));
  std::vector<std::vector<glm::vec3>> out(style.wisps.size());
  const StrandSet& rest = field.rest();
  for (std::size_t w = 0; w < style.wisps.size(); ++w) {
    const std::vector<glm::vec3>& key = style.wisps[w].key_strand;
    // the carried points the control points are (index into the wisp's
    // dense key strand), each kept outside the bodies
    std::vector<std::size_t> at(key.size());
    for (std::size_t k = 0; k < key.size(); ++k) at[k] = k * kPerSpan;
    const glm::vec3* dense = carried.data() + rest.first[w];
    auto point = [&](std::size_t a) { return a == 0 ? key[0] : keptOutside(solver, dense[a]); };
    std::vector<glm::vec3> c(key.size());
    std::vector<float> clear(key.size(), kClear);
    for (std::size_t k = 0; k < key.size(); ++k) c[k] = point(at[k]);
    // A span whose spline dips into a body gets the carried point halfway
    // along it (the hair lay outside, its sparse spline need not); one
    // between neighbouring carried points (round a nose, say) has its ends
    // kept farther out by the depth.
    for (int round = 0; round < 8; ++round) {
      const std::vector<std::pair<std::size_t, float>> dips = spansInside(solver, c);
      if (dips.empty()) break;
      for (auto it = dips.rbegin(); it != dips.rend(); ++it) {
        const std::size_t k = it->first;
        if (at[k + 1] - at[k] >= 2) {
          const std::size_t mid = (at[k] + at[k + 1]) / 2;
          at.insert(at.begin() + static_cast<std::ptrdiff_t>(k + 1), mid);
          c.insert(c.begin() + static_cast<std::ptrdiff_t>(k + 1), point(mid));
          clear.insert(clear.begin() + static_cast<std::ptrdiff_t>(k + 1), kClear);
          continue;
        }
        for (std::size_t e : {k, k + 1}) {
          if (e == 0) continue;  // the root stays
          clear[e] += it->second;
          c[e] = keptOutside(solver, c[e], clear[e]);
        }
      }
    }
    out[w] = std::move(c);
  }
  return out;
}

}  // namespace loosehair
