// The wind's air, whichever model carries it (method.md §5; docs/design.md
// "Air on a grid"): the paper's SPH air particles (air.hpp, AirSystem) or a
// velocity field on a grid (air_grid.hpp, AirGrid). Once it has built one,
// the solver talks to the air through this interface only: the hair-air
// drag before the hair's step, the air's own motion after it, and what the
// queries, statistics and state hash read (snapshots, which hold each
// model's own state, tell the two apart).
#pragma once

#include "loosehair/head_motion.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/wind.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace loosehair {

class WindAir {
 public:
  /// The bodies as the air asks for them when it moves, placed at the end
  /// of the hair's step (the solver implements it for each step, without
  /// allocating).
  class Bodies {
   public:
    HeadKinematics start, end;  // the head at the hair step's start and end
    /// Whether the bodies are placed otherwise than at the air's last move.
    bool moved = true;
    /// Grid signed distances (m, < 0 inside), outward normals and the
    /// bodies' velocities (head frame) at head-frame points.
    virtual void local(const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal, glm::vec3* velocity) const = 0;
    /// Grid signed distances and world velocities of the bodies at world
    /// points.
    virtual void worldSample(const glm::vec3* world, std::size_t n, float* phi, glm::vec3* velocity) const = 0;
    /// Exact signed distances at world points.
    virtual void worldDistance(const glm::vec3* world, std::size_t n, float* phi) const = 0;

   protected:
    ~Bodies() = default;
  };

  virtual ~WindAir() = default;
  virtual AirModel model() const = 0;
  /// The wind it was built from (a snapshot's scene fingerprint holds it).
  virtual const WindParams& params() const = 0;

  /// The hair-air drag of a hair step `dt` from the state at its start (the
  /// head at `head`): adds the force on each non-root hair particle to
  /// `hair_force` (head frame) and gives the air the opposite.
  virtual void exchange(const HeadKinematics& head, std::span<const glm::vec3> hair_x,
                        std::span<const glm::vec3> hair_v, std::span<const float> hair_m,
                        std::span<const std::uint8_t> hair_root, std::span<glm::vec3> hair_force, float dt,
                        int threads) = 0;
  /// Counts a hair step of `dt`; true when move() is due after it.
  virtual bool due(float dt) = 0;
  /// Moves the air to the end `t_end` of the hair step [t, t_end] (`dt`
  /// long).
  virtual void move(double t, double t_end, float dt, const Bodies& bodies, int threads) = 0;

  /// Air particles, or the grid's open cells.
  virtual std::size_t count() const = 0;
  /// Their world positions and velocities (either may be null), the head
  /// at `head`.
  virtual void worldState(const HeadKinematics& head, std::vector<glm::vec3>* x, std::vector<glm::vec3>* v) const = 0;
  /// Their densities (kg/m^3).
  virtual std::span<const float> density() const = 0;
  /// The longest hair step the air allows (s); infinity when it keeps its
  /// own pace.
  virtual double stableTimeStep() const = 0;
  /// Sets the air's counts of the last step in `stats`.
  virtual void report(StepStats& stats) const = 0;
  /// How many of the air's numbers (velocities, positions, pressures) are
  /// not finite: the solver's instability check covers the air too.
  virtual std::size_t nonFinite() const = 0;
  /// Feeds the state a step carries to the next to `mix` (the state hash).
  virtual void hashState(const std::function<void(const void* data, std::size_t bytes)>& mix) const = 0;
};

}  // namespace loosehair
