#include "solver/connection_builder.hpp"

#include "solver/kernel.hpp"
#include "solver/neighbor_grid.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>
#include <vector>

namespace loosehair {

float alignment(const glm::vec3& ti, const glm::vec3& tj, const glm::vec3& xij) {
  const float len = glm::length(xij);
  if (!(len > 0.0f)) return 0.0f;
  const glm::vec3 e = xij / len;
  const float cos_i = glm::dot(ti, e);   // cos(theta_ij): t_i against x_ij
  const float cos_j = -glm::dot(tj, e);  // cos(theta_ji): t_j against x_ji = -x_ij
  if (!(cos_i * cos_j < 0.0f)) return 0.0f;
  return std::abs(cos_i - cos_j) * 0.5f;
}

namespace {

struct Candidate {
  std::uint32_t i, j;  // i < j
  float length, strength, weight, cos_i, cos_j;
  bool j_on_tip_side_of_i;
  bool aligned;      // a_ij >= a0
  bool last_resort;  // a_ij = 0: only for a particle with no other root-side pair
};

constexpr float kLastResortAlignment = 0.05f;

}  // namespace

namespace {

// Every pair within the support (no root-root pair), with its eq. 5
// strength, kernel weight, rest angles and which side of i it lies on.
std::vector<Candidate> candidatePairs(std::span<const glm::vec3> x, std::span<const glm::vec3> t,
                                      std::span<const float> s, std::span<const std::uint8_t> is_root,
                                      const ConnectionOptions& opt, const CubicKernel& kernel) {
  const std::size_t n = x.size();
  NeighborGrid grid;
  grid.build(x, kernel.support(), opt.threads);

  std::vector<Candidate> cand;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j : grid.neighbors(i)) {
      if (j <= i || (is_root[i] && is_root[j])) continue;
      const glm::vec3 xij = x[j] - x[i];
      const float l = glm::length(xij);
      if (!(l > 0.0f)) continue;
      const float a = alignment(t[i], t[j], xij);
      Candidate c;
      c.last_resort = !(a > 0.0f);
      c.i = i;
      c.j = j;
      c.length = l;
      // eq. 5; a pair side by side (a = 0) is kept only as the last resort
      // of a particle with nothing else towards the root, with the weakest
      // strength a pair can have (the per-particle rescaling of §3.3 then
      // makes it as stiff as a whole neighbourhood would be)
      c.strength = (c.last_resort ? kLastResortAlignment : a) * l;
      c.weight = c.strength * kernel.W(l);
      c.cos_i = std::clamp(glm::dot(t[i], xij / l), -1.0f, 1.0f);
      c.cos_j = std::clamp(-glm::dot(t[j], xij / l), -1.0f, 1.0f);
      c.j_on_tip_side_of_i = s[j] > s[i] || (s[j] == s[i] && glm::dot(xij, t[i]) >= 0.0f);
      c.aligned = a >= opt.alignment_threshold;
      cand.push_back(c);
    }
  }

  return cand;
}

// Which candidates are kept: the aligned ones, thinned to about
// target_connections a particle (the weakest first, never a particle's
// strongest root-side or tip-side pair); a particle with nothing aligned
// towards the root keeps a fallback.
std::vector<std::uint8_t> keptPairs(const std::vector<Candidate>& cand, std::size_t n,
                                    std::span<const std::uint8_t> is_root, const ConnectionOptions& opt) {
  // Strongest root-side and tip-side candidate of every non-root particle,
  // among the aligned pairs and, as a fallback, among all pairs.
  auto stronger = [&](std::uint32_t a, std::uint32_t b) {  // candidate a beats b?
    if (cand[a].weight != cand[b].weight) return cand[a].weight > cand[b].weight;
    return a < b;
  };
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> best_root(n, kNone), best_tip(n, kNone), fallback_root(n, kNone);
  std::vector<std::uint32_t> degree(n, 0);
  auto improve = [&](std::uint32_t& best, std::uint32_t k) {
    if (best == kNone || stronger(k, best)) best = k;
  };
  std::vector<std::uint32_t> last_root(n, kNone);  // nearest root-side pair with a = 0
  for (std::uint32_t k = 0; k < cand.size(); ++k) {
    const Candidate& c = cand[k];
    const bool tip_of_i = c.j_on_tip_side_of_i;
    if (c.last_resort) {
      std::uint32_t& best = tip_of_i ? last_root[c.j] : last_root[c.i];
      if (best == kNone || c.length < cand[best].length) best = k;
      continue;
    }
    if (!c.aligned) {
      improve(tip_of_i ? fallback_root[c.j] : fallback_root[c.i], k);
      continue;
    }
    ++degree[c.i];
    ++degree[c.j];
    improve(tip_of_i ? best_tip[c.i] : best_root[c.i], k);
    improve(tip_of_i ? best_root[c.j] : best_tip[c.j], k);
  }
  std::vector<std::uint8_t> keep(cand.size(), 0), protect(cand.size(), 0);
  for (std::size_t k = 0; k < cand.size(); ++k) keep[k] = cand[k].aligned ? 1 : 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (is_root[i]) continue;
    if (best_root[i] != kNone) protect[best_root[i]] = 1;
    if (best_tip[i] != kNone) protect[best_tip[i]] = 1;
  }
  std::vector<std::uint32_t> by_weight;
  for (std::uint32_t k = 0; k < cand.size(); ++k)
    if (cand[k].aligned) by_weight.push_back(k);
  std::sort(by_weight.begin(), by_weight.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (cand[a].weight != cand[b].weight) return cand[a].weight < cand[b].weight;
    return a < b;  // candidates are generated in (i, j) order
  });
  const auto nn = static_cast<std::uint32_t>(std::max(1, opt.target_connections));
  for (std::uint32_t k : by_weight) {
    const Candidate& c = cand[k];
    if (protect[k] || degree[c.i] <= nn || degree[c.j] <= nn) continue;
    keep[k] = 0;
    --degree[c.i];
    --degree[c.j];
  }
  // A particle with no aligned neighbour towards the root would hang on
  // nothing: give it its strongest less-aligned root-side pair instead.
  // Failing that (its neighbours all lie beside it), its nearest root-side
  // pair: without one a particle hangs on its root tether alone.
  for (std::size_t i = 0; i < n; ++i) {
    if (is_root[i] || best_root[i] != kNone) continue;
    if (fallback_root[i] != kNone)
      keep[fallback_root[i]] = 1;
    else if (last_root[i] != kNone)
      keep[last_root[i]] = 1;
  }

  return keep;
}

