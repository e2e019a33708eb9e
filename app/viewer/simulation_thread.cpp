#include "viewer/simulation_thread.hpp"

#include "loosehair/render/frame.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/snapshot.hpp"
#include "loosehair/strand_field.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <future>
#include <set>
#include <tuple>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace loosehair::viewer {
namespace {

double wallNow() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

SimulationThread::SimulationThread(const SceneDesc& scene, bool paused) : scene_(scene), paused_(paused) {
  solver_ = std::make_unique<Solver>(buildSolver(scene_, &build_));
  rest_ = std::make_shared<const Particles>(solver_->particles());
  built_scene_ = std::make_shared<const SceneDesc>(scene_);
  built_report_ = std::make_shared<const BuildReport>(build_);
  // one worker: the simulation has the other cores
  carrier_ = std::make_unique<StrandCarrier>(1);
  publish(0.0);
  pace_wall_ = wallNow();
  pace_sim_ = solver_->time();
  thread_ = std::thread([this] { loop(); });
}

SimulationThread::~SimulationThread() {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  published_.notify_all();
  if (thread_.joinable()) thread_.join();
  carrier_.reset();
}

std::shared_ptr<const CarriedStrands> SimulationThread::latestStrands() const {
  std::shared_ptr<const CarriedStrands> s = carrier_->latest();
  std::lock_guard<std::mutex> lk(mutex_);
  if (strand_count_ == 0 || !s || s->generation != generation_) return nullptr;
  return s;
}

bool SimulationThread::waitForStrands() const {
  std::int64_t frame = 0;
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (strand_count_ == 0) return false;
    frame = latest_->frame;
    generation = latest_->generation;
  }
  return carrier_->waitFor(frame, generation);
}

SceneDesc SimulationThread::scene() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return scene_;
}

BuildReport SimulationThread::buildReport() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return build_;
}

std::shared_ptr<const PublishedFrame> SimulationThread::latest() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return latest_;
}

void SimulationThread::setPaused(bool paused) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    paused_ = paused;
    pace_wall_ = wallNow();
    pace_sim_ = latest_->time;
  }
  wake_.notify_all();
  published_.notify_all();
}

bool SimulationThread::paused() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return paused_;
}

void SimulationThread::stepOnce() {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    paused_ = true;
    step_once_ = true;
  }
  wake_.notify_all();
}

void SimulationThread::runUntil(std::int64_t n) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    pause_at_ = n;
    paused_ = latest_->frame >= n;
    pace_wall_ = wallNow();
    pace_sim_ = latest_->time;
  }
  wake_.notify_all();
  published_.notify_all();
}

void SimulationThread::setSpeed(double factor) {
  if (!(factor == 0.0 || (factor >= 0.1 && factor <= 4.0)))
    throw std::invalid_argument("speed must be 0 (as fast as possible) or in [0.1, 4], got " + std::to_string(factor));
  {
    std::lock_guard<std::mutex> lk(mutex_);
    speed_ = factor;
    pace_wall_ = wallNow();
    pace_sim_ = latest_->time;
  }
  wake_.notify_all();
}

double SimulationThread::speed() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return speed_;
}

void SimulationThread::setHeadTarget(const HeadKeyframe& pose) {
  std::lock_guard<std::mutex> lk(mutex_);
  head_target_ = pose;
  head_script_ = nullptr;
}

void SimulationThread::setHeadScript(std::function<std::optional<HeadKeyframe>(double)> pose) {
  std::lock_guard<std::mutex> lk(mutex_);
  head_script_ = std::move(pose);
}

std::vector<HeadKeyframe> SimulationThread::headKeys() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return head_keys_;
}

void SimulationThread::apply(std::function<void(Solver&)> change) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    changes_.push_back(std::move(change));
  }
  wake_.notify_all();
}

void SimulationThread::restart(const SceneDesc& scene) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    restart_ = scene;
  }
  wake_.notify_all();
}

std::string SimulationThread::takeError() {
  std::lock_guard<std::mutex> lk(mutex_);
  std::string e;
  e.swap(error_);
  return e;
}

std::string SimulationThread::applyAndWait(std::function<void(Solver&)> change) {
  auto done = std::make_shared<std::promise<std::string>>();
  std::future<std::string> result = done->get_future();
  apply([change = std::move(change), done](Solver& s) {
    try {
      change(s);
      done->set_value("");
    } catch (const std::exception& e) {
      done->set_value(e.what());
    }
  });
  return result.get();
}

void SimulationThread::saveSnapshot(const std::string& path) {
  const std::string e = applyAndWait([path](Solver& s) { loosehair::saveSnapshot(s, path); });
  if (!e.empty()) {
    std::lock_guard<std::mutex> lk(mutex_);
    error_ = e;
  }
}

