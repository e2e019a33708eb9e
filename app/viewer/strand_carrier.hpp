// The viewer's render strands, carried on a thread of their own (issue "the
// real picture at interactive rates"). The simulation hands over each
// finished frame's particles and placed bodies and goes on at once; this
// thread binds the strands to the rest state when they are first asked for
// and carries the newest frame it was given, dropping the ones it had no
// time for; the window draws the newest carried strands. So neither the
// simulation nor the window waits for the carry, and at most one frame's
// carry is ever pending.
#pragma once

#include "loosehair/particles.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/body.hpp"
#include "loosehair/strand_field.hpp"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace loosehair::viewer {

/// Strands carried for one simulated frame, in world coordinates.
struct CarriedStrands {
  std::vector<glm::vec3> points;
  int points_each = 0;
  std::int64_t frame = 0;        // the simulated frame they were carried for
  std::uint64_t generation = 0;  // the simulation's restart count then
  double carry_ms = 0;           // wall time of the carry
  // Carried on the GPU instead (StrandCarrier::setOnGpu): `points` is
  // empty and the window's context carries these with
  // render::GpuStrandCarry.
  std::shared_ptr<const StrandField> field;
  std::vector<glm::vec3> position, direction;  // head frame
  std::vector<BodyPlacement> bodies;
  glm::mat4 head_to_world{1.0f};
};

/// What the simulation hands over after a frame.
struct CarryJob {
  std::int64_t frame = 0;
  std::uint64_t generation = 0;
  std::size_t strands = 0;  // how many strands are wanted (0: none)
  // the scene as built, to bind to (shared: the same for every frame of a run)
  std::shared_ptr<const SceneDesc> scene;
  std::shared_ptr<const BuildReport> build;
  std::shared_ptr<const Particles> rest;
  std::vector<glm::vec3> position, direction;  // head frame
  std::vector<BodyPlacement> bodies;           // placed at the frame's time (Solver::bodyPlacements)
  glm::mat4 head_to_world{1.0f};               // render::headToWorld of the frame's head pose
};

class StrandCarrier {
 public:
  /// `threads`: the carry's worker threads.
  explicit StrandCarrier(int threads);
  ~StrandCarrier();
  StrandCarrier(const StrandCarrier&) = delete;
  StrandCarrier& operator=(const StrandCarrier&) = delete;

  /// The newest frame to carry; replaces one not yet started.
  void submit(CarryJob job);
  /// The newest carried strands (null before the first).
  std::shared_ptr<const CarriedStrands> latest() const;
  /// Waits until strands for frame `frame` (or later) of `generation` are
  /// carried, or until nothing that could bring them is pending. False then.
  bool waitFor(std::int64_t frame, std::uint64_t generation) const;
  /// Only binds, and hands the window what to carry on the GPU
  /// (CarriedStrands::field) instead of the points.
  void setOnGpu(bool on);
  /// The message of the last binding that failed ("" if none), and clears it.
  std::string takeError();

 private:
  void loop();

  int threads_;
  mutable std::mutex mutex_;
  mutable std::condition_variable wake_, done_;
  std::optional<CarryJob> pending_;
  bool busy_ = false, stop_ = false;
  std::shared_ptr<const CarriedStrands> latest_;
  std::string error_;
  // the carry thread's own
  std::shared_ptr<const StrandField> field_;
  bool on_gpu_ = false;  // under mutex_
  std::size_t bound_strands_ = 0;
  std::uint64_t bound_generation_ = ~std::uint64_t{0};
  std::thread thread_;
};

}  // namespace loosehair::viewer
