// Hair hung from the scalp of a scene without a style (method.md §6.1): the
// length over the scalp (hair.length times the length map), the root
// direction from the whorl, and the cantilever strand from any scalp point.
// Shared by the particles (scene.cpp) and the render strands
// (strands/render_strands.cpp), so both hang the same hair.
#pragma once

#include "init/cantilever.hpp"
#include "init/length_map.hpp"
#include "loosehair/body.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <limits>

namespace loosehair {

struct SceneDesc;
class HeadModel;

class HangingHair {
 public:
  /// Throws SceneError naming the scene's hair.length_map when it cannot be read.
  HangingHair(const SceneDesc& scene, const HeadModel& model);

  /// L(u, v) in metres (at least 2 % of hair.length), and its maximum.
  float length(glm::vec2 uv) const;
  float maxLength() const { return max_length_; }
  /// Unit root direction at uv: w_n n + w_t (direction away from the whorl).
  glm::vec3 rootDirection(glm::vec2 uv) const;
  /// The cantilever strand from the scalp point at uv, `segments` pieces,
  /// kept `clearance` (+ layering s) out of the head and the torso as
  /// placed at the start; grown only as far as s = `needed` is read
  /// (CantileverStrand). Safe to call from several threads at once.
  CantileverStrand strand(glm::vec2 uv, int segments, float clearance,
                          float needed = std::numeric_limits<float>::infinity()) const;

 private:
  const SceneDesc& scene_;
  const HeadModel& model_;
  LengthMap length_map_;
  float max_length_ = 0;
  glm::vec3 gravity_dir_{0.0f};
  bool has_gravity_ = false;
  UnionBody start_bodies_;
};

}  // namespace loosehair
