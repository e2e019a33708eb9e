// The hair chain's stage of the step (hair_chain.hpp).
#include "solver/solver_internal.hpp"

namespace loosehair {

// The hair chain (sim/src/solver/hair_chain.hpp) with the tethers: each particle
// within reach of hair nearer its root and of its root (and tie), nearer
// the root first. Its moves may stop a particle moving away from the hair,
// never throw it back (`moved`, projectOutOfBodies).
void Solver::holdHairChains(std::vector<std::uint8_t>& moved) {
  const auto& rp = particles_.root_point;
  const auto& sarc = particles_.arc_length;
  const float scale = 1.0f + params_.tether_slack;
  moved.assign(particles_.size(), 0);
  chain_->project(particles_.position, sarc, [&](std::size_t i, glm::vec3 y) {
    moved[i] = 1;
    y = tether::within(y, rp[i], scale * sarc[i]);
    if (!tie_reach_.empty() && tie_reach_[i] >= 0.0f) y = tether::within(y, tie_point_[i], scale * tie_reach_[i]);
    return y;
  });
}

}  // namespace loosehair
