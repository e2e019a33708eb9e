// Member strands of a wisp (method.md §6.2; Zhang & Wünsche §3.2).
//
// Roots: Poisson-disc darts over the region's scalp triangles, drawn by area,
// the region's root first. Shape: the key strand's dense Catmull-Rom
// polyline K(s) with its rotation-minimising frame F(s); member m with root
// r_m and a random vector d_m from the ball of radius offset_radius follows
//
//   P_m(s) = K(s) + (1 - g(s)) (r_m - K(0)) + (s / L) F(s) d_m  [+ curl]
//
// so the offset from the translated key strand grows linearly from 0 at the
// root to |d_m| <= offset_radius at the tip (the paper's per-control-point
// offsets, evaluated continuously along the curve). g = 0 without ties;
// through a tie, g rises smoothly from 0 at the root to 1 where the key
// strand crosses the ring, so the wisp's members converge onto the key
// strand there (their offset bounded to stay inside the ring) and hang
// together beyond it. Finally each member is cut to its length and pushed
// out of the head and torso.
//
// Blending (issue 44, WispParams::blend > 0, wisps not through a tie): the
// translated key strand K(s) - K(0) becomes a weighted mean of the key
// strands of the wisp and its neighbours, each taken at the same fraction
// of its own length, with weights from the member root's distances to the
// wisps' roots: neighbour j counts exp(-(d_j^2 - d_own^2) / (2 sigma_j^2))
// against the own wisp's 1, sigma_j = 0.35 blend |R_own - R_j|. Midway
// between two roots the two count the same, so the members of adjacent
// wisps meet in one shape there; near its own root a member follows its
// own key strand. Wisps whose tips part by more than half the strand's
// length (a parting) are not blended.
//
// The hairline (WispParams::edge_ramp): a member rooted at distance d from
// the edge of the hair (the boundary edges of the union of all regions'
// scalp triangles) is kept with probability d / edge_ramp, drawn from a
// stream of its own, so the edge thins out instead of ending in a row.
#include "init/mesh_scalp.hpp"
#include "loosehair/style.hpp"
#include "util/parallel.hpp"
#include "util/point_hash.hpp"
#include "util/random.hpp"
#include "style/hair_tie.hpp"
#include "style/rotation_minimizing_frame.hpp"
#include "style/wisp_region.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace loosehair {
namespace {

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

glm::vec3 inBall(Random& rng, float radius) {
  for (;;) {
    const glm::vec3 q(static_cast<float>(rng.uniform(-1.0, 1.0)), static_cast<float>(rng.uniform(-1.0, 1.0)),
                      static_cast<float>(rng.uniform(-1.0, 1.0)));
    if (glm::dot(q, q) <= 1.0f) return radius * q;
  }
}

// Polyline points a segment of the key strand's dense curve, for `spacing`.
int pointsASegment(const Wisp& w, float spacing) {
  float longest = 0;
  for (std::size_t k = 1; k < w.key_strand.size(); ++k)
    longest = std::max(longest, glm::length(w.key_strand[k] - w.key_strand[k - 1]));
  return std::clamp(static_cast<int>(std::ceil(longest / spacing)), 2, 256);
}

// The points of each of a wisp's member strands.
double pointsAStrand(const Wisp& w, float spacing) {
  return static_cast<double>(w.key_strand.size() - 1) * pointsASegment(w, spacing) + 1.0;
}

// The most strands memberRoots gives a wisp of scalp area `area`.
double mostMembers(const Wisp& w, double area) {
  if (w.params.strands > 0) return static_cast<double>(w.params.strands);
  return std::max(1.0, std::round(static_cast<double>(w.params.density) * 1e4 * area));
}

// Roots of a wisp's members in (u, v), the region's root first.
// `area`: regionArea of the wisp's region.
std::vector<glm::vec2> memberRoots(const Wisp& w, const HeadModel& head, double area, Random& rng) {
  const ScalpTriangles& s = head.scalpTriangles();
  const std::vector<std::uint32_t> tris = regionTriangles(w.region, head);
  std::vector<glm::vec2> roots{regionRoot(w.region, head)};
  if (tris.empty()) return roots;
  const double wanted = mostMembers(w, area);
  const auto target = static_cast<std::size_t>(wanted);
  if (target <= 1 || !(area > 0.0)) return roots;
  const float radius = static_cast<float>(0.6 / std::sqrt(wanted / area));
  std::vector<double> cdf;
  double total = 0;
  for (std::uint32_t t : tris) cdf.push_back(total += s.areas[t]);
  PointHash taken(radius);
  auto accept = [&](glm::vec3 p) {
    if (taken.anyNearer(p, radius)) return false;
    taken.add(p);
    return true;
  };
  accept(head.scalpPoint(roots[0]));
  const std::size_t tries = 40 * target + 64;
  for (std::size_t k = 0; k < tries && roots.size() < target; ++k) {
    const double x = rng.uniform() * total;
    const std::size_t i =
        std::min(static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin()), tris.size() - 1);
    const auto tr = s.triangles[tris[i]];
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    const glm::vec2 uv = static_cast<float>(1.0 - r1) * s.uvs[tr.x] +
                         static_cast<float>(r1 * (1.0 - r2)) * s.uvs[tr.y] + static_cast<float>(r1 * r2) * s.uvs[tr.z];
    if (!regionContains(w.region, head, uv)) continue;
    if (accept(head.scalpPoint(uv))) roots.push_back(uv);
  }
  return roots;
}