void SimulationThread::loadSnapshot(const std::string& path) {
  const std::string e = applyAndWait([this, path](Solver& s) {
    loosehair::loadSnapshot(s, path);  // throws before changing anything
    // on the simulation thread, between frames: frame_ and the head are its own
    frame_ = static_cast<std::int64_t>(std::llround(s.time() * scene_.frame_rate));
    s.setTrajectory(scene_.motion);
    std::lock_guard<std::mutex> lk(mutex_);
    live_head_.reset();
    head_target_.reset();
    head_script_ = nullptr;
    head_keys_.clear();
    rate_window_.clear();
  });
  if (!e.empty()) {
    std::lock_guard<std::mutex> lk(mutex_);
    error_ = e;
  }
}

void SimulationThread::setPublishGrid(bool on) {
  std::lock_guard<std::mutex> lk(mutex_);
  publish_grid_ = on;
}

void SimulationThread::setPublishAir(bool on) {
  std::lock_guard<std::mutex> lk(mutex_);
  publish_air_ = on;
}

void SimulationThread::setPublishStrands(std::size_t count) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    strand_count_ = count;
  }
  // shown at once, also while paused
  apply([](Solver&) {});
}

bool SimulationThread::waitForFrame(std::int64_t n) const {
  std::unique_lock<std::mutex> lk(mutex_);
  published_.wait(lk, [&] { return stop_ || latest_->frame >= n || (paused_ && !step_once_ && !restart_); });
  return latest_->frame >= n;
}

// Builds the scene asked for (the lock released meanwhile) and takes it
// in: a new generation, the head and frame count reset, its first frame
// published. Called and returns with `lk` locked; a scene that fails to
// build leaves its error and the running scene.
void SimulationThread::rebuild(std::unique_lock<std::mutex>& lk) {
  const SceneDesc next = std::move(*restart_);
  restart_.reset();
  lk.unlock();
  std::unique_ptr<Solver> solver;
  BuildReport report;
  std::string error;
  try {
    solver = std::make_unique<Solver>(buildSolver(next, &report));
  } catch (const std::exception& e) {
    error = e.what();
  }
  lk.lock();
  if (!solver) {
    error_ = error;
    published_.notify_all();
    return;
  }
  scene_ = next;
  build_ = report;
  solver_ = std::move(solver);
  rest_ = std::make_shared<const Particles>(solver_->particles());
  built_scene_ = std::make_shared<const SceneDesc>(scene_);
  built_report_ = std::make_shared<const BuildReport>(build_);
  ++generation_;
  live_head_.reset();
  head_target_.reset();
  head_script_ = nullptr;
  head_keys_.clear();
  frame_ = 0;
  rate_window_.clear();
  lk.unlock();
  publish(0.0);
  lk.lock();
  pace_wall_ = wallNow();
  pace_sim_ = solver_->time();
}

// The head moved by hand: the live trajectory, from the rest pose before
// the first input; without new input the last pose holds.
void SimulationThread::moveHead(const std::optional<HeadKeyframe>& target) {
  if (target) {
    if (!live_head_) {
      live_head_.emplace(scene_.frame_rate);
      for (std::int64_t n = 0; n < frame_; ++n) live_head_->beginFrame(n, HeadKeyframe{});
    }
    live_head_->beginFrame(frame_, *target);
    solver_->setTrajectory(live_head_->trajectory());
  } else if (live_head_) {
    live_head_->beginFrame(frame_, live_head_->latest());
    solver_->setTrajectory(live_head_->trajectory());
  }
}

// Pacing: never ahead of real time times the speed; time lost to a slow
// frame is not made up afterwards. Called with `lk` locked.
void SimulationThread::pace(std::unique_lock<std::mutex>& lk) {
  if (speed_ > 0.0) {
    const double due = pace_wall_ + (latest_->time - pace_sim_) / speed_;
    const double now = wallNow();
    if (due > now) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(due - now);
      wake_.wait_until(lk, until, [&] { return stop_ || restart_.has_value() || paused_ || step_once_; });
    } else {
      pace_wall_ = now;
      pace_sim_ = latest_->time;
    }
  }
}

