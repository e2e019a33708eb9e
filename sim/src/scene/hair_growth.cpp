// Growing a scene's hair particles (method.md §6.1, §6.2).
#include "scene/hair_growth.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/param_table.hpp"
#include "init/cantilever.hpp"
#include "init/hanging_hair.hpp"
#include "init/poisson_pillar.hpp"
#include "init/length_map.hpp"
#include "init/mesh_scalp.hpp"
#include "init/scalp_surface.hpp"
#include "bodies/head_orientation.hpp"
#include "loosehair/json_checks.hpp"
#include "solver/neighbor_grid.hpp"
#include "util/parallel.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/head_model.hpp"
#include "files/json_fields.hpp"
#include "loosehair/style.hpp"
#include "style/hair_tie.hpp"
#include "style/style_seeding.hpp"
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <chrono>
#include <optional>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <unordered_map>
#include <set>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace loosehair {

Style sceneStyle(const SceneDesc& scene, const HeadModel& model, BuildReport* report) {
  const HairSpec& hair = scene.hair;
  Style style = hair.style_data ? *hair.style_data : loadStyle(hair.style);
  if (!style.head.sameAs(scene)) {
    BuildReport other;
    const HeadModel from = HeadModel::build(style.head, style.source, scene.limits.mesh, &other);
    checkStyle(style, from);
    style = retargetStyle(style, from, model);
    if (report)
      report->warnings.push_back(
          "hair.style: the style was made on another head; its wisps were placed on this one by their scalp (u, v)");
  } else {
    checkStyle(style, model);
  }
  return style;
}

// The threads the scene's build runs on: solver.threads where it is in
// range (one out of range is refused with the other solver parameters
// once the particles are made: until then, the default), else all.
int buildThreads(const SceneDesc& scene) {
  const int asked = scene.sim.threads;
  return asked > 0 && asked <= parallel::kMaxThreads ? asked : parallel::availableThreads();
}

// The particles of a styled scene (method.md §6.2): the style's member strands,
// on the scene's head (retargeted by (u, v) when the style was made on
// another one), sampled by Poisson-disc darts; particles inside a tie are
// held like roots.
// Returns the style's own shape-keeping strength (Hz).
float growFromStyle(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp, BuildReport& rep,
                    TieTethers& tethers) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const HairSpec& hair = scene.hair;
  const Style style = sceneStyle(scene, model, &rep);
  const StrandSet strands = buildMemberStrands(style, model, kStrandSpacing, scene.limits.style, buildThreads(scene));
  if (strands.size() == 0) throw SceneError(scene.source + ": hair.style: the style grows no strands");
  rep.style_wisps = style.wisps.size();
  rep.style_strands = strands.size();
  rep.style_points = strands.points.size();
  rep.seconds_strands = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto t1 = Clock::now();
  const StrandSeeding seeded = seedFromStrands(strands, hair.particles, scene.seed);
  rep.seconds_sampling = std::chrono::duration<double>(Clock::now() - t1).count();
  const std::size_t n = seeded.samples.size();
  if (n < 2)
    throw SceneError(scene.source + ": hair.particles: too few particles could be placed on the style's strands");
  rp = seeded.radius;
  // Beyond a tie the ring is the hair's new root: a particle there measures
  // its arc length from where its strand crosses the ring, and its tether
  // (|x - r| <= s) runs to that point. (Measured from the scalp, strands of
  // the wisps gathered into one tail would have very different s side by
  // side, and the connections, made between neighbours in order of s, would
  // not hang the tail from the tie.)
  std::vector<std::optional<TieCrossing>> crossing(strands.size());
  std::vector<float> crossing_hold(strands.size(), 0.0f);
  if (!style.ties.empty()) {
    std::vector<glm::vec3> line;
    for (std::size_t k = 0; k < strands.size(); ++k) {
      line.assign(strands.points.begin() + strands.first[k], strands.points.begin() + strands.first[k + 1]);
      for (const HairTie& t : style.ties)
        if (auto c = crossTie(line, t); c && (!crossing[k] || c->arc_length < crossing[k]->arc_length)) {
          crossing[k] = c;
          crossing_hold[k] = t.hold;
        }
    }
  }
  p.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const StrandSample& q = seeded.samples[k];
    p.position[k] = q.position;
    p.direction[k] = q.direction;
    p.velocity[k] = glm::vec3(0.0f);
    p.uv[k] = q.uv;
    p.arc_length[k] = q.s;
    p.root_point[k] = q.root;
    p.mass[k] = hair.mass / static_cast<float>(n);
    bool tied = false;
    for (const HairTie& t : style.ties) tied = tied || insideTie(t, q.position);
    const std::optional<TieCrossing>& c = crossing[q.strand];
    if (c && q.s >= c->arc_length) {
      p.arc_length[k] = q.s - c->arc_length;
      p.root_point[k] = c->point;
    } else if (c && q.s >= 0.0f) {  // between scalp and tie: held from both ends
      if (tethers.reach.empty()) {
        tethers.point.assign(n, glm::vec3(0.0f));
        tethers.reach.assign(n, -1.0f);
        tethers.hold.assign(n, 0.0f);
      }
      tethers.point[k] = c->point;
      tethers.reach[k] = c->arc_length - q.s;
      tethers.hold[k] = crossing_hold[q.strand];
    }
    p.is_root[k] = (q.s < 0.0f || tied) ? 1 : 0;
    if (tied && q.s >= 0.0f) ++rep.tied_particles;
  }
  return style.shape_keeping;
}

