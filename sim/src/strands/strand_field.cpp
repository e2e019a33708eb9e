// Strands carried by the particle field: binding at rest, then per frame the
// particles' rotations, the interpolation, the length limit along each
// strand and the push out of the bodies (loosehair/strand_field.hpp).
#include "loosehair/strand_field.hpp"

#include "loosehair/solver.hpp"
#include "util/parallel.hpp"
#include "strands/particle_rotation.hpp"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace loosehair {

namespace {

// Smooth weight of q = d / h in [0, 1): (1 - q^2)^3, zero with zero slope at
// q = 1, so bindings change particle groups without a kink.
float smoothWeight(float d2, float inv_h2) {
  const float a = 1.0f - d2 * inv_h2;
  return a > 0.0f ? a * a * a : 0.0f;
}

// Particles sorted by cell of a uniform grid, looked up by binary search.
class CellIndex {
 public:
  CellIndex(std::span<const glm::vec3> x, float cell) : inv_(1.0f / cell) {
    entries_.reserve(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) entries_.push_back({key(cellOf(x[i])), static_cast<std::uint32_t>(i)});
    std::sort(entries_.begin(), entries_.end(),
              [](const Entry& a, const Entry& b) { return a.key != b.key ? a.key < b.key : a.index < b.index; });
  }
  /// f(index) for every particle in the cells overlapping the ball (p, radius).
  template <class F>
  void forEachNear(glm::vec3 p, float radius, F&& f) const {
    const glm::ivec3 lo = cellOf(p - glm::vec3(radius)), hi = cellOf(p + glm::vec3(radius));
    // the key orders cells by x, then y, then z: a run of z is one range
    for (int xk = lo.x; xk <= hi.x; ++xk)
      for (int y = lo.y; y <= hi.y; ++y) {
        const std::uint64_t first = key({xk, y, lo.z}), last = key({xk, y, hi.z});
        auto it = std::lower_bound(entries_.begin(), entries_.end(), first,
                                   [](const Entry& e, std::uint64_t v) { return e.key < v; });
        for (; it != entries_.end() && it->key <= last; ++it) f(it->index);
      }
  }

 private:
  struct Entry {
    std::uint64_t key;
    std::uint32_t index;
  };
  glm::ivec3 cellOf(glm::vec3 p) const { return glm::ivec3(glm::floor(p * inv_)); }
  static std::uint64_t key(glm::ivec3 c) {
    auto part = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v + (1 << 20)) & 0x1fffffu); };
    return (part(c.x) << 42) | (part(c.y) << 21) | part(c.z);
  }
  float inv_;
  std::vector<Entry> entries_;
};

struct Candidate {
  float weight;
  std::uint32_t index;
};

// The k heaviest candidates, each less the (k+1)-th weight so that a
// particle leaving or joining the group does so with weight 0 (smooth),
// normalised. Returns false if no weight is left.
bool pickWeights(std::vector<Candidate>& c, int k, std::uint32_t* index, float* weight) {
  const std::size_t kk = static_cast<std::size_t>(k);
  // the k + 1 heaviest in order (a total order: the same for any input order)
  const auto heavier = [](const Candidate& a, const Candidate& b) {
    return a.weight != b.weight ? a.weight > b.weight : a.index < b.index;
  };
  std::partial_sort(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(std::min(c.size(), kk + 1)), c.end(), heavier);
  const float floor_w = c.size() > kk ? c[kk].weight : 0.0f;
  double sum = 0;
  for (std::size_t j = 0; j < kk; ++j) {
    const float w = j < c.size() ? c[j].weight - floor_w : 0.0f;
    index[j] = j < c.size() ? c[j].index : (c.empty() ? 0u : c[0].index);
    weight[j] = w;
    sum += w;
  }
  if (!(sum > 0.0)) return false;
  for (std::size_t j = 0; j < kk; ++j) weight[j] = static_cast<float>(weight[j] / sum);
  return true;
}

