// The hair chain's stage of the step (hair_chain_stage.hpp).
#include "solver/hair_chain_stage.hpp"

#include "solver/hair_chain.hpp"
#include "solver/tether.hpp"

namespace loosehair {

void holdHairChains(const HairChain& chain, float tether_slack, std::span<const glm::vec3> root_point,
                    std::span<const float> arc_length, std::span<const glm::vec3> tie_point,
                    std::span<const float> tie_reach, std::vector<glm::vec3>& position,
                    std::vector<std::uint8_t>& moved) {
  const float scale = 1.0f + tether_slack;
  moved.assign(position.size(), 0);
  chain.project(position, arc_length, [&](std::size_t i, glm::vec3 y) {
    moved[i] = 1;
    y = tether::within(y, root_point[i], scale * arc_length[i]);
    if (!tie_reach.empty() && tie_reach[i] >= 0.0f) y = tether::within(y, tie_point[i], scale * tie_reach[i]);
    return y;
  });
}

}  // namespace loosehair
