// Hair caught where its tether and a body disagree.
//
// A particle pushed out of a body is slid round it towards its root
// (tether::slideAlongSurface), which meets the tether wherever the body's
// surface leads there. Under the flat bottom of a bust, with the root above
// it, no slide along the bottom does: the straight line to the root runs
// through the body, the hair's own way goes round the edge, and the last
// push-out leaves the particle beyond its tether (2.95% of the hair's
// length, issue 43). Such a particle is put back along its hair: onto the
// segment from its nearest partner nearer the root (the hair chain's
// candidates, hair_chain.hpp) that is itself in place, as far along it as
// its tether reaches and where no body is. That partner lies where the hair
// really goes round the body, so the particle follows it there; it takes
// the partner's velocity, as hair drawn along does. Where no partner is in
// place (a strand's whole tip under a neck cut flat: 2.8% on the mannequin
// head, issue 45), the particle walks round the body instead, 5 mm steps
// along its surface towards the root, until its tether reaches, and stops.
//
// Serial and by arc length, so that a partner nearer the root has been put
// back first and the result does not depend on the threads. Caught
// particles are rare (none in most steps), each costs a few point queries.
#include "loosehair/solver.hpp"

#include "solver/hair_chain.hpp"
#include "solver/tether.hpp"

#include <algorithm>

namespace loosehair {

void Solver::freeTrappedHair(const std::vector<BodyFrame>& frames, const HeadKinematics& head) {
  trapped_list_.clear();
  for (std::uint32_t i = 0; i < trapped_.size(); ++i)
    if (trapped_[i]) trapped_list_.push_back(i);
  if (trapped_list_.empty()) return;
  auto& x = particles_.position;
  auto& v = particles_.velocity;
  const auto& rp = particles_.root_point;
  const auto& sarc = particles_.arc_length;
  std::stable_sort(trapped_list_.begin(), trapped_list_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return sarc[a] < sarc[b]; });
  const float reach_scale = 1.0f + params_.tether_slack;
  constexpr int kTries = 6;  // halving the way towards the partner
  constexpr int kWalkSteps = 32;
  constexpr float kWalkStep = 0.005f;  // m
  for (std::uint32_t i : trapped_list_) {
    const float reach = reach_scale * sarc[i];
    // the nearest partner nearer the root that is in place and within i's
    // tether itself
    std::uint32_t best = i;
    float best_d2 = INFINITY;
    for (std::uint32_t j : chain_->candidates(i)) {
      if (trapped_[j]) continue;
      const glm::vec3 dr = x[j] - rp[i];
      if (glm::dot(dr, dr) > reach * reach) continue;
      const glm::vec3 d = x[j] - x[i];
      const float d2 = glm::dot(d, d);
      if (d2 < best_d2) best_d2 = d2, best = j;
    }
    float t = best == i ? -1.0f : tether::farthestWithin(x[best], x[i], rp[i], reach);
    for (int k = 0; k < kTries && t > 0.0f; ++k, t *= 0.5f) {
      const glm::vec3 y = x[best] + t * (x[i] - x[best]);
      float phi = 0.0f;
      glm::vec3 normal;
      queryBodies(frames, head, &y, 1, &phi, &normal, nullptr);
      if (phi >= 0.0f) {
        x[i] = y;
        v[i] = v[best];
        trapped_[i] = 0;
        break;
      }
    }
    if (!trapped_[i]) continue;
    // No partner in place (the tip of a strand under a neck cut flat, say):
    // walked round the body towards the root, in steps along the surface
    // pushed out again, until its tether reaches; it comes to rest there.
    glm::vec3 y = x[i];
    for (int k = 0; k < kWalkSteps; ++k) {
      float phi = 0.0f;
      glm::vec3 normal;
      queryBodies(frames, head, &y, 1, &phi, &normal, nullptr);
      if (phi < 0.0f) y -= (phi - tether::kSkin) * normal;
      const glm::vec3 to_root = rp[i] - y;
      if (phi >= 0.0f && glm::dot(to_root, to_root) <= reach * reach) {
        x[i] = y;
        v[i] = glm::vec3(0.0f);
        trapped_[i] = 0;
        break;
      }
      const glm::vec3 e = to_root - glm::dot(to_root, normal) * normal;
      const float a = glm::length(e);
      if (!(a > 0.0f)) break;
      y += (std::min(a, kWalkStep) / a) * e;
    }
  }
}

}  // namespace loosehair