void checkFinite(const std::vector<glm::vec3>& v, const char* what) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y) || !std::isfinite(v[i].z))
      throw std::invalid_argument(std::string("StrandField: ") + what + " " + std::to_string(i) + " is not finite");
}

// Rounds of (push out by the bodies' fast approximation, length limit);
// exact pushes of what is left inside, at most kFinalPushes times; rounds
// of (mend the length at the tip, exact pushes).
constexpr int kRoughRounds = 3, kFinalPushes = 4, kTrimRounds = 2;
// A push that would leave a segment longer than this many rest lengths
// went through a thin part (pushOut); the entry point is then found to
// 2^-kEntryBisections of the segment (nearSidePush).
constexpr float kThroughStretch = 2.0f;
constexpr int kEntryBisections = 12;

// The smoothing along a strand: a binomial window of 2 kSmoothHalf + 1
// points, cut at the strand's ends and renormalised (the weights always sum
// to one, so a rigid motion commutes with it); the root is never moved.
constexpr int kSmoothHalf = 3;
constexpr float kSmoothTaps[kSmoothHalf + 1] = {20.0f, 15.0f, 6.0f, 1.0f};

template <class Get>
glm::vec3 smoothAt(std::size_t j, std::size_t n, Get&& get) {
  if (j == 0) return get(0);
  // the window may not reach past the root: it narrows near it
  const std::size_t half = std::min<std::size_t>(kSmoothHalf, j);
  glm::vec3 sum(0.0f);
  float wsum = 0.0f;
  for (std::size_t d = 0; d <= half; ++d) {
    const float w = kSmoothTaps[d];
    sum += w * get(j - d);
    wsum += w;
    if (d > 0 && j + d < n) {
      sum += w * get(j + d);
      wsum += w;
    }
  }
  return sum / wsum;
}
// A particle's rigid motion is fitted to its neighbours within 3 supports
// (at most the 64 nearest, at least 6): wide enough that neighbouring
// particles' motions differ smoothly, so the strands they carry bend
// smoothly (narrower neighbourhoods gave kinks where tips pile up).
constexpr std::size_t kMaxRotationNeighbors = 64, kMinRotationNeighbors = 6;
constexpr float kRotationRadius = 3.0f;

}  // namespace

BodyContacts solverBodyContacts(const Solver& solver) {
  return [&solver](std::span<const glm::vec3> p, float limit, bool rough, std::span<float> phi,
                   std::span<glm::vec3> n) { solver.bodyContacts(p, solver.time(), limit, phi, n, rough); };
}

