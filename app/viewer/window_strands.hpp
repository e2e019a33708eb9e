// The strands the viewer's window draws (issue 45): the carry thread's
// points, or, where the strands are carried by a compute shader, the
// carry done here, in the window's OpenGL context, from what the carry
// thread handed over (CarriedStrands::field and the frame's particles).
// Owns the render::GpuStrandCarry of the field bound now; a carry that
// fails (a body without a bounding box, ...) turns the carry thread back
// to the CPU.
#pragma once

#include "viewer/strand_carrier.hpp"

#include "loosehair/render/renderer.hpp"
#include "loosehair/render/strand_carry_gpu.hpp"

#include <cstdint>
#include <memory>

namespace loosehair::viewer {

class SimulationThread;

class WindowStrands {
 public:
  /// `input` (a frame's) with `strands` added. Carries them on the GPU
  /// when they were handed over for that and are new; `carry_ms` then
  /// receives the time it took (CPU side), else 0.
  /// Only every `stride`-th strand is carried where fewer are drawn
  /// (RenderSettings::strand_budget, render::strandBudgetStride).
  void add(const CarriedStrands& strands, SimulationThread& sim, render::FrameInput& input, double& carry_ms,
           std::size_t stride = 1);

 private:
  std::unique_ptr<render::GpuStrandCarry> carry_;
  std::shared_ptr<const StrandField> field_;  // the field carry_ was made for
  std::int64_t frame_ = -1;
  std::uint64_t generation_ = 0;
  std::size_t stride_ = 0;  // of the last carry
  bool failed_ = false;     // then on the CPU: strands handed over for the GPU are not drawn
};

}  // namespace loosehair::viewer
