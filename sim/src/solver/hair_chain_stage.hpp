// The hair chain's stage of the step (hair_chain.hpp): no particle loose
// from the hair.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

class HairChain;

/// Each particle within reach of hair nearer its root and of its root (and
/// its tie), nearer the root first (`chain`). Reads `root_point`,
/// `arc_length` and the ties (`tie_point`, `tie_reach`: empty for none, a
/// reach < 0 for a particle without one); writes `position` and `moved`
/// (which particles it moved: their moves may stop a particle moving away
/// from the hair, never throw it back; body_contacts.cpp).
void holdHairChains(const HairChain& chain, float tether_slack, std::span<const glm::vec3> root_point,
                    std::span<const float> arc_length, std::span<const glm::vec3> tie_point,
                    std::span<const float> tie_reach, std::vector<glm::vec3>& position,
                    std::vector<std::uint8_t>& moved);

}  // namespace loosehair