StrandField::StrandField(StrandSet rest, const Particles& particles, const StrandFieldOptions& options, int threads)
    : rest_(std::move(rest)), options_(options), k_(options.particles_per_point) {
  if (!(options.support > 0.0f) || !std::isfinite(options.support))
    throw std::invalid_argument("StrandField: support " + std::to_string(options.support) + " must be > 0");
  if (k_ < 1 || k_ > 8)
    throw std::invalid_argument("StrandField: particles_per_point " + std::to_string(k_) + " is outside 1..8");
  if (!(options.length_tolerance >= 0.0f && options.length_tolerance < 0.5f))
    throw std::invalid_argument("StrandField: length_tolerance " + std::to_string(options.length_tolerance) +
                                " is outside [0, 0.5)");
  if (!(options.clearance >= 0.0f && options.clearance < 0.1f))
    throw std::invalid_argument("StrandField: clearance " + std::to_string(options.clearance) +
                                " is outside [0, 0.1) m");
  if (particles.size() == 0) throw std::invalid_argument("StrandField: no particles to carry the strands");
  if (rest_.size() == 0) throw std::invalid_argument("StrandField: no strands");
  if (rest_.first.size() != rest_.size() + 1 || rest_.first.back() != rest_.points.size())
    throw std::invalid_argument("StrandField: the strand list is inconsistent");
  for (std::size_t s = 0; s < rest_.size(); ++s)
    if (rest_.pointCount(s) < 2)
      throw std::invalid_argument("StrandField: strand " + std::to_string(s) + " has fewer than 2 points");
  checkFinite(rest_.points, "strand point");
  checkFinite(particles.position, "particle");

  particles_ = particles.size();
  rest_position_ = particles.position;
  rest_direction_ = particles.direction;
  const float h = options.support;
  const CellIndex cells(rest_position_, h);

  // Each particle's neighbourhood for its rotation: roots see roots only
  // (they move with the head, so their rotation is the head's).
  nb_first_.assign(particles_ + 1, 0);
  {
    std::vector<std::vector<Candidate>> lists(particles_);
    parallel::forEachDynamic(threads, particles_, [&](std::size_t i) {
      std::vector<Candidate>& c = lists[i];
      const bool root = particles.is_root[i] != 0;
      // at least a few neighbours, so that the rotation is determined
      for (float radius = kRotationRadius * h; c.size() < kMinRotationNeighbors && radius <= 8.0f * h; radius *= 2.0f) {
        c.clear();
        const float ih2 = 1.0f / (radius * radius);
        cells.forEachNear(rest_position_[i], radius, [&](std::uint32_t j) {
          if (root && !particles.is_root[j]) return;
          const glm::vec3 d = rest_position_[j] - rest_position_[i];
          const float w = smoothWeight(glm::dot(d, d), ih2);
          if (w > 0.0f) c.push_back({w, j});
        });
      }
      std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) {
        return a.weight != b.weight ? a.weight > b.weight : a.index < b.index;
      });
      if (c.size() > kMaxRotationNeighbors) c.resize(kMaxRotationNeighbors);
    });
    for (std::size_t i = 0; i < particles_; ++i) {
      nb_first_[i + 1] = nb_first_[i] + static_cast<std::uint32_t>(lists[i].size());
      for (const Candidate& c : lists[i]) {
        nb_index_.push_back(c.index);
        nb_weight_.push_back(c.weight);
      }
    }
  }

  // Each strand point's carriers: near it at rest and rooted near its root;
  // a root point is carried by root particles only, so it stays on the scalp.
  const std::size_t np = rest_.points.size();
  const std::size_t k = static_cast<std::size_t>(k_);
  bind_index_.assign(np * k, 0);
  bind_weight_.assign(np * k, 0.0f);
  detail_.assign(np, glm::vec3(0.0f));
  rest_length_.assign(np, 0.0f);
  bool any_root = false;
  for (std::size_t i = 0; i < particles_ && !any_root; ++i) any_root = particles.is_root[i] != 0;
  parallel::forEachDynamic(threads, rest_.size(), [&](std::size_t s) {
    std::vector<Candidate> c;
    const std::uint32_t b = rest_.first[s], e = rest_.first[s + 1];
    const glm::vec3 root = rest_.points[b];
    for (std::uint32_t pi = b; pi < e; ++pi) {
      const glm::vec3 r = rest_.points[pi];
      const bool roots_only = pi == b && any_root;
      bool ok = false;
      for (int round = 0; round < 8 && !ok; ++round) {
        // rounds: radius h, 2h, 4h, 8h with the root term, then without it
        const bool root_term = round < 4;
        const float radius = h * static_cast<float>(1 << (round % 4));
        const float ih2 = 1.0f / (radius * radius);
        c.clear();
        cells.forEachNear(r, radius, [&](std::uint32_t j) {
          if (roots_only && !particles.is_root[j]) return;
          const glm::vec3 d = rest_position_[j] - r;
          float w = smoothWeight(glm::dot(d, d), ih2);
          if (w > 0.0f && root_term) {
            const glm::vec3 dr = particles.root_point[j] - root;
            w *= smoothWeight(glm::dot(dr, dr), ih2);
          }
          if (w > 0.0f) c.push_back({w, j});
        });
        ok = pickWeights(c, k_, &bind_index_[pi * k], &bind_weight_[pi * k]);
      }
      if (!ok) {  // nothing within 8h: the nearest particle carries it
        std::uint32_t best = 0;
        float best_d = INFINITY;
        for (std::uint32_t j = 0; j < particles_; ++j) {
          if (roots_only && !particles.is_root[j]) continue;
          const glm::vec3 d = rest_position_[j] - r;
          const float dd = glm::dot(d, d);
          if (dd < best_d) best_d = dd, best = j;
        }
        for (std::size_t j = 0; j < k; ++j) {
          bind_index_[pi * k + j] = best;
          bind_weight_[pi * k + j] = j == 0 ? 1.0f : 0.0f;
        }
      }
      if (pi + 1 < e) rest_length_[pi] = glm::length(rest_.points[pi + 1] - r);
    }
    // the rest strand's own detail, which the smoothing would take away
    const std::size_t n = e - b;
    for (std::size_t j = 0; j < n; ++j)
      detail_[b + j] = rest_.points[b + j] - smoothAt(j, n, [&](std::size_t i) { return rest_.points[b + i]; });
  });
}

