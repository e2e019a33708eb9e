// The wind's air as the solver sees it (method.md §5; wind_air.hpp): made
// from the wind's parameters, its bodies placed for it, and its queries.
#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- wind (method.md §5) -----------------------------------------------------------
void Solver::setWind(const WindParams& wind) {
  std::vector<BodyFrame> frames;
  HeadKinematics head;
  placeBodies(time_, frames, head);
  if (wind.model == AirModel::Grid) {
    auto grid = std::make_unique<AirGrid>(wind);
    air_bodies_key_.clear();
    airBodiesMoved(frames, head);
    grid->fill(time_, [&](const glm::vec3* w, std::size_t n, float* phi, glm::vec3* v) {
      worldBodySample(frames, head, w, n, phi, v, true);
    });
    air_ = std::move(grid);
    return;
  }
  auto air = std::make_unique<AirSystem>(wind);
  air->fill(time_, head,
            [&](const glm::vec3* w, std::size_t n, float* phi) { worldBodyDistance(frames, head, w, n, phi); });
  air_ = std::move(air);
}

bool Solver::airBodiesMoved(const std::vector<BodyFrame>& frames, const HeadKinematics& head) {
  // Everything the bodies' distances and velocities depend on, bit for bit
  // (the scratch keeps its capacity from step to step).
  std::vector<double>& key = air_bodies_scratch_;
  key.clear();
  auto put = [&key](const auto& v, int n) {
    for (int k = 0; k < n; ++k) key.push_back(static_cast<double>(glm::value_ptr(v)[k]));
  };
  put(head.pose.rotation, 9);
  put(head.pose.center, 3);
  put(head.velocity, 3);
  put(head.angular_velocity, 3);
  for (const BodyFrame& f : frames) {
    key.push_back(static_cast<double>(reinterpret_cast<std::uintptr_t>(f.body)));
    put(f.m, 9);
    put(f.d, 3);
    put(f.ro, 9);
    put(f.rh_t, 9);
    put(f.vo, 3);
    put(f.wo, 3);
  }
  const bool moved = key.size() != air_bodies_key_.size() ||
                     std::memcmp(key.data(), air_bodies_key_.data(), key.size() * sizeof(double)) != 0;
  std::swap(key, air_bodies_key_);
  return moved;
}

void Solver::worldBodySample(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* world,
                             std::size_t n, float* phi, glm::vec3* velocity, bool rough) const {
  const glm::dmat3 rt = glm::transpose(head.pose.rotation);
  const glm::vec3 omega(head.angular_velocity);
  const glm::mat3 rot(head.pose.rotation);
  const glm::vec3 frame_v(head.velocity);
  parallel::forEach(threads_, (n + kBodyBlock - 1) / kBodyBlock, [&](std::size_t bb) {
    const std::size_t b = bb * kBodyBlock, len = std::min(kBodyBlock, n - b);
    glm::vec3 local[kBodyBlock]{}, nrm[kBodyBlock], surface[kBodyBlock];
    for (std::size_t k = 0; k < len; ++k) local[k] = glm::vec3(rt * (glm::dvec3(world[b + k]) - head.pose.center));
    queryBodies(frames, head, local, len, phi + b, nrm, velocity ? surface : nullptr, INFINITY, rough);
    // the bodies' velocity relative to the head frame, made a world one
    if (velocity)
      for (std::size_t k = 0; k < len; ++k)
        velocity[b + k] = rot * (surface[k] + glm::cross(omega, local[k])) + frame_v;
  });
}

void Solver::worldBodyDistance(const std::vector<BodyFrame>& frames, const HeadKinematics& head, const glm::vec3* world,
                               std::size_t n, float* phi) const {
  worldBodySample(frames, head, world, n, phi, nullptr, false);
}

bool Solver::windOnGrid() const { return air_ && air_->model() == AirModel::Grid; }

std::size_t Solver::airCount() const { return air_ ? air_->count() : 0; }

void Solver::worldAirPositions(std::vector<glm::vec3>& out) const {
  out.clear();
  if (air_) air_->worldState(trajectory_.kinematics(time_), &out, nullptr);
}

void Solver::worldAirVelocities(std::vector<glm::vec3>& out) const {
  out.clear();
  if (air_) air_->worldState(trajectory_.kinematics(time_), nullptr, &out);
}

std::span<const float> Solver::airDensity() const { return air_ ? air_->density() : std::span<const float>(); }

double Solver::holdTimeStep() const {
  const double w = shape_ ? shape_->fastest() : 0.0;
  return w > 0.0 ? kMaxHoldPhasePerStep / w : INFINITY;
}

double Solver::airStableTimeStep() const { return air_ ? air_->stableTimeStep() : INFINITY; }

}  // namespace loosehair
