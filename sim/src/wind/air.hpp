// The air particles of the wind (method.md §5). Positions and velocities are in
// the head frame like the hair's; the box they live in is fixed in the world.
// Every loop gathers into the particle it owns, and a hair-air pair's force
// is computed by the same expression from both sides, so the exchange is
// exactly equal and opposite and the result does not depend on threads.
#pragma once

#include "loosehair/head_motion.hpp"
#include "loosehair/wind.hpp"
#include "solver/kernel.hpp"
#include "solver/neighbor_grid.hpp"
#include "wind/wind_air.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace loosehair {

class AirSystem final : public WindAir {
 public:
  /// Signed distance to the bodies for world-frame points (m, < 0 inside).
  using WorldDistance = std::function<void(const glm::vec3* world, std::size_t n, float* phi)>;

  explicit AirSystem(const WindParams& params);

  /// Fills the box with air at rest density moving with the wind at time t.
  void fill(double t, const HeadKinematics& head, const WorldDistance& bodies);

  /// Wind speed upwind at time t (m/s), gusts included.
  float speedAt(double t) const;
  /// Largest speed the profile reaches (m/s).
  float maxSpeed() const;
  /// The air's own stable step (s): weakly compressible, 0.5 h_air /
  /// (c + max speed); projected, h_air / max speed (the air moves at most
  /// h_air a step relative to the head).
  double stableTimeStep() const override;
  float smoothingLength() const { return h_; }
  float particleMass() const { return mass_; }
  float restDensity() const { return rest_density_; }
  float soundSpeed() const { return sound_speed_; }

  /// Neighbours among the air, the density projection of a step `dt` long
  /// (with projection_iterations > 0), neighbours between hair and air,
  /// then air density.
  void findNeighbors(std::span<const glm::vec3> hair_x, float dt, int threads);
  /// Pressure (weakly compressible air only), viscosity and drag forces; the drag on the hair is added to
  /// `hair_force`. `dt` sets the drag limiter.
  void accumulateForces(std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                        std::span<const float> hair_m, std::span<const std::uint8_t> hair_root,
                        std::span<glm::vec3> hair_force, float dt, int threads);
  /// Symplectic Euler with the head-frame inertial forces (no gravity: air
  /// is neutrally buoyant); the inflow layer (within 2 h_air of the upwind
  /// face) moves with the wind speed at time t.
  void integrate(double t, float dt, const HeadKinematics& head, int threads);
  /// Head pose at the time of the positions (for the box faces).
  void setPose(const HeadPose& pose) { pose_ = pose; }
  /// Emits air through the upwind face for the time the step advanced and
  /// removes what left the box. `t` is the time at the end of the step.
  void emitAndRemove(double t, float dt, const HeadKinematics& head, const WorldDistance& bodies);

  // WindAir: the exchange is findNeighbors and accumulateForces, the move
  // integrate, the bodies' free-slip push and emitAndRemove, at every hair
  // step.
  AirModel model() const override { return AirModel::Particles; }
  const WindParams& params() const override { return p_; }
  void exchange(const HeadKinematics& head, std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                std::span<const float> hair_m, std::span<const std::uint8_t> hair_root, std::span<glm::vec3> hair_force,
                float dt, int threads) override;
  bool due(float) override { return true; }
  void move(double t, double t_end, float dt, const Bodies& bodies, int threads) override;
  /// The air particles.
  std::size_t count() const override { return x_.size(); }
  void worldState(const HeadKinematics& head, std::vector<glm::vec3>* x, std::vector<glm::vec3>* v) const override;
  void report(StepStats& stats) const override;
  std::size_t nonFinite() const override;
  void hashState(const std::function<void(const void* data, std::size_t bytes)>& mix) const override;

  std::vector<glm::vec3>& positions() { return x_; }
  std::vector<glm::vec3>& velocities() { return v_; }
  const std::vector<glm::vec3>& positions() const { return x_; }
  const std::vector<glm::vec3>& velocities() const { return v_; }
  std::span<const float> density() const override { return density_; }
  /// The drag force on the hair from the last accumulateForces (N); its sum
  /// is minus the sum of airDragForce.
  std::span<const glm::vec3> airDragForce() const { return drag_on_air_; }
  /// The whole force on each air particle from the last accumulateForces (N).
  std::span<const glm::vec3> airForce() const { return force_; }
  std::size_t hairAirPairs() const { return hair_list_.size(); }
  std::size_t emitted() const { return emitted_; }
  std::size_t removed() const { return removed_; }

