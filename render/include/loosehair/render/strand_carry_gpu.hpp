// The strands carried by the particles on the GPU (issue 45): the bindings
// of a StrandField uploaded once, each frame the particles' rigid motions
// (StrandField::particleMotions, on the CPU: a few thousand particles) and
// a compute shader (render/shaders/strand_carry.comp) that carries every
// strand, holds its lengths and pushes it out of the bodies, whose signed
// distances are sampled once onto grids (loosehair/distance_volume.hpp).
// The points stay on the GPU, where the strand pass draws them from
// (FrameInput::strand_buffer). Needs OpenGL 4.3 (compute shaders); Mesa's
// software OpenGL has it. The CPU carry (StrandField::deform) stays what
// exports and tests use; the two agree within the volumes' error
// (tests/test_strand_carry_gpu.cpp).
#pragma once

#include "loosehair/distance_volume.hpp"
#include "loosehair/body.hpp"
#include "loosehair/strand_field.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace loosehair::render {

/// Whether the current context (GL loaded) runs compute shaders; if not,
/// `why` (optional) says why.
bool gpuStrandCarrySupported(std::string* why = nullptr);

class GpuStrandCarry {
 public:
  /// At most this many bodies push the strands.
  static constexpr int kMaxBodies = 8;
  /// Uploads `field`'s bindings into the current context. The context and
  /// `field` must outlive this. Throws RenderError where compute shaders
  /// are missing or the points are more than a buffer texture holds.
  explicit GpuStrandCarry(const StrandField& field, const DistanceVolumeOptions& volumes = {});
  ~GpuStrandCarry();
  GpuStrandCarry(const GpuStrandCarry&) = delete;
  GpuStrandCarry& operator=(const GpuStrandCarry&) = delete;

  /// Carries the strands for particles at `positions` with hair
  /// `directions` (head frame, the field's particles), out of `bodies`
  /// (Solver::bodyPlacements: each body's distance volume is sampled the
  /// first time it comes, on `threads` threads), and places them in the
  /// world by `head_to_world`. Throws RenderError for a body without a
  /// bounding box or more than kMaxBodies bodies, std::invalid_argument for
  /// wrong sizes. With `stride` k > 1 only strands 0, k, 2k, ... are
  /// carried (the others keep their last points): enough for a picture
  /// that draws only those (RenderSettings::strand_budget).
  void carry(std::span<const glm::vec3> positions, std::span<const glm::vec3> directions,
             const std::vector<BodyPlacement>& bodies, const glm::mat4& head_to_world, int threads = 1,
             std::size_t stride = 1);

  /// The carried points (world), strand after strand: a GL buffer of
  /// points() RGBA32F texels (xyz; w unused).
  unsigned buffer() const;
  std::size_t points() const;
  /// Points a strand (the field's strands all have as many: the renderer
  /// draws only such), 0 where they differ.
  int pointsPerStrand() const;
  /// The strands' mean rest length (m).
  float meanLength() const;
  /// The carried points read back (for tests and comparison; slow).
  void readBack(std::vector<glm::vec3>& out) const;
  /// Blocks until the last carry has finished (for timing: carry only
  /// queues the work).
  void wait() const;
  /// Seconds spent sampling distance volumes so far.
  double volumeSeconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loosehair::render