// Refuses a style that could grow more than the budget, before any work.
void checkBudget(const Style& style, const std::vector<double>& area, float spacing, const StrandBudget& budget) {
  double strands = 0, points = 0, worst_points = -1;
  std::size_t worst = 0;
  for (std::size_t wi = 0; wi < style.wisps.size(); ++wi) {
    const Wisp& w = style.wisps[wi];
    if (w.key_strand.size() < 2) continue;
    const double members = mostMembers(w, area[wi]);
    const double each = pointsAStrand(w, spacing);
    strands += members;
    points += members * each;
    if (members * each > worst_points) {
      worst_points = members * each;
      worst = wi;
    }
  }
  if (strands <= static_cast<double>(budget.max_strands) && points <= static_cast<double>(budget.max_points)) return;
  const Wisp& w = style.wisps[worst];
  auto count = [](double v) { return std::to_string(static_cast<long long>(std::min(v, 9.0e18))); };
  const std::string most =
      2.0 * worst_points >= points
          ? "most of them from wisps[" + std::to_string(worst) + "] (" + count(mostMembers(w, area[worst])) +
                " strands of " + count(pointsAStrand(w, spacing)) + " points): lower its density or strands"
          : "spread over " + std::to_string(style.wisps.size()) + " wisps: use fewer wisps or lower their densities";
  throw StyleError(style.source + ": the wisps would grow up to " + count(strands) + " strands of " + count(points) +
                   " points, above the limit of " + std::to_string(budget.max_strands) + " strands and " +
                   std::to_string(budget.max_points) + " points, " + most +
                   ", or use fewer key-strand control points or a coarser point spacing (or --allow-expensive)");
}

}  // namespace

namespace {

// Every wisp's dense key strand, its arc lengths and the first tie it
// passes through: blending reads its neighbours'.
struct KeyStrands {
  std::vector<std::vector<glm::vec3>> dense;
  std::vector<std::vector<float>> arc;
  std::vector<std::optional<TieCrossing>> crossing;
  std::vector<const HairTie*> ring;
  /// A wisp whose shape others may blend with (a key strand of some length, no tie).
  bool blendable(std::size_t j) const { return !dense[j].empty() && arc[j].back() > 0.0f && !crossing[j]; }
  /// Key strand j from its root at fraction t of its length.
  glm::vec3 shapeAt(std::size_t j, float t) const {
    const std::vector<float>& s = arc[j];
    const float at = t * s.back();
    const std::size_t hi = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), at) - s.begin()), s.size() - 1);
    const std::size_t lo = hi > 0 ? hi - 1 : 0;
    const float span = s[hi] - s[lo];
    const float f = span > 0.0f ? std::clamp((at - s[lo]) / span, 0.0f, 1.0f) : 0.0f;
    return dense[j][lo] + f * (dense[j][hi] - dense[j][lo]) - dense[j][0];
  }
};

KeyStrands keyStrands(const Style& style, float spacing, int threads) {
  const std::size_t nw = style.wisps.size();
  KeyStrands keys;
  keys.dense.resize(nw);
  keys.arc.resize(nw);
  keys.crossing.resize(nw);
  keys.ring.assign(nw, nullptr);
  auto& dense = keys.dense;
  auto& arc = keys.arc;
  auto& crossing = keys.crossing;
  auto& ring = keys.ring;
  parallel::forEachDynamic(threads, nw, [&](std::size_t wi) {
    const Wisp& w = style.wisps[wi];
    if (w.key_strand.size() < 2) return;
    dense[wi] = catmullRom(w.key_strand, pointsASegment(w, spacing));
    arc[wi].assign(dense[wi].size(), 0.0f);
    for (std::size_t j = 1; j < dense[wi].size(); ++j)
      arc[wi][j] = arc[wi][j - 1] + glm::length(dense[wi][j] - dense[wi][j - 1]);
    // the first tie the key strand passes through
    for (const HairTie& t : style.ties)
      if (auto c = crossTie(dense[wi], t); c && (!crossing[wi] || c->arc_length < crossing[wi]->arc_length)) {
        crossing[wi] = c;
        ring[wi] = &t;
      }
  });
  return keys;
}