int StrandField::smoothingHalfWidth() { return kSmoothHalf; }
std::span<const float> StrandField::smoothingTaps() { return kSmoothTaps; }

void StrandField::particleMotions(std::span<const glm::vec3> x, std::span<const glm::vec3> t,
                                  std::vector<glm::mat3>& rot, std::vector<glm::vec3>& shift, int threads) const {
  if (x.size() != particles_ || t.size() != particles_)
    throw std::invalid_argument("StrandField::particleMotions: " + std::to_string(x.size()) + " positions and " +
                                std::to_string(t.size()) + " directions for " + std::to_string(particles_) +
                                " particles");
  rot.resize(particles_);
  shift.resize(particles_);
  parallel::forEach(threads, particles_, [&](std::size_t i) {
    const std::uint32_t b = nb_first_[i], e = nb_first_[i + 1];
    glm::vec3 c(0.0f), c0(0.0f);
    float wsum = 0.0f;
    for (std::uint32_t q = b; q < e; ++q) {
      const float w = nb_weight_[q];
      c += w * x[nb_index_[q]];
      c0 += w * rest_position_[nb_index_[q]];
      wsum += w;
    }
    glm::mat3 a(0.0f);
    if (wsum > 0.0f) {
      c /= wsum;
      c0 /= wsum;
      for (std::uint32_t q = b; q < e; ++q) {
        const float w = nb_weight_[q];
        const glm::vec3 d = x[nb_index_[q]] - c, d0 = rest_position_[nb_index_[q]] - c0;
        a += glm::outerProduct(w * d, d0);
      }
    }
    // The hair direction pins the rotation where the neighbourhood is thin
    // (nearly a line), with the weight of a neighbour half the support away.
    const float hd = options_.support * options_.support * 0.25f * std::max(wsum, 1e-6f);
    a += glm::outerProduct(hd * t[i], rest_direction_[i]);
    rot[i] = rotationPart(a, rest_direction_[i], t[i]);
    // the neighbourhood's rigid motion y -> R y + shift, which takes its
    // rest centroid to its centroid now (a particle alone: itself)
    if (!(wsum > 0.0f)) c = x[i], c0 = rest_position_[i];
    shift[i] = c - rot[i] * c0;
  });
}

// One deform call's work (StrandField::deform): the strands carried by the
// particles, then pushed out of the bodies and held near their rest
// lengths, a block of strands at a time.
class StrandField::Deformer {
 public:
  Deformer(const StrandField& f, std::span<const glm::vec3> x_in, const BodyContacts* bodies_in,
           const std::vector<float>& phi, std::vector<glm::vec3>& out_in)
      : rest_(f.rest_),
        bind_index_(f.bind_index_),
        bind_weight_(f.bind_weight_),
        detail_(f.detail_),
        rest_length_(f.rest_length_),
        k(static_cast<std::size_t>(f.k_)),
        tol(f.options_.length_tolerance),
        clearance(f.options_.clearance),
        x(x_in),
        bodies(bodies_in),
        particle_phi(phi),
        out(out_in) {}

