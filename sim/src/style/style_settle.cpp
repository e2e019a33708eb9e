#include "loosehair/style_settle.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/strand_field.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace loosehair {

namespace {
// points a span of the key strand carried (the spline passes through the
// control points at multiples of it)
constexpr int kPerSpan = 4;
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
    out[w].resize(key.size());
    for (std::size_t k = 0; k < key.size(); ++k)
      out[w][k] = k == 0 ? key[0] : carried[rest.first[w] + static_cast<std::uint32_t>(k * kPerSpan)];
  }
  return out;
}

}  // namespace loosehair
