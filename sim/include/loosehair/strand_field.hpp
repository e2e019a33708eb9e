// Strands carried by the particle field (issue "strands", method.md §7.5).
//
// The particles are a deformation field of the hair volume: each render
// strand point is bound once, at the rest state, to the few particles near
// it whose strands root near its own, and follows them afterwards:
//
//   p = sum_k w_k (R_k r + y_k)
//
// with r the point's rest position and (R_k, y_k) the rigid motion that
// best carries particle k's neighbourhood from rest to now (shape matching
// with its hair direction: R_k the rotation part, y_k taking the rest
// centroid to the current one), which also smooths the particles' jitter. The
// weights are smooth in r and sum to one, so the strands bend smoothly and
// a rigid motion of all particles moves every point by the same motion.
// Then, along each strand from the root, segment lengths are kept within a
// tolerance of their rest lengths, and points are pushed out of the bodies.
// No GL here: the renderer and the exporters take the points.
#pragma once

#include "loosehair/body.hpp"
#include "loosehair/particles.hpp"
#include "loosehair/style.hpp"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace loosehair {

class Solver;

struct StrandFieldOptions {
  /// Binding radius (m): particles farther than this from a strand point at
  /// rest, or rooted farther than this from its root, do not carry it.
  /// Must be > 0 (typically twice the particle spacing); where no particle
  /// is in reach the radius is doubled, up to three times.
  float support = 0.02f;
  /// Particles carrying one point (1..8).
  int particles_per_point = 4;
  /// Segment lengths are kept within this fraction of their rest length.
  float length_tolerance = 0.01f;
  /// Points (roots excepted) are kept this far out of the bodies (m).
  float clearance = 5e-4f;
};

/// The head and the world bodies of `solver` at its current time, for
/// head-frame points.
BodyContacts solverBodyContacts(const Solver& solver);

class StrandField {
 public:
  /// Binds `rest` (every strand at least 2 points; head frame) to the rest
  /// state `particles`. Throws std::invalid_argument on empty input, bad
  /// options or non-finite points.
  StrandField(StrandSet rest, const Particles& particles, const StrandFieldOptions& options, int threads = 1);

  /// The strands for particles at `positions` with hair `directions` (same
  /// frame as the rest state, one per particle): `out` receives
  /// rest().points.size() points. `bodies` (may be null) keeps points out
  /// of the bodies. Same bits for any thread count. Throws
  /// std::invalid_argument on wrong sizes.
  void deform(std::span<const glm::vec3> positions, std::span<const glm::vec3> directions, const BodyContacts* bodies,
              std::vector<glm::vec3>& out, int threads = 1) const;
  /// The same for a solver's current state, head frame, out of its bodies.
  void deform(const Solver& solver, std::vector<glm::vec3>& out, int threads = 1) const;
  /// The same in world coordinates (the head frame placed by the head's
  /// pose now), for drawing and export.
  void deformWorld(const Solver& solver, std::vector<glm::vec3>& out, int threads = 1) const;

  /// Each particle's rigid motion now, the first stage of deform: the
  /// rotation R_k and shift y_k that carry its neighbourhood from rest to
  /// `positions` (one each per particle). For a carry elsewhere (the GPU:
  /// render/shaders/strand_carry.comp) from the bindings below.
  void particleMotions(std::span<const glm::vec3> positions, std::span<const glm::vec3> directions,
                       std::vector<glm::mat3>& rot, std::vector<glm::vec3>& shift, int threads = 1) const;
  /// Particles carrying each point (carriersPerPoint() a point: indices
  /// and weights, point after point).
  int carriersPerPoint() const { return k_; }
  std::span<const std::uint32_t> bindIndices() const { return bind_index_; }
  std::span<const float> bindWeights() const { return bind_weight_; }
  /// Each rest point less its rest strand smoothed (the detail the carried
  /// frame puts back after the smoothing along the strand, kSmoothTaps).
  std::span<const glm::vec3> restDetail() const { return detail_; }
  /// The smoothing along a strand: taps[0] at the point, taps[d] d points
  /// away, for d up to smoothingHalfWidth() (cut at the ends, renormalised,
  /// the root not moved).
  static int smoothingHalfWidth();
  static std::span<const float> smoothingTaps();

  const StrandSet& rest() const { return rest_; }
  std::size_t strandCount() const { return rest_.size(); }
  /// Rest length of segment j of the whole point list (from point j to j+1;
  /// 0 where j is a strand's last point).
  std::span<const float> restSegmentLengths() const { return rest_length_; }
  const StrandFieldOptions& options() const { return options_; }

 private:
  class Deformer;  // one deform call's work (strand_field.cpp)
  StrandSet rest_;
  StrandFieldOptions options_;
  int k_ = 4;
  std::size_t particles_ = 0;
  // per point: the particles carrying it (k_ each)
  std::vector<std::uint32_t> bind_index_;
  std::vector<float> bind_weight_;
  std::vector<glm::vec3> detail_;  // rest point minus its smoothed rest position
  std::vector<float> rest_length_;
  // per particle: rest position, rest direction, and its neighbourhood
  std::vector<glm::vec3> rest_position_, rest_direction_;
  std::vector<std::uint32_t> nb_first_, nb_index_;
  std::vector<float> nb_weight_;
};

}  // namespace loosehair