  /// Strands [s0, s1): carried, then (with bodies) pushed out and held.
  void deformBlock(std::size_t s0, std::size_t s1, const std::vector<glm::mat3>& rot,
                   const std::vector<glm::vec3>& shift);

 private:
  // The points of strands [s0, s1) that may be nearer than `threshold` to a
  // body, strand roots excepted (they stay where their particles put them,
  // on the scalp): the distance is 1-Lipschitz, so phi(p) >= phi_k -
  // |p - x_k| for each carrier k, with phi_k a lower bound of its
  // particle's distance; the others need no query. (Pushing out by the
  // grid's error in the rough rounds, so that no exact query would be
  // needed, halved the time but bent strands where the grid's normals turn:
  // the 99th percentile of the bend went from 41 to 69 degrees on hang.json.)
  // (appended to `which`, in order)
  void selectNearStrand(std::size_t s, float threshold, std::vector<std::uint32_t>& which) const;
  void selectNear(std::size_t s0, std::size_t s1, float threshold, std::vector<std::uint32_t>& which) const;
  // A point deep in a thin part (an ear), pushed to the part's far side:
  // the segment from the point before it (`outside`, pushed already) enters
  // the body at c (bisection on the exact distance), and the point goes to
  // the clearance over the tangent plane there, so the strand lies along
  // the side it came from; where that is not outside either, to c itself.
  // `pushed` (the push to the nearest side) stands where the point before
  // is not outside (a root a rounding inside the scalp).
  glm::vec3 nearSidePush(const glm::vec3& outside, const glm::vec3& inside, const glm::vec3& pushed) const;
  // Queries the points `which` (`rough`: by the fast approximation) and
  // pushes those nearer than `trigger` out to the clearance; `which` keeps
  // the points it moved.
  void pushOut(bool rough, float trigger, std::vector<std::uint32_t>& which, std::vector<glm::vec3>& pts,
               std::vector<float>& phi, std::vector<glm::vec3>& nrm);
  // rebuilds strand s from its root with every segment as it is now but
  // held within the tolerance of its rest length: a stretched segment is
  // shortened along itself, a squeezed one lengthened and turned towards
  // the carried rest direction of the segment (`carried`, indexed from the
  // block's first point `b0`) the more it is squeezed, so a strand squeezed
  // by the particles lies out instead of folding. The segments are taken
  // as they are, not towards the old places of the points after them, so a
  // correction moves the rest of the strand with it (no zigzag).
  void limitLengths(std::size_t s, std::size_t b0, const std::vector<glm::vec3>& carried);
  // true if it moved any point
  bool trimTip(std::size_t s);
  /// Strands [s0, s1) carried by the particles, then smoothed along the
  /// strand with the rest strand's detail put back in the carried frame:
  /// p = S(p) + M d; `carried`: each rest segment's direction, turned.
  void carry(std::size_t s0, std::size_t s1, const std::vector<glm::mat3>& rot, const std::vector<glm::vec3>& shift,
             std::vector<glm::vec3>& carried);

  const StrandSet& rest_;
  const std::vector<std::uint32_t>& bind_index_;
  const std::vector<float>& bind_weight_;
  const std::vector<glm::vec3>& detail_;
  const std::vector<float>& rest_length_;
  const std::size_t k;
  const float tol, clearance;
  std::span<const glm::vec3> x;
  const BodyContacts* bodies;
  const std::vector<float>& particle_phi;
  std::vector<glm::vec3>& out;
};

void StrandField::Deformer::selectNearStrand(std::size_t s, float threshold, std::vector<std::uint32_t>& which) const {
  for (std::uint32_t q = rest_.first[s] + 1; q < rest_.first[s + 1]; ++q) {
    float bound = -INFINITY;
    for (std::size_t i = 0; i < k; ++i) {
      const std::uint32_t j = bind_index_[q * k + i];
      bound = std::max(bound, particle_phi[j] - glm::length(out[q] - x[j]));
    }
    if (bound < threshold) which.push_back(q);
  }
}