void SimulationThread::loop() {
  std::unique_lock<std::mutex> lk(mutex_);
  for (;;) {
    wake_.wait(lk, [&] { return stop_ || restart_ || !changes_.empty() || !paused_ || step_once_; });
    if (stop_) return;
    if (restart_) {
      rebuild(lk);
      continue;
    }
    std::deque<std::function<void(Solver&)>> changes;
    changes.swap(changes_);
    const bool run = !paused_ || step_once_;
    step_once_ = false;
    std::optional<HeadKeyframe> target = head_target_;
    if (head_script_) {
      const double t = static_cast<double>(frame_) / scene_.frame_rate;
      if (std::optional<HeadKeyframe> p = head_script_(t)) {
        target = *p;
        head_target_ = *p;
      } else {
        head_script_ = nullptr;
      }
    }
    lk.unlock();
    for (auto& change : changes) {
      try {
        change(*solver_);
      } catch (const std::exception& e) {
        lk.lock();
        error_ = e.what();
        lk.unlock();
      }
    }
    if (!run) {  // a change while paused: show its effect
      publish(0.0);
      lk.lock();
      continue;
    }
    moveHead(target);
    const double t0 = wallNow();
    std::string failure;
    try {
      solver_->advance(build_.substeps);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    ++frame_;
    const double t1 = wallNow();
    publish(1e3 * (t1 - t0));
    lk.lock();
    if (live_head_) head_keys_ = live_head_->keys();
    if (pause_at_ && frame_ >= *pause_at_) {
      paused_ = true;
      pause_at_.reset();
      published_.notify_all();
    }
    if (!failure.empty()) {
      error_ = "the simulation stopped: " + failure;
      paused_ = true;
      published_.notify_all();
      continue;
    }
    pace(lk);
  }
}

void SimulationThread::publish(double frame_ms) {
  auto f = std::make_shared<PublishedFrame>();
  f->input = render::frameFromSolver(*solver_, build_.mean_neighbor_distance);
  f->frame = frame_;
  f->time = solver_->time();
  f->state_hash = solver_->stateHash();
  f->last_step = solver_->stats().last;
  f->frame_ms = frame_ms;
  f->particles = solver_->particles().size();
  f->connections = solver_->stats().active_connections;
  f->contacts = solver_->stats().body_contacts;
  f->neighbor_pairs = solver_->stats().neighbor_pairs;
  f->grid_cell = 2.0f * solver_->params().h2;
  f->shape_keeping = solver_->params().shape_keeping;
  f->params = solver_->params();
  f->wind = solver_->hasWind();
  bool grid = false, air = false;
  std::size_t strand_count = 0;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    grid = publish_grid_;
    air = publish_air_;
    strand_count = strand_count_;
    f->generation = generation_;
  }
  // the frame handed to the carrier, which carries it when it is free; a
  // binding that failed turns the strands off, and strands turned off are
  // handed over once, so that it lets its field go
  if (std::string failed = carrier_->takeError(); !failed.empty()) {
    std::lock_guard<std::mutex> lk(mutex_);
    error_ = failed;
    strand_count_ = strand_count = 0;
  }
  if (strand_count > 0 || handed_strands_ > 0) {
    CarryJob job;
    job.frame = frame_;
    job.generation = f->generation;
    job.strands = strand_count;
    if (strand_count > 0) {
      {
        std::lock_guard<std::mutex> lk(mutex_);
        job.scene = built_scene_;
        job.build = built_report_;
        job.rest = rest_;
      }
      job.position = solver_->particles().position;
      job.direction = solver_->particles().direction;
      job.bodies = solver_->bodyPlacements();
      job.head_to_world = render::headToWorld(solver_->head().pose);
    }
    carrier_->submit(std::move(job));
    handed_strands_ = strand_count;
  }
  if (air && f->wind) solver_->worldAirPositions(f->air);
  if (grid && f->grid_cell > 0) {
    std::set<std::tuple<int, int, int>> cells;                  // sorted: the same picture every time
    for (const glm::vec3& p : solver_->particles().position) {  // head frame, as the grid
      const glm::ivec3 c(glm::floor(p / f->grid_cell));
      cells.emplace(c.x, c.y, c.z);
      if (cells.size() >= 20000) break;
    }
    for (const auto& [x, y, z] : cells) f->neighbor_cells.push_back(glm::vec3(x, y, z) * f->grid_cell);
  }
  std::lock_guard<std::mutex> lk(mutex_);
  const double now = wallNow();
  rate_window_.emplace_back(now, f->time);
  while (rate_window_.size() > 2 && now - rate_window_.front().first > 1.0) rate_window_.pop_front();
  const double wall = rate_window_.back().first - rate_window_.front().first;
  f->real_time_factor = wall > 0 ? (rate_window_.back().second - rate_window_.front().second) / wall : 0.0;
  f->paused = paused_;
  latest_ = std::move(f);
  published_.notify_all();
}

}  // namespace loosehair::viewer
