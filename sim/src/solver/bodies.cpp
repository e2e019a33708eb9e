// The bodies the hair meets (method.md §5): the head, the world bodies
// (torso, obstacles) placed in the head frame at a time, and the queries
// of their distance, normal and surface velocity.
#include "solver/solver_internal.hpp"

namespace loosehair {

void Solver::addWorldBody(std::shared_ptr<const Body> body, HeadTrajectory motion, double begin, double end,
                          bool obstacle) {
  if (!body) throw std::invalid_argument("addWorldBody: no body");
  if (std::isnan(begin) || std::isnan(end) || !(begin < end))
    throw std::invalid_argument("addWorldBody: the active time interval is empty");
  world_bodies_.push_back({std::move(body), std::move(motion), begin, end, obstacle});
}

void Solver::placeBodies(double t, std::vector<BodyFrame>& frames, HeadKinematics& head, bool include_obstacles) const {
  head = trajectory_.kinematics(t);
  frames.clear();
  for (const auto& wb : world_bodies_) {
    if (!(t >= wb.begin && t < wb.end)) continue;
    if (wb.obstacle && !include_obstacles) continue;
    const HeadKinematics o = wb.motion.kinematics(t);
    const glm::dmat3 ro_t = glm::transpose(o.pose.rotation);
    BodyFrame f;
    f.body = wb.body.get();
    f.m = glm::mat3(ro_t * head.pose.rotation);
    f.d = glm::vec3(ro_t * (head.pose.center - o.pose.center));
    f.ro = glm::mat3(o.pose.rotation);
    f.rh_t = glm::mat3(glm::transpose(head.pose.rotation));
    f.vo = glm::vec3(o.velocity);
    f.wo = glm::vec3(o.angular_velocity);
    frames.push_back(f);
  }
}

void Solver::prepareBodyHints(const std::vector<BodyFrame>& frames) const {
  const std::size_t n = particles_.size();
  auto want = [&](const Body* body) {
    for (auto& [b, hints] : body_hints_)
      if (b == body) {
        if (hints.size() != n) hints.assign(n, -1);
        return;
      }
    body_hints_.emplace_back(body, std::vector<std::int32_t>(n, -1));
  };
  want(head_.get());
  for (const BodyFrame& f : frames) want(f.body);
  // the hints of bodies not asked this step (an obstacle that ended) go:
  // hints change no answer, so one that comes back starts without
  std::erase_if(body_hints_, [&](const auto& entry) {
    if (entry.first == head_.get()) return false;
    for (const BodyFrame& f : frames)
      if (f.body == entry.first) return false;
    return true;
  });
}

std::int32_t* Solver::bodyHints(const Body* body) const {
  for (auto& [b, hints] : body_hints_)
    if (b == body && hints.size() == particles_.size()) return hints.data();
  return nullptr;
}

void Solver::queryBodies(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* x,
                         std::size_t n, float* phi, glm::vec3* normal, glm::vec3* surface_velocity, float limit,
                         bool rough, const std::uint32_t* index) const {
  // The exact queries of one body over the points, with the particles'
  // hints for it where there are any.
  std::int32_t hint[kBodyBlock];
  auto exact = [&](const Body& body, const glm::vec3* p, std::size_t count, std::size_t first, float* out_phi,
                   glm::vec3* out_normal) {
    std::int32_t* hints = index ? bodyHints(&body) : nullptr;
    if (!hints) {
      body.signedDistanceBelow(p, count, limit, out_phi, out_normal);
      return;
    }
    for (std::size_t b = 0; b < count; b += kBodyBlock) {
      const std::size_t len = std::min(kBodyBlock, count - b);
      for (std::size_t k = 0; k < len; ++k) hint[k] = hints[index[first + b + k]];
      body.signedDistanceBelowHinted(p + b, len, limit, out_phi + b, out_normal + b, hint);
      for (std::size_t k = 0; k < len; ++k) hints[index[first + b + k]] = hint[k];
    }
  };
  // Where every body answers phi >= limit, the nearest may be any of them:
  // the callers only look at the normal and the surface velocity below it.
  if (rough)
    head_->roughDistanceBelow(x, n, limit, phi, normal);
  else
    exact(*head_, x, n, 0, phi, normal);
  if (surface_velocity)
    for (std::size_t k = 0; k < n; ++k) surface_velocity[k] = glm::vec3(0.0f);
  if (frames.empty()) return;
  glm::vec3 q[kBodyBlock], nb[kBodyBlock];
  float pb[kBodyBlock];
  const glm::vec3 omega(head.angular_velocity);
  const glm::vec3 frame_vel(glm::transpose(head.pose.rotation) * head.velocity);
  for (std::size_t b = 0; b < n; b += kBodyBlock) {
    const std::size_t len = std::min(kBodyBlock, n - b);
    for (const BodyFrame& f : frames) {
      for (std::size_t k = 0; k < len; ++k) q[k] = f.m * x[b + k] + f.d;
      if (rough)
        f.body->roughDistanceBelow(q, len, limit, pb, nb);
      else
        exact(*f.body, q, len, b, pb, nb);
      for (std::size_t k = 0; k < len; ++k) {
        if (!(pb[k] < phi[b + k])) continue;
        phi[b + k] = pb[k];
        normal[b + k] = glm::transpose(f.m) * nb[k];
        if (surface_velocity) {
          const glm::vec3 vw = f.vo + f.ro * glm::cross(f.wo, q[k]);
          surface_velocity[b + k] = f.rh_t * vw - glm::cross(omega, x[b + k]) - frame_vel;
        }
      }
    }
  }
}

void Solver::bodyDistance(std::span<const glm::vec3> points, double t, std::vector<float>& phi,
                          bool include_obstacles) const {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(t, frames, head, include_obstacles);
  phi.resize(points.size());
  std::vector<glm::vec3> nrm(points.size());
  queryBodies(frames, head, points.data(), points.size(), phi.data(), nrm.data(), nullptr);
}

std::vector<BodyPlacement> Solver::bodyPlacements() const {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(time_, frames, head, true);
  std::vector<BodyPlacement> placed{{head_, glm::mat3(1.0f), glm::vec3(0.0f)}};
  for (const BodyFrame& f : frames)
    for (const WorldBody& wb : world_bodies_)
      if (wb.body.get() == f.body) {
        placed.push_back({wb.body, f.m, f.d});
        break;
      }
  return placed;
}

void Solver::bodyContacts(std::span<const glm::vec3> points, double t, float limit, std::span<float> phi,
                          std::span<glm::vec3> normal, bool rough) const {
  if (phi.size() < points.size() || normal.size() < points.size())
    throw std::invalid_argument("Solver::bodyContacts: output spans shorter than the points");
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(t, frames, head, true);
  queryBodies(frames, head, points.data(), points.size(), phi.data(), normal.data(), nullptr, limit, rough);
}

}  // namespace loosehair