void StrandField::Deformer::selectNear(std::size_t s0, std::size_t s1, float threshold,
                                       std::vector<std::uint32_t>& which) const {
  which.clear();
  for (std::size_t s = s0; s < s1; ++s) selectNearStrand(s, threshold, which);
}

glm::vec3 StrandField::Deformer::nearSidePush(const glm::vec3& outside, const glm::vec3& inside,
                                              const glm::vec3& pushed) const {
  glm::vec3 lo = outside, hi = inside, at = outside;
  float f = 0.0f;
  glm::vec3 n(0.0f);
  auto ask = [&](const glm::vec3& point) {
    at = point;
    (*bodies)(std::span<const glm::vec3>(&at, 1), 1e-6f, false, std::span<float>(&f, 1), std::span<glm::vec3>(&n, 1));
  };
  ask(lo);
  if (!(f >= 0.0f)) return pushed;
  glm::vec3 n_lo = n;
  for (int it = 0; it < kEntryBisections; ++it) {
    ask(0.5f * (lo + hi));
    if (f >= 0.0f) {
      lo = at;
      n_lo = n;
    } else {
      hi = at;
    }
  }
  const float height = glm::dot(inside - lo, n_lo);
  const glm::vec3 over = inside + (clearance - height) * n_lo;
  ask(over);
  return f >= 0.0f ? over : lo + clearance * n_lo;
}

void StrandField::Deformer::pushOut(bool rough, float trigger, std::vector<std::uint32_t>& which,
                                    std::vector<glm::vec3>& pts, std::vector<float>& phi, std::vector<glm::vec3>& nrm) {
  if (which.empty()) return;
  pts.resize(which.size());
  for (std::size_t m = 0; m < which.size(); ++m) pts[m] = out[which[m]];
  phi.resize(which.size());
  nrm.resize(which.size());
  (*bodies)(pts, std::max(trigger, 1e-6f), rough, phi, nrm);
  std::size_t kept = 0;
  for (std::size_t m = 0; m < which.size(); ++m) {
    if (!(phi[m] < trigger)) continue;
    const std::uint32_t q = which[m];
    glm::vec3 pushed = out[q] + (clearance - phi[m]) * nrm[m];
    // A point deep in a thin part (an ear) is nearest to its far side:
    // pushed there, its segment would reach through the part, so it goes
    // over the side the strand came from instead.
    if (glm::length(pushed - out[q - 1]) > kThroughStretch * rest_length_[q - 1])
      pushed = nearSidePush(out[q - 1], out[q], pushed);
    out[q] = pushed;
    which[kept++] = q;
  }
  which.resize(kept);
}

void StrandField::Deformer::limitLengths(std::size_t s, std::size_t b0, const std::vector<glm::vec3>& carried) {
  const std::uint32_t b = rest_.first[s], e = rest_.first[s + 1];
  glm::vec3 prev_old = out[b];
  for (std::uint32_t q = b + 1; q < e; ++q) {
    const glm::vec3 cur_old = out[q];
    glm::vec3 d = cur_old - prev_old;
    prev_old = cur_old;
    const float len = glm::length(d), l0 = rest_length_[q - 1];
    const float hi = l0 * (1.0f + tol), lo = l0 * (1.0f - tol);
    if (len > hi) {
      d *= hi / len;
    } else if (len < lo) {
      // continuous: no turn at the limit itself
      glm::vec3 dir = d + (lo - len) * carried[q - 1 - b0];
      const float dl = glm::length(dir);
      d = (dl > 1e-7f * l0 ? dir / dl : carried[q - 1 - b0]) * lo;
    }
    out[q] = out[q - 1] + d;
  }
}

