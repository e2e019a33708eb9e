#include "viewer/window_strands.hpp"

#include "viewer/simulation_thread.hpp"

#include <chrono>
#include <cstdio>
#include <exception>

namespace loosehair::viewer {

void WindowStrands::add(const CarriedStrands& strands, SimulationThread& sim, render::FrameInput& input,
                        double& carry_ms, std::size_t stride) {
  carry_ms = 0.0;
  if (!strands.field) {  // carried on the CPU
    input.strand_points = strands.points;
    input.strand_points_each = strands.points_each;
    return;
  }
  input.strand_points_each = 0;  // none drawn unless carried below
  if (failed_) return;           // until the CPU's strands come
  try {
    if (field_ != strands.field) {
      carry_.reset();
      carry_ = std::make_unique<render::GpuStrandCarry>(*strands.field);
      field_ = strands.field;
      frame_ = -1;
    }
    if (strands.frame != frame_ || strands.generation != generation_ || stride != stride_) {
      const auto t0 = std::chrono::steady_clock::now();
      carry_->carry(strands.position, strands.direction, strands.bodies, strands.head_to_world, 1, stride);
      stride_ = stride;
      carry_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      frame_ = strands.frame;
      generation_ = strands.generation;
    }
    input.strand_buffer = carry_->buffer();
    input.strand_buffer_points = carry_->points();
    input.strand_mean_length = carry_->meanLength();
    input.strand_points_each = carry_->pointsPerStrand();
  } catch (const std::exception& x) {
    std::fprintf(stderr, "loosehair-view: %s; the strands are carried on the CPU instead\n", x.what());
    sim.setStrandsOnGpu(false);
    failed_ = true;
    carry_.reset();
    field_.reset();
  }
}

}  // namespace loosehair::viewer
