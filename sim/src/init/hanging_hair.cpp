#include "init/hanging_hair.hpp"

#include "init/scalp_surface.hpp"
#include "loosehair/head_model.hpp"
#include "loosehair/scene.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <memory>
#include <vector>

namespace loosehair {

namespace {
constexpr float kMinLengthFraction = 0.02f;

// A body fixed in the world seen from the head frame at one head pose.
class PlacedBody final : public Body {
 public:
  PlacedBody(std::shared_ptr<const Body> body, const HeadPose& pose)
      : body_(std::move(body)), r_(pose.rotation), c_(pose.center) {}
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override {
    std::vector<glm::vec3> q(n);
    for (std::size_t k = 0; k < n; ++k) q[k] = r_ * p[k] + c_;
    body_->signedDistance(q.data(), n, phi, normal);
    const glm::mat3 rt = glm::transpose(r_);
    for (std::size_t k = 0; k < n; ++k) normal[k] = rt * normal[k];
  }

 private:
  std::shared_ptr<const Body> body_;
  glm::mat3 r_;
  glm::vec3 c_;
};

}  // namespace

HangingHair::HangingHair(const SceneDesc& scene, const HeadModel& model) : scene_(scene), model_(model) {
  const HairSpec& hair = scene.hair;
  if (!hair.length_map.empty()) {
    try {
      length_map_ = LengthMap(hair.length_map);
    } catch (const std::exception& e) {
      throw SceneError(scene.source + ": hair.length_map: " + e.what());
    }
  }
  max_length_ = hair.length * std::max(length_map_.maximum(), kMinLengthFraction);
  // What the initial strands must stay out of: the head and, placed where
  // the head is at the start, the torso.
  start_bodies_.add(model.head());
  if (model.torso()) start_bodies_.add(std::make_shared<PlacedBody>(model.torso(), scene.motion.pose(0.0)));
  const glm::dmat3 r0 = scene.motion.pose(0.0).rotation;
  gravity_dir_ = glm::vec3(glm::transpose(r0) * glm::dvec3(scene.sim.gravity));
  has_gravity_ = glm::length(gravity_dir_) > 0.0f;
  if (has_gravity_) gravity_dir_ = glm::normalize(gravity_dir_);
}

float HangingHair::length(glm::vec2 uv) const {
  return scene_.hair.length * std::max(length_map_(uv), kMinLengthFraction);
}

glm::vec3 HangingHair::rootDirection(glm::vec2 uv) const {
  const HairSpec& hair = scene_.hair;
  const glm::vec3 nrm = model_.scalp().normal(uv);
  glm::vec3 away = -hair.whorl - glm::dot(-hair.whorl, nrm) * nrm;
  const float away_len = glm::length(away);
  glm::vec3 root_dir = hair.w_n * nrm;
  if (away_len > 1e-6f) root_dir += hair.w_t * (away / away_len);
  return glm::length(root_dir) > 1e-6f ? glm::normalize(root_dir) : nrm;
}

CantileverStrand HangingHair::strand(glm::vec2 uv, int segments, float clearance, float needed) const {
  const glm::vec3 root_dir = rootDirection(uv);
  return CantileverStrand(model_.scalp().point(uv), root_dir, has_gravity_ ? gravity_dir_ : root_dir, length(uv),
                          scene_.hair.bending_stiffness, &start_bodies_, clearance, scene_.hair.layering, segments,
                          needed);
}

}  // namespace loosehair