// The edge of the hair: edges of the union of the regions' triangles that
// only one of its triangles has.
std::vector<std::pair<glm::vec3, glm::vec3>> hairEdge(const Style& style, const HeadModel& head) {
  std::vector<std::pair<glm::vec3, glm::vec3>> hair_edge;
  const ScalpTriangles& st = head.scalpTriangles();
  std::vector<std::uint8_t> in(st.triangles.size(), 0);
  for (const Wisp& w : style.wisps)
    for (std::uint32_t t : regionTriangles(w.region, head)) in[t] = 1;
  std::vector<std::pair<std::uint64_t, int>> edges;  // (lower vertex << 32 | higher), count
  for (std::size_t t = 0; t < st.triangles.size(); ++t) {
    if (!in[t]) continue;
    for (int e = 0; e < 3; ++e) {
      std::uint32_t a = st.triangles[t][e], b = st.triangles[t][(e + 1) % 3];
      if (a > b) std::swap(a, b);
      edges.emplace_back((static_cast<std::uint64_t>(a) << 32) | b, 1);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i == 1)
      hair_edge.emplace_back(st.positions[edges[i].first >> 32], st.positions[edges[i].first & 0xffffffffu]);
    i = j;
  }
  return hair_edge;
}

float edgeDistance(const std::vector<std::pair<glm::vec3, glm::vec3>>& hair_edge, glm::vec3 p) {
  float best = INFINITY;
  for (const auto& [a, b] : hair_edge) {
    const glm::vec3 ab = b - a;
    const float l2 = glm::dot(ab, ab);
    const float t = l2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / l2, 0.0f, 1.0f) : 0.0f;
    best = std::min(best, glm::length(p - (a + t * ab)));
  }
  return best;
}

// The neighbours a wisp blends with: within four times the nearest one, and
// not across a parting (their tips, from the roots, further apart than
// half the strand: blended, the two would fall between them, where neither
// goes, over a face). Each with its sigma^2.
std::vector<std::pair<std::size_t, float>> blendNeighbours(const KeyStrands& keys, std::size_t wi, float blend,
                                                           float length) {
  const std::size_t nw = keys.dense.size();
  const std::vector<glm::vec3>& key = keys.dense[wi];
  std::vector<std::pair<std::size_t, float>> near;  // wisp, sigma^2
  if (blend > 0.0f && keys.blendable(wi)) {
    float nearest = INFINITY;
    for (std::size_t j = 0; j < nw; ++j)
      if (j != wi && keys.blendable(j)) nearest = std::min(nearest, glm::length(keys.dense[j][0] - key[0]));
    for (std::size_t j = 0; j < nw; ++j) {
      if (j == wi || !keys.blendable(j)) continue;
      const float d = glm::length(keys.dense[j][0] - key[0]);
      const bool parting = glm::length(keys.shapeAt(j, 1.0f) - keys.shapeAt(wi, 1.0f)) > 0.5f * length;
      if (d > 1e-6f && d <= 4.0f * nearest && !parting) {
        const float sigma = 0.35f * blend * d;
        near.emplace_back(j, sigma * sigma);
      }
    }
  }
  return near;
}

// A member's points cut to `cut` along its own arc; returns how many are
// kept (at least 2).
std::size_t cutToLength(std::vector<glm::vec3>& pts, float cut) {
  std::size_t n = 1;
  float s = 0;
  for (; n < pts.size(); ++n) {
    const float seg = glm::length(pts[n] - pts[n - 1]);
    if (s + seg >= cut) {
      const float t = seg > 0.0f ? (cut - s) / seg : 0.0f;
      if (t > 1e-3f) pts[n] = pts[n - 1] + t * (pts[n] - pts[n - 1]), ++n;
      break;
    }
    s += seg;
  }
  n = std::max<std::size_t>(n, 2);
  return n;
}

