#include "loosehair/render_strands.hpp"

#include "init/hanging_hair.hpp"
#include "init/scalp_surface.hpp"
#include "loosehair/head_model.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/strand_field.hpp"
#include "util/parallel.hpp"
#include "util/random.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {

StrandSet resampleStrands(const StrandSet& strands, int points) {
  if (points < 2 || points > 256)
    throw std::invalid_argument("points per strand " + std::to_string(points) + " is outside 2..256");
  StrandSet out;
  out.first.assign(1, 0);
  std::vector<float> s;
  for (std::size_t k = 0; k < strands.size(); ++k) {
    const glm::vec3* p = strands.points.data() + strands.first[k];
    const std::size_t n = strands.pointCount(k);
    if (n < 2) continue;
    s.assign(n, 0.0f);
    for (std::size_t j = 1; j < n; ++j) s[j] = s[j - 1] + glm::length(p[j] - p[j - 1]);
    const float length = s.back();
    if (!(length > 0.0f)) continue;
    std::size_t seg = 0;
    for (int j = 0; j < points; ++j) {
      const float target = length * static_cast<float>(j) / static_cast<float>(points - 1);
      while (seg + 2 < n && s[seg + 1] < target) ++seg;
      const float span = s[seg + 1] - s[seg];
      const float a = span > 0.0f ? std::clamp((target - s[seg]) / span, 0.0f, 1.0f) : 0.0f;
      out.points.push_back(j == 0 ? p[0] : j == points - 1 ? p[n - 1] : p[seg] + a * (p[seg + 1] - p[seg]));
    }
    out.first.push_back(static_cast<std::uint32_t>(out.points.size()));
    out.wisp.push_back(k < strands.wisp.size() ? strands.wisp[k] : 0u);
    out.root_uv.push_back(k < strands.root_uv.size() ? strands.root_uv[k] : glm::vec2(0.0f));
  }
  return out;
}

namespace {

// A style's member strands, its wisps' densities scaled so that about
// `target` strands grow (counted wisps, an imported groom's, stay as made).
StrandSet styleStrands(const SceneDesc& scene, const HeadModel& model, std::size_t target, int threads) {
  Style style = sceneStyle(scene, model);
  // counted with coarse polylines: the count does not depend on the spacing
  // of the points, and the coarse build costs a fraction of the real one
  constexpr float kCountingSpacing = 0.05f;
  const StrandSet counting = buildMemberStrands(style, model, kCountingSpacing, scene.limits.style, threads);
  std::size_t counted = 0, dense = 0;
  for (std::size_t k = 0; k < counting.size(); ++k) {
    if (style.wisps[counting.wisp[k]].params.strands > 0)
      ++counted;
    else
      ++dense;
  }
  if (dense > 0 && target > counted) {
    const float scale = static_cast<float>(target - counted) / static_cast<float>(dense);
    for (Wisp& w : style.wisps)
      if (w.params.strands == 0) w.params.density *= scale;
  }
  return buildMemberStrands(style, model, kStrandSpacing, scene.limits.style, threads);
}

// One strand per scalp sample, hung like the particles (method.md §6.1):
// samples uniform in area from the scene's seed.
StrandSet hangingStrands(const SceneDesc& scene, const HeadModel& model, std::size_t target, int points,
                         float poisson_radius, int threads) {
  const HangingHair hanging(scene, model);
  const ScalpSurface& scalp = model.scalp();
  // the particles' Poisson radius (or an estimate of it), for their
  // clearance off the head and the pieces of their cantilevers: the same
  // pieces give the same curve
  const float rp = poisson_radius > 0.0f ? poisson_radius
                                         : std::cbrt(static_cast<float>(scalp.area()) * hanging.maxLength() /
                                                     static_cast<float>(std::max(scene.hair.particles, 1)));
  const float clearance = std::max(scene.sim.contact_thickness, 0.25f * rp);
  Random rng(scene.seed ^ 0x5bd1e995c0ffee11ULL);
  StrandSet out;
  // the roots in the seed's order, then each strand's cantilever on its
  // own (most of the binding's time: exact body queries along each one)
  out.root_uv.resize(target);
  for (std::size_t k = 0; k < target; ++k) out.root_uv[k] = scalp.sampleByArea(rng);
  const std::size_t per = static_cast<std::size_t>(points);
  out.points.resize(target * per);
  out.first.resize(target + 1);
  for (std::size_t k = 0; k <= target; ++k) out.first[k] = static_cast<std::uint32_t>(k * per);
  out.wisp.assign(target, 0);
  parallel::forEachDynamic(threads, target, [&](std::size_t k) {
    const glm::vec2 uv = out.root_uv[k];
    const int segments = std::max(8, static_cast<int>(std::ceil(hanging.length(uv) / (0.5f * rp))));
    const CantileverStrand strand = hanging.strand(uv, segments, clearance);
    const float length = strand.length();
    glm::vec3* p = &out.points[k * per];
    for (int j = 0; j < points; ++j)
      p[j] =
          j == 0 ? scalp.point(uv) : strand.position(length * static_cast<float>(j) / static_cast<float>(points - 1));
  });
  return out;
}

}  // namespace

StrandSet growRenderStrands(const SceneDesc& scene, const HeadModel& model, const RenderStrandOptions& options,
                            int threads) {
  if (options.strands < 1 || options.strands > 2'000'000)
    throw std::invalid_argument("strands " + std::to_string(options.strands) + " is outside 1..2000000");
  if (options.points < 2 || options.points > 256)
    throw std::invalid_argument("points per strand " + std::to_string(options.points) + " is outside 2..256");
  // strands times points, before they are made (a groom's one-strand wisps
  // may come to more strands than asked)
  auto check = [&](std::size_t strands) {
    const double points = static_cast<double>(strands) * options.points;
    if (points > static_cast<double>(scene.limits.max_strand_points))
      throw SceneError(scene.source + ": " + std::to_string(strands) + " render strands of " +
                       std::to_string(options.points) + " points make " +
                       std::to_string(static_cast<long long>(points)) + " points, above the limit of " +
                       std::to_string(scene.limits.max_strand_points) +
                       ": ask for fewer strands or points a strand (--strands, --strand-points) (or "
                       "--allow-expensive)");
  };
  const bool styled = scene.hair.style_data || !scene.hair.style.empty();
  if (styled) {
    StrandSet grown = styleStrands(scene, model, options.strands, threads);
    check(grown.size());
    return resampleStrands(grown, options.points);
  }
  check(options.strands);
  return hangingStrands(scene, model, options.strands, options.points, options.poisson_radius, threads);
}

StrandField bindSceneStrands(const SceneDesc& scene, const Particles& rest, const BuildReport& build,
                             RenderStrandOptions options, int threads) {
  const HeadModel model = HeadModel::build(scene, scene.source, scene.limits.mesh);
  StrandFieldOptions field;
  field.support = 2.0f * std::max(build.mean_neighbor_distance, 1e-4f);
  if (options.poisson_radius <= 0.0f) options.poisson_radius = build.poisson_radius;
  // strands are grown in the shape the particles were grown in: bound to
  // that state where the scene settled the hair before its first frame
  return StrandField(growRenderStrands(scene, model, options, threads), build.grown ? *build.grown : rest, field,
                     threads);
}

}  // namespace loosehair