// Particles a thread takes at a time while growing their strands.
constexpr std::size_t kStrandBatch = 64;

// The particles of a scene without a style (method.md §6.1): Poisson-disc
// samples of the hair pillar in (u, v, s), hung by cantilever strands from
// root directions given by the whorl.
void growCantilever(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp, BuildReport& rep) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  const HairSpec& hair = scene.hair;
  const ScalpSurface& scalp = model.scalp();
  const HangingHair hanging(scene, model);
  auto length_at = [&](glm::vec2 uv) { return hanging.length(uv); };
  const float max_length = hanging.maxLength();
  PillarOptions popt;
  popt.target_count = hair.particles;
  popt.seed = scene.seed;
  auto t_sampling = Clock::now();
  const PillarResult pillar = samplePillar(scalp, length_at, max_length, popt);
  rep.seconds_sampling = since(t_sampling);
  rp = pillar.radius;
  const std::size_t n = pillar.samples.size();
  if (n < 2) throw SceneError(scene.source + ": hair.particles: too few particles could be placed");

  // 2. Root directions from the whorl and cantilever strands (method.md §6.1).
  const float clearance = std::max(scene.sim.contact_thickness, 0.25f * rp);
  auto t_strands = Clock::now();

  p.resize(n);
  // Each particle's own strand, grown only as far as the particle (the
  // pieces beyond do not change the ones before): the particles are
  // independent, so they are shared among the threads (the same bits on
  // any count). The bodies' queries and the scalp's are read-only.
  parallel::forEachDynamic(buildThreads(scene), (n + kStrandBatch - 1) / kStrandBatch, [&](std::size_t batch) {
    for (std::size_t k = batch * kStrandBatch, e = std::min(n, k + kStrandBatch); k < e; ++k) {
      const PillarSample& smp = pillar.samples[k];
      p.uv[k] = smp.uv;
      p.arc_length[k] = smp.s;
      p.root_point[k] = smp.point;
      p.mass[k] = hair.mass / static_cast<float>(n);
      p.velocity[k] = glm::vec3(0.0f);
      if (smp.s < 0.0f) {
        const glm::vec3 root_dir = hanging.rootDirection(smp.uv);
        p.is_root[k] = 1;
        p.position[k] = smp.point + smp.s * root_dir;
        p.direction[k] = root_dir;
      } else {
        p.is_root[k] = 0;
        const float length = length_at(smp.uv);
        const int segments = std::max(8, static_cast<int>(std::ceil(length / (0.5f * rp))));
        const CantileverStrand strand = hanging.strand(smp.uv, segments, clearance, smp.s);
        p.position[k] = strand.position(smp.s);
        p.direction[k] = strand.tangent(smp.s);
      }
    }
  });

  rep.seconds_strands = since(t_strands);
}

}  // namespace loosehair