// The kept pairs as each particle's list of entries, root side first, then
// by partner.
ConnectionSet assembleConnections(const std::vector<Candidate>& cand, const std::vector<std::uint8_t>& keep,
                                  std::size_t n) {
  ConnectionSet cs;
  cs.offset.assign(n + 1, 0);
  for (std::size_t k = 0; k < cand.size(); ++k)
    if (keep[k]) {
      ++cs.offset[cand[k].i + 1];
      ++cs.offset[cand[k].j + 1];
    }
  for (std::size_t i = 0; i < n; ++i) cs.offset[i + 1] += cs.offset[i];
  const std::size_t m = cs.offset[n];
  cs.partner.resize(m);
  cs.rest_length.resize(m);
  cs.strength.resize(m);
  cs.cos_rest.resize(m);
  cs.sin_rest.resize(m);
  cs.tip_side.resize(m);
  std::vector<std::uint32_t> fill(cs.offset.begin(), cs.offset.end() - 1);
  auto put = [&](std::uint32_t owner, std::uint32_t other, const Candidate& c, float cos_theta, bool tip) {
    const std::uint32_t e = fill[owner]++;
    cs.partner[e] = other;
    cs.rest_length[e] = c.length;
    cs.strength[e] = c.strength;
    cs.cos_rest[e] = cos_theta;
    cs.sin_rest[e] = restSine(cos_theta);
    cs.tip_side[e] = tip ? 1 : 0;
  };
  for (std::size_t k = 0; k < cand.size(); ++k) {
    if (!keep[k]) continue;
    const Candidate& c = cand[k];
    put(c.i, c.j, c, c.cos_i, c.j_on_tip_side_of_i);
  }
  for (std::size_t k = 0; k < cand.size(); ++k) {
    if (!keep[k]) continue;
    const Candidate& c = cand[k];
    put(c.j, c.i, c, c.cos_j, !c.j_on_tip_side_of_i);
  }
  // The two passes append i's lower partners after its higher ones: sort each
  // list, root side first, then by partner.
  cs.tip_offset.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = cs.offset[i], e = cs.offset[i + 1];
    std::vector<std::uint32_t> idx(e - b);
    std::iota(idx.begin(), idx.end(), b);
    std::sort(idx.begin(), idx.end(), [&](std::uint32_t p, std::uint32_t q) {
      if (cs.tip_side[p] != cs.tip_side[q]) return cs.tip_side[p] < cs.tip_side[q];
      return cs.partner[p] < cs.partner[q];
    });
    std::uint32_t tip_begin = e;
    for (std::size_t k = idx.size(); k-- > 0;)
      if (cs.tip_side[idx[k]]) tip_begin = b + static_cast<std::uint32_t>(k);
    cs.tip_offset[i] = tip_begin;
    auto permute = [&](auto& v) {
      std::vector<typename std::decay_t<decltype(v)>::value_type> tmp(e - b);
      for (std::size_t k = 0; k < idx.size(); ++k) tmp[k] = v[idx[k]];
      std::copy(tmp.begin(), tmp.end(), v.begin() + b);
    };
    permute(cs.partner);
    permute(cs.rest_length);
    permute(cs.strength);
    permute(cs.cos_rest);
    permute(cs.sin_rest);
    permute(cs.tip_side);
  }
  return cs;
}

}  // namespace

ConnectionSet buildConnections(std::span<const glm::vec3> x, std::span<const glm::vec3> t, std::span<const float> s,
                               std::span<const std::uint8_t> is_root, const ConnectionOptions& opt) {
  const CubicKernel kernel(opt.h1);
  const std::vector<Candidate> cand = candidatePairs(x, t, s, is_root, opt, kernel);
  const std::vector<std::uint8_t> keep = keptPairs(cand, x.size(), is_root, opt);
  return assembleConnections(cand, keep, x.size());
}

std::size_t countUnanchored(const ConnectionSet& c, std::span<const std::uint8_t> is_root) {
  const std::size_t n = is_root.size();
  std::vector<std::uint8_t> anchored(n, 0);
  std::queue<std::uint32_t> q;
  for (std::uint32_t i = 0; i < n; ++i)
    if (is_root[i]) {
      anchored[i] = 1;
      q.push(i);
    }
  // i is anchored if some j in Nr(i) is; equivalently walk from anchored j to
  // the partners on j's tip side.
  while (!q.empty()) {
    const std::uint32_t j = q.front();
    q.pop();
    for (std::uint32_t e = c.begin(j); e < c.end(j); ++e) {
      const std::uint32_t i = c.partner[e];
      if (c.tip_side[e] && !anchored[i]) {
        anchored[i] = 1;
        q.push(i);
      }
    }
  }
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += anchored[i] ? 0 : 1;
  return count;
}

}  // namespace loosehair