bool StrandField::Deformer::trimTip(std::size_t s) {
  const std::uint32_t b = rest_.first[s], e = rest_.first[s + 1];
  double len = 0, rest = 0;
  for (std::uint32_t q = b + 1; q < e; ++q) {
    len += glm::length(out[q] - out[q - 1]);
    rest += rest_length_[q - 1];
  }
  if (len < rest * (1.0 - tol)) {
    // squeezed (points pushed together onto a body): the tip goes on
    // along its last segment by what is missing
    const glm::vec3 d = out[e - 1] - out[e - 2];
    const float l = glm::length(d);
    if (!(l > 0.0f)) return false;
    out[e - 1] += d * static_cast<float>((rest * (1.0 - tol) - len) / static_cast<double>(l));
    return true;
  }
  double excess = len - rest * (1.0 + tol);
  if (!(excess > 0.0)) return false;
  bool moved = false;
  // shorten the segments from the tip back, each by at most half of it,
  // carrying every move on to the points after it
  for (std::uint32_t q = e - 1; q > b && excess > 0.0; --q) {
    const glm::vec3 d = out[q] - out[q - 1];
    const float l = glm::length(d);
    const float cut = static_cast<float>(std::min(excess, 0.5 * static_cast<double>(l)));
    if (!(l > 0.0f) || cut <= 0.0f) continue;
    const glm::vec3 move = -d * (cut / l);
    for (std::uint32_t r = q; r < e; ++r) out[r] += move;
    excess -= cut;
    moved = true;
  }
  return moved;
}

void StrandField::Deformer::carry(std::size_t s0, std::size_t s1, const std::vector<glm::mat3>& rot,
                                  const std::vector<glm::vec3>& shift, std::vector<glm::vec3>& carried) {
  const std::size_t b = rest_.first[s0];
  std::vector<glm::vec3> raw;
  std::vector<glm::mat3> frame;
  for (std::size_t s = s0; s < s1; ++s) {
    const std::size_t sb = rest_.first[s], n = rest_.first[s + 1] - sb;
    raw.resize(n);
    frame.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t q = sb + j;
      const std::uint32_t* idx = &bind_index_[q * k];
      const float* w = &bind_weight_[q * k];
      glm::vec3 c(0.0f);
      glm::mat3 m(0.0f);
      for (std::size_t i = 0; i < k; ++i) {
        c += w[i] * shift[idx[i]];
        m += w[i] * rot[idx[i]];
      }
      raw[j] = m * rest_.points[q] + c;
      frame[j] = m;
    }
    for (std::size_t j = 0; j < n; ++j) {
      out[sb + j] = smoothAt(j, n, [&](std::size_t i) { return raw[i]; }) + frame[j] * detail_[sb + j];
      // the rest segment's direction, turned as the particles turn
      if (j + 1 < n) {
        const glm::vec3 seg = frame[j] * (rest_.points[sb + j + 1] - rest_.points[sb + j]);
        const float sl = glm::length(seg);
        carried[sb + j - b] = sl > 0.0f ? seg / sl : glm::vec3(0.0f, -1.0f, 0.0f);
      }
    }
  }
}