  /// What a step carries to the next (snapshots).
  struct State {
    std::vector<glm::vec3> x, v;
    std::vector<float> density;
    double advance = 0;
    std::uint64_t layer_counter = 0;
    std::uint64_t emitted = 0, removed = 0;
  };
  State state() const { return {x_, v_, density_, advance_, layer_counter_, emitted_, removed_}; }
  void restore(State s) {
    x_ = std::move(s.x);
    v_ = std::move(s.v);
    density_ = std::move(s.density);
    advance_ = s.advance;
    layer_counter_ = s.layer_counter;
    emitted_ = static_cast<std::size_t>(s.emitted);
    removed_ = static_cast<std::size_t>(s.removed);
  }

 private:
  // findNeighbors' steps (air.cpp)
  void sortByCell(float support, int threads);
  void listHairAir(std::span<const glm::vec3> hair_x, float support, float support2, int threads);
  void emitLayer(float along, const HeadKinematics& head, const WorldDistance& bodies, float speed);

  WindParams p_;
  HeadPose pose_;
  glm::vec3 e_wind_{0, 0, -1}, e_up_{0, 1, 0}, e_side_{1, 0, 0};
  float h_ = 0, mass_ = 0, rest_density_ = 0, sound_speed_ = 0;
  double advance_ = 0;  // wind run since the last emitted layer (m)
  std::uint64_t layer_counter_ = 0;
  std::size_t emitted_ = 0, removed_ = 0;

  /// Density the air beyond a box face at distance d would add: rest
  /// density times the kernel mass beyond a plane, tabulated.
  float missingDensity(float d) const;
  /// SPH density of air particle a from the last neighbour lists and the
  /// faces' missing air.
  float densityAt(std::size_t a, const CubicKernel& k) const;
  /// The faces' missing air at air particle a (0 beyond a support).
  float faceDensity(std::size_t a) const;
  /// Air particle a in the box's frame: along the wind, up, across (m from
  /// the box centre).
  glm::vec3 inBox(std::size_t a) const;
  /// Air particle a is within `reach` of a face of the box.
  bool nearFace(std::size_t a, float reach) const;
  /// Moves the air towards rest density (air_projection.cpp).
  void projectDensity(float dt, int threads);
  void initProjection();
  /// eps of the projection as a fraction of the lattice's denominator.
  static constexpr float kProjectionRelax = 1.0f;
  float rest_denominator_ = 0;
  std::vector<float> lambda_, lambda_sum_;
  std::vector<glm::vec3> shift_, start_;
  std::vector<float> beyond_;  // kernel mass beyond a plane at d = 2h k / (n-1)

  std::vector<glm::vec3> x_, v_, force_, drag_on_air_;
  std::vector<float> density_, pressure_, air_limiter_;
  NeighborGrid grid_;
  // hair -> air neighbours and the transposed air -> hair lists
  std::vector<std::uint32_t> hair_start_, hair_list_, air_start_, air_list_;
  std::vector<std::uint32_t> air_pair_;  // air list entry -> its hair list entry
  std::vector<float> pair_w_;            // W(|x_i - x_a|, h_air) per hair list entry
  std::vector<float> hair_limiter_;      // drag limiters, see accumulateForces
  // air sorted by cell for the cross search: unique cell keys and ranges
  std::vector<std::uint64_t> cell_key_;
  std::vector<std::uint32_t> cell_begin_;
  // per-step scratch, kept to avoid allocating every step
  std::vector<std::uint32_t> sorted_index_, fill_;
  std::vector<std::uint64_t> key_, key_tmp_;
  std::vector<glm::vec3> x_tmp_, v_tmp_;
  std::vector<std::vector<std::uint32_t>> buffers_;
};

}  // namespace loosehair
