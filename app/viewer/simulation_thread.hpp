// The viewer's simulation, on a thread of its own (issue: interactive
// viewer). It steps the solver a scene frame at a time with the scene's
// fixed step, paced to real time times a speed factor (or as fast as it
// can), and publishes each finished frame for the window to draw; the
// window never waits for it. Changes (pause, step, restart, parameters,
// the head moved by hand) are queued and applied between frames, each at a
// definite frame, so the same inputs at the same simulation times give the
// same bits: with no inputs, the state after N frames is the CLI's.
#pragma once

#include "loosehair/live_head.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/strand_field.hpp"
#include "viewer/strand_carrier.hpp"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace loosehair::viewer {

/// A finished frame, as the window draws and reports it.
struct PublishedFrame {
  render::FrameInput input;  // world coordinates
  std::int64_t frame = 0;    // frames simulated since the (re)start
  double time = 0;           // simulated time (s)
  std::uint64_t state_hash = 0;
  StageTimes last_step;         // timings of the frame's last step
  double frame_ms = 0;          // wall time the frame took to simulate
  double real_time_factor = 0;  // simulated / wall time over the last second
  std::size_t particles = 0, connections = 0, contacts = 0, neighbor_pairs = 0;
  bool paused = false;
  std::uint64_t generation = 0;  // counts restarts: a new scene may have a new head
  bool wind = false;             // the solver has wind
  std::vector<glm::vec3> air;    // its air particles (world), while their debug view is on
  float grid_cell = 0;
  float shape_keeping = 0;  // the running solver's strength (Hz)
  SimParams params;         // the running solver's parameters            // the neighbour grid's cell size, 2 h2 (m)
  std::vector<glm::vec3> neighbor_cells;  // lower corners of occupied grid cells (head frame), capped
};

class SimulationThread {
 public:
  /// Builds the scene's solver (on the calling thread: throws SceneError
  /// and the like for a bad scene) and starts the thread, paused or not.
  SimulationThread(const SceneDesc& scene, bool paused);
  ~SimulationThread();
  SimulationThread(const SimulationThread&) = delete;
  SimulationThread& operator=(const SimulationThread&) = delete;

  /// The newest finished frame (never null).
  std::shared_ptr<const PublishedFrame> latest() const;
  /// The scene that runs and what building it chose (copies: a restart on
  /// the simulation thread replaces them).
  SceneDesc scene() const;
  BuildReport buildReport() const;

  void setPaused(bool paused);
  bool paused() const;
  /// One frame, then paused.
  void stepOnce();
  /// Plays on and pauses when frame `n` is reached (for --frames and
  /// scripts: inputs then land on exact frames).
  void runUntil(std::int64_t n);
  /// Simulated seconds per wall second: 0.1 to 4, or 0 for as fast as it
  /// can. Throws std::invalid_argument otherwise.
  void setSpeed(double factor);
  double speed() const;

  /// The pose the head should have now (its keyframe time is ignored):
  /// from the next frame on, the head follows a LiveHead trajectory.
  void setHeadTarget(const HeadKeyframe& pose);
  /// A scripted motion of the hand-moved head (the shake and nod buttons):
  /// `pose(t)` at each frame's simulated time t, until it returns nothing;
  /// then the head holds the last pose. Replaces a drag target.
  void setHeadScript(std::function<std::optional<HeadKeyframe>(double)> pose);
  /// The live head's keys so far (empty while the scene's motion runs).
  std::vector<HeadKeyframe> headKeys() const;

  /// Runs `change` on the solver between frames (a parameter set live).
  void apply(std::function<void(Solver&)> change);
  /// A new scene (or the same one again): built on the simulation thread;
  /// a failure keeps the current simulation and is reported by lastError.
  void restart(const SceneDesc& scene);
  /// The message of the last restart that failed ("" when none did), and
  /// clears it.
  std::string takeError();
  /// Runs `change` between frames and waits for it; what it throws is
  /// returned as the message ("" when it succeeded).
  std::string applyAndWait(std::function<void(Solver&)> change);

  /// Writes a snapshot of the state (sim/include/loosehair/snapshot.hpp) at
  /// the next frame boundary; a failure is reported by takeError. Blocks
  /// until it is written (or failed).
  void saveSnapshot(const std::string& path);
  /// Goes on from a snapshot of this scene at the next frame boundary,
  /// bit-identically (the head returns to the scene's own motion). A bad
  /// or foreign file is reported by takeError and changes nothing.
  void loadSnapshot(const std::string& path);
  /// Publishes the occupied neighbour-grid cells, and the air particles,
  /// with each frame (debug views; copied only while asked for).
  void setPublishGrid(bool on);
  void setPublishAir(bool on);
  /// Carries about `count` render strands with the particles: each frame
  /// is handed to a StrandCarrier, which binds them to the scene's rest
  /// state the first time (a second or two) and carries the newest frame
  /// on its own thread; latestStrands() has the newest. 0 stops them.
  void setPublishStrands(std::size_t count);
  /// The strands are carried on the GPU by the window (the carrier only
  /// binds them: CarriedStrands::field), or on the carrier's thread.
  void setStrandsOnGpu(bool on) { carrier_->setOnGpu(on); }
  /// The newest carried strands (null when none are asked for or carried
  /// yet); they may be a few frames behind latest().
  std::shared_ptr<const CarriedStrands> latestStrands() const;
  /// Waits until the strands of the newest published frame are carried
  /// (for scripts and --frames: the picture of an exact frame). False if
  /// strands are off or their binding failed.
  bool waitForStrands() const;

  /// Waits until frame `n` has been published (for scripts and tests).
  /// False if the thread stopped or it is paused before reaching it.
  bool waitForFrame(std::int64_t n) const;

 private:
  // loop()'s steps (simulation_thread.cpp)
  void rebuild(std::unique_lock<std::mutex>& lk);
  void moveHead(const std::optional<HeadKeyframe>& target);
  void pace(std::unique_lock<std::mutex>& lk);
  void loop();
  void simulateFrame();
  void publish(double frame_ms);

  SceneDesc scene_;
  BuildReport build_;
  std::unique_ptr<Solver> solver_;  // the simulation thread's only
  // the scene as built, for the carrier to bind strands to
  std::shared_ptr<const SceneDesc> built_scene_;
  std::shared_ptr<const BuildReport> built_report_;
  std::shared_ptr<const Particles> rest_;
  std::size_t strand_count_ = 0;
  std::size_t handed_strands_ = 0;  // the count last handed to the carrier (simulation thread's)
  std::unique_ptr<StrandCarrier> carrier_;
  std::optional<LiveHead> live_head_;
  std::int64_t frame_ = 0;

  mutable std::mutex mutex_;
  mutable std::condition_variable wake_, published_;
  bool stop_ = false, paused_ = false, step_once_ = false, publish_grid_ = false, publish_air_ = false;
  std::uint64_t generation_ = 0;
  std::optional<std::int64_t> pause_at_;
  double speed_ = 1.0;
  std::optional<HeadKeyframe> head_target_;
  std::function<std::optional<HeadKeyframe>(double)> head_script_;
  std::deque<std::function<void(Solver&)>> changes_;
  std::optional<SceneDesc> restart_;
  std::string error_;
  std::vector<HeadKeyframe> head_keys_;
  std::shared_ptr<const PublishedFrame> latest_;
  // pacing: wall clock and simulated time at the last change of speed or pause
  double pace_wall_ = 0, pace_sim_ = 0;
  std::deque<std::pair<double, double>> rate_window_;  // (wall, sim) of recent frames
  std::thread thread_;
};

}  // namespace loosehair::viewer