void StrandField::Deformer::deformBlock(std::size_t s0, std::size_t s1, const std::vector<glm::mat3>& rot,
                                        const std::vector<glm::vec3>& shift) {
  const std::size_t b = rest_.first[s0], e = rest_.first[s1];
  std::vector<glm::vec3> carried(e - b);
  carry(s0, s1, rot, shift, carried);
  std::vector<float> phi;
  std::vector<glm::vec3> nrm, pts;
  std::vector<std::uint32_t> which;
  if (!bodies) {
    for (std::size_t s = s0; s < s1; ++s) limitLengths(s, b, carried);
    return;
  }
  // the push out of the bodies (by their fast approximation) and the
  // length limit, in turn; then exact pushes, so no point is left inside
  for (int round = 0; round < kRoughRounds; ++round) {
    selectNear(s0, s1, clearance, which);
    pushOut(true, clearance, which, pts, phi, nrm);
    for (std::size_t s = s0; s < s1; ++s) limitLengths(s, b, carried);
  }
  // last, exact pushes until no point is left inside: the points pushed
  // are queried again (one pushed out of a body into another, in a
  // crease, needs more than one)
  selectNear(s0, s1, 1e-6f, which);
  for (int round = 0; round < kFinalPushes && !which.empty(); ++round) pushOut(false, 0.0f, which, pts, phi, nrm);
  // Pushes around a convex body lengthen a strand, pushes together onto
  // it shorten one; beyond the tolerance this is mended at the tip end:
  // points move along their segments (a chord of a segment's length dips
  // less than the clearance into a head), and the points are checked once
  // more.
  // Only the points of strands trimmed and those the last push moved (and
  // did not check again) can be inside now: the others were found outside
  // and have not moved, so asking again would change nothing.
  std::vector<std::uint32_t> trimmed, merged;
  for (int round = 0; round < kTrimRounds; ++round) {
    trimmed.clear();
    for (std::size_t s = s0; s < s1; ++s)
      if (trimTip(s)) selectNearStrand(s, 1e-6f, trimmed);
    merged.clear();
    std::set_union(which.begin(), which.end(), trimmed.begin(), trimmed.end(), std::back_inserter(merged));
    which.swap(merged);
    for (int p = 0; p < kFinalPushes && !which.empty(); ++p) pushOut(false, 0.0f, which, pts, phi, nrm);
  }
}

void StrandField::deform(std::span<const glm::vec3> x, std::span<const glm::vec3> t, const BodyContacts* bodies,
                         std::vector<glm::vec3>& out, int threads) const {
  if (x.size() != particles_ || t.size() != particles_)
    throw std::invalid_argument("StrandField::deform: " + std::to_string(x.size()) + " positions and " +
                                std::to_string(t.size()) + " directions for " + std::to_string(particles_) +
                                " particles");
  std::vector<glm::mat3> rot;
  std::vector<glm::vec3> shift;
  particleMotions(x, t, rot, shift, threads);
  // lower bounds of the particles' distances to the bodies (exact nearer
  // than a few supports, where strand points may need them)
  std::vector<float> particle_phi;
  if (bodies) {
    particle_phi.resize(particles_);
    std::vector<glm::vec3> pn(particles_);
    constexpr std::size_t kChunk = 1024;
    const float reach = 4.0f * options_.support + options_.clearance;
    parallel::forEachDynamic(threads, (particles_ + kChunk - 1) / kChunk, [&](std::size_t c) {
      const std::size_t b = c * kChunk, n = std::min(kChunk, particles_ - b);
      (*bodies)(x.subspan(b, n), reach, false, std::span<float>(particle_phi.data() + b, n),
                std::span<glm::vec3>(pn.data() + b, n));
    });
  }
  out.resize(rest_.points.size());
  Deformer deformer(*this, x, bodies, particle_phi, out);
  constexpr std::size_t kStrandBlock = 256;
  const std::size_t blocks = (rest_.size() + kStrandBlock - 1) / kStrandBlock;
  parallel::forEachDynamic(threads, blocks, [&](std::size_t blk) {
    const std::size_t s0 = blk * kStrandBlock, s1 = std::min(rest_.size(), s0 + kStrandBlock);
    deformer.deformBlock(s0, s1, rot, shift);
  });
}

void StrandField::deform(const Solver& solver, std::vector<glm::vec3>& out, int threads) const {
  const BodyContacts bodies = solverBodyContacts(solver);
  deform(solver.particles().position, solver.particles().direction, &bodies, out, threads);
}

void StrandField::deformWorld(const Solver& solver, std::vector<glm::vec3>& out, int threads) const {
  deform(solver, out, threads);
  const HeadPose pose = solver.head().pose;
  const glm::mat3 r(pose.rotation);
  const glm::vec3 c(pose.center);
  parallel::forEach(threads, out.size(), [&](std::size_t q) { out[q] = r * out[q] + c; });
}

}  // namespace loosehair