// A member's points [1, n) out of the head and torso (a translated copy may
// dip into a curved head), to the clearance. Exact only near the surface:
// the push acts only below the clearance; the second pass asks again about
// the points the first pushed (a crease), the others cannot have changed.
struct PushScratch {
  std::vector<float> phi;
  std::vector<glm::vec3> nrm, q;
  std::vector<std::uint32_t> which;
};
void pushOutOfHead(const HeadModel& head, std::vector<glm::vec3>& pts, std::size_t n, float clearance, bool exact,
                   PushScratch& scratch) {
  std::vector<float>& phi = scratch.phi;
  std::vector<glm::vec3>& nrm = scratch.nrm;
  std::vector<glm::vec3>& q = scratch.q;
  std::vector<std::uint32_t>& which = scratch.which;
  phi.resize(n);
  nrm.resize(n);
  q.resize(n);
  which.resize(n);
  const Body* bodies[2] = {head.head().get(), head.torso().get()};
  for (const Body* b : bodies) {
    if (!b) continue;
    std::size_t asked = n - 1;
    for (std::size_t j = 0; j < asked; ++j) which[j] = static_cast<std::uint32_t>(j + 1);
    for (int pass = 0; pass < 2 && asked > 0; ++pass) {
      for (std::size_t k = 0; k < asked; ++k) q[k] = pts[which[k]];
      if (exact)
        b->signedDistanceBelow(q.data(), asked, clearance, phi.data(), nrm.data());
      else
        b->roughDistanceBelow(q.data(), asked, clearance, phi.data(), nrm.data());
      std::size_t pushed = 0;
      for (std::size_t k = 0; k < asked; ++k)
        if (phi[k] < clearance) {
          pts[which[k]] += (clearance - phi[k]) * nrm[k];
          which[pushed++] = which[k];
        }
      asked = pushed;
    }
  }
}

// One wisp's member strands (method.md §6.2): roots sampled in its region,
// each the key strand moved to its root (or blended with the neighbours'
// shapes), offset, curled, cut to its length and kept out of the head.
StrandSet wispMembers(const Style& style, std::size_t wi, const HeadModel& head, const KeyStrands& keys,
                      const std::vector<double>& area, const std::vector<std::pair<glm::vec3, glm::vec3>>& hair_edge,
                      float clearance, bool exact) {
  StrandSet out;
  const Wisp& w = style.wisps[wi];
  const WispParams& par = w.params;
  if (w.key_strand.size() < 2) return out;
  const std::vector<glm::vec3>& key = keys.dense[wi];
  const std::vector<float>& sk = keys.arc[wi];
  const float length = sk.back();
  if (!(length > 0.0f)) return out;
  const glm::vec2 root_uv = head.nearestScalpUv(key[0]);
  const std::vector<CurveFrame> frame = rotationMinimizingFrames(key, head.scalpTangentU(root_uv));
  const std::optional<TieCrossing>& tie = keys.crossing[wi];
  const HairTie* tie_ring = keys.ring[wi];
  std::vector<std::pair<std::size_t, float>> near;  // wisp, sigma^2
  if (par.blend > 0.0f && keys.blendable(wi)) near = blendNeighbours(keys, wi, par.blend, length);
  // each neighbour's shape at the own key strand's samples (the same
  // fractions of the length for every member)
  std::vector<std::vector<glm::vec3>> near_shape(near.size(), std::vector<glm::vec3>(key.size()));
  for (std::size_t n = 0; n < near.size(); ++n)
    for (std::size_t k = 0; k < key.size(); ++k) near_shape[n][k] = keys.shapeAt(near[n].first, sk[k] / length);
  std::vector<std::pair<std::size_t, float>> weights;  // a member's: index into near, weight
  Random rng(par.seed);
  const std::vector<glm::vec2> roots = memberRoots(w, head, area[wi], rng);
  Random shape(par.seed ^ 0x6a09e667f3bcc909ULL);
  Random thin(par.seed ^ 0xbb67ae8584caa73bULL);
  std::vector<glm::vec3> pts(key.size());
  PushScratch scratch;
  for (const glm::vec2 uv : roots) {
    const glm::vec3 root = head.scalpPoint(uv);
    if (par.edge_ramp > 0.0f && !hair_edge.empty() && !(thin.uniform() * par.edge_ramp < edgeDistance(hair_edge, root)))
      continue;  // thinned towards the hairline
    const glm::vec3 delta = root - key[0];
    // the neighbours' weights against the own wisp's 1, normalised
    weights.clear();
    float total = 1.0f;
    const float own2 = glm::dot(delta, delta);
    for (std::size_t n = 0; n < near.size(); ++n) {
      const glm::vec3 dj = root - keys.dense[near[n].first][0];
      const float r = std::exp(-(glm::dot(dj, dj) - own2) / (2.0f * near[n].second));
      if (r > 1e-3f) {
        weights.emplace_back(n, r);
        total += r;
      }
    }
    glm::vec3 d = inBall(shape, par.offset_radius);
    const float keep = 1.0f - par.length_variation * static_cast<float>(shape.uniform());
    const float phase = static_cast<float>(2.0 * std::numbers::pi * shape.uniform());
    if (tie) {  // inside the ring where the wisp passes through it
      const float allowed = std::max(0.0f, 0.85f * tie_ring->radius - tie->axis_distance);
      const float at_tie = glm::length(d) * tie->arc_length / length;
      if (at_tie > allowed) d *= allowed / at_tie;
    }
    for (std::size_t j = 0; j < key.size(); ++j) {
      const float s = sk[j];
      const float g = tie ? (s < tie->arc_length ? smoothstep01(s / tie->arc_length) : 1.0f) : 0.0f;
      const CurveFrame& f = frame[j];
      glm::vec3 p;
      if (weights.empty()) {
        p = key[j] + (1.0f - g) * delta;
      } else {  // no tie here (g = 0): the blended shape from the member's root
        glm::vec3 blended = (key[j] - key[0]) / total;
        for (const auto& [n, r] : weights) blended += (r / total) * near_shape[n][j];
        p = root + blended;
      }
      p += (s / length) * (d.x * f.tangent + d.y * f.normal + d.z * f.binormal);
      if (par.curl_radius > 0.0f) {
        const float rho = par.curl_radius * smoothstep01(s / par.curl_period);
        const float th = 2.0f * std::numbers::pi_v<float> * s / par.curl_period + phase;
        p += rho * (std::cos(th) * f.normal + std::sin(th) * f.binormal);
      }
      pts[j] = p;
    }
    // cut to the member's length along its own arc; through a tie only the
    // tail beyond the ring is shortened (a member ending before the ring
    // would not be held by it)
    float cut = keep * length;
    if (tie) {
      float own = 0.0f;  // the member's own arc to where the key strand crosses the ring
      for (std::size_t j = 1; j < pts.size() && sk[j - 1] < tie->arc_length; ++j)
        own += glm::length(pts[j] - pts[j - 1]);
      cut = own + keep * std::max(0.0f, length - tie->arc_length);
    }
    const std::size_t n = cutToLength(pts, cut);
    // out of the head and torso (a translated copy may dip into a curved head)
    pushOutOfHead(head, pts, n, clearance, exact, scratch);
    out.points.insert(out.points.end(), pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(n));
    out.first.push_back(static_cast<std::uint32_t>(out.points.size()));
    out.wisp.push_back(static_cast<std::uint32_t>(wi));
    out.root_uv.push_back(uv);
  }
  return out;
}

}  // namespace

