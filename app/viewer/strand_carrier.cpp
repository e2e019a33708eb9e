#include "viewer/strand_carrier.hpp"

#include "loosehair/render_strands.hpp"

#include <chrono>
#include <exception>
#include <utility>

namespace loosehair::viewer {

StrandCarrier::StrandCarrier(int threads) : threads_(threads < 1 ? 1 : threads) {
  thread_ = std::thread([this] { loop(); });
}

StrandCarrier::~StrandCarrier() {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  done_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void StrandCarrier::submit(CarryJob job) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    pending_ = std::move(job);
  }
  wake_.notify_all();
}

std::shared_ptr<const CarriedStrands> StrandCarrier::latest() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return latest_;
}

bool StrandCarrier::waitFor(std::int64_t frame, std::uint64_t generation) const {
  std::unique_lock<std::mutex> lk(mutex_);
  auto there = [&] { return latest_ && latest_->generation == generation && latest_->frame >= frame; };
  done_.wait(lk, [&] { return stop_ || there() || (!pending_ && !busy_); });
  return there();
}

void StrandCarrier::setOnGpu(bool on) {
  std::lock_guard<std::mutex> lk(mutex_);
  on_gpu_ = on;
}

std::string StrandCarrier::takeError() {
  std::lock_guard<std::mutex> lk(mutex_);
  return std::exchange(error_, std::string());
}

void StrandCarrier::loop() {
  std::unique_lock<std::mutex> lk(mutex_);
  for (;;) {
    wake_.wait(lk, [&] { return stop_ || pending_.has_value(); });
    if (stop_) return;
    CarryJob job = std::move(*pending_);
    pending_.reset();
    busy_ = true;
    const bool on_gpu = on_gpu_;
    lk.unlock();
    std::shared_ptr<CarriedStrands> carried;
    std::string failure;
    const auto start = std::chrono::steady_clock::now();
    try {
      if (job.strands == 0) {
        field_.reset();
        bound_strands_ = 0;
      } else {
        if (!field_ || bound_strands_ != job.strands || bound_generation_ != job.generation) {
          // a new run or another count: bound again to the rest state
          field_.reset();
          RenderStrandOptions so;
          so.strands = job.strands;
          field_ =
              std::make_shared<const StrandField>(bindSceneStrands(*job.scene, *job.rest, *job.build, so, threads_));
          bound_strands_ = job.strands;
          bound_generation_ = job.generation;
        }
        carried = std::make_shared<CarriedStrands>();
        if (on_gpu) {
          carried->field = field_;
          carried->position = std::move(job.position);
          carried->direction = std::move(job.direction);
          carried->bodies = std::move(job.bodies);
          carried->head_to_world = job.head_to_world;
        } else {
          const BodyContacts bodies = placedBodyContacts(std::move(job.bodies));
          field_->deform(job.position, job.direction, &bodies, carried->points, threads_);
          const glm::mat3 rotation(job.head_to_world);
          const glm::vec3 centre(job.head_to_world[3]);
          for (glm::vec3& p : carried->points) p = rotation * p + centre;
        }
        carried->points_each = static_cast<int>(field_->rest().pointCount(0));
        carried->frame = job.frame;
        carried->generation = job.generation;
        carried->carry_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      }
    } catch (const std::exception& e) {
      failure = std::string("strands: ") + e.what();
      field_.reset();
      bound_strands_ = 0;
      carried.reset();
    }
    lk.lock();
    busy_ = false;
    if (!failure.empty()) error_ = failure;
    if (job.strands == 0 || !failure.empty())
      latest_.reset();
    else
      latest_ = std::move(carried);
    done_.notify_all();
  }
}

}  // namespace loosehair::viewer
