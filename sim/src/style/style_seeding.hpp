// Seeding the LCP particles from a style's member strands (method.md §6.2): a
// Poisson-disc sampling, in the world metric, of the volume the strands
// sweep, roots included (method.md §6.1).
#pragma once

#include "loosehair/style.hpp"

#include <cstdint>
#include <vector>

namespace loosehair {

struct StrandSample {
  glm::vec3 position;    // head frame (m)
  glm::vec3 direction;   // the strand's unit tangent there
  glm::vec2 uv;          // the strand root's (u, v)
  float s;               // arc length from the root (m); negative under the scalp
  glm::vec3 root;        // the strand's root point on the scalp
  std::uint32_t strand;  // which member strand
};

struct StrandSeeding {
  std::vector<StrandSample> samples;
  float radius = 0;      // Poisson radius reached (m)
  float root_depth = 0;  // s_r (m)
};

/// Dart throwing over the strands' pillars {(strand k, s): -s_r <= s <=
/// L_k}, candidates drawn in proportion to L_k + s_r from a fixed sequence
/// of the seed; a candidate is kept if no kept sample lies within the radius
/// (3-D distance of their positions). The radius is adjusted until the count
/// is within 2% of `target` (or the closest of a few rounds is kept). Root
/// samples (s < 0) lie at root + s t_0, t_0 the strand's first tangent.
StrandSeeding seedFromStrands(const StrandSet& strands, int target, std::uint64_t seed, float root_depth_scale = 1.0f);

}  // namespace loosehair