StrandSet buildMemberStrands(const Style& style, const HeadModel& head, float spacing, const StrandBudget& budget,
                             int threads, bool exact) {
  spacing = std::max(spacing, 1e-4f);
  // each region's scalp area, once (a pass over the scalp each)
  std::vector<double> area(style.wisps.size(), 0.0);
  for (std::size_t wi = 0; wi < style.wisps.size(); ++wi)
    if (style.wisps[wi].key_strand.size() >= 2) area[wi] = regionArea(style.wisps[wi].region, head);
  checkBudget(style, area, spacing, budget);
  const float clearance = 1e-3f;
  // each wisp on its own (its own random streams), then in the wisps' order;
  // a wisp's `first` holds only its strands' ends (the leading 0 is the
  // whole set's)
  const std::size_t nw = style.wisps.size();
  const KeyStrands keys = keyStrands(style, spacing, threads);
  // the edge of the hair (wanted only with a ramp)
  bool any_ramp = false;
  for (const Wisp& w : style.wisps) any_ramp = any_ramp || w.params.edge_ramp > 0.0f;
  const std::vector<std::pair<glm::vec3, glm::vec3>> hair_edge =
      any_ramp ? hairEdge(style, head) : std::vector<std::pair<glm::vec3, glm::vec3>>();
  std::vector<StrandSet> per_wisp(nw);
  parallel::forEachDynamic(threads, nw, [&](std::size_t wi) {
    per_wisp[wi] = wispMembers(style, wi, head, keys, area, hair_edge, clearance, exact);
  });
  StrandSet all;
  all.first.push_back(0);
  for (const StrandSet& part : per_wisp) {
    const auto base = static_cast<std::uint32_t>(all.points.size());
    all.points.insert(all.points.end(), part.points.begin(), part.points.end());
    for (const std::uint32_t f : part.first) all.first.push_back(base + f);
    all.wisp.insert(all.wisp.end(), part.wisp.begin(), part.wisp.end());
    all.root_uv.insert(all.root_uv.end(), part.root_uv.begin(), part.root_uv.end());
  }
  return all;
}

}  // namespace loosehair
