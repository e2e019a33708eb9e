// Poisson-disc sampling of the hair pillar {(u,v,s): -s_r <= s <= L(u,v)}
// with the world metric d^2 = |f^-1(u1,v1) - f^-1(u2,v2)|^2 + (s1 - s2)^2
// (method.md §6.1). Deterministic for a seed.
#pragma once

#include "init/scalp_surface.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace loosehair {

struct PillarSample {
  glm::vec2 uv;
  float s;          // arc length (m), negative in the root layer
  glm::vec3 point;  // f^-1(u, v)
};

struct PillarOptions {
  int target_count = 1000;
  std::uint64_t seed = 1;
  /// Depth of the root layer s_r as a multiple of the disc radius.
  float root_depth_scale = 1.0f;
  /// Candidates thrown per wanted sample.
  int candidates_per_sample = 12;
};

struct PillarResult {
  std::vector<PillarSample> samples;
  float radius = 0;      // the Poisson radius r_P reached (m)
  float root_depth = 0;  // s_r (m)
};

/// Dart throwing with a fixed candidate sequence; the radius is adjusted
/// (count ~ r^-3) until the count is within 1% of the target or the best of
/// a few rounds is kept. No two samples are closer than `radius`.
/// `length(uv)` is L(u, v) in metres (> 0), `max_length` its maximum.
PillarResult samplePillar(const ScalpSurface& scalp, const std::function<float(glm::vec2)>& length, float max_length,
                          const PillarOptions& options);

/// Greedy dart throwing with a given radius (one round of samplePillar).
std::vector<PillarSample> samplePillarWithRadius(const ScalpSurface& scalp,
                                                 const std::function<float(glm::vec2)>& length, float max_length,
                                                 float radius, float root_depth, std::uint64_t seed,
                                                 std::size_t candidates);

}  // namespace loosehair
