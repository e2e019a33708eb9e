// The loose springs taken implicitly (issue "real time at scale";
// docs/design.md "Implicit springs"): one linearised backward-Euler step of
// the damped springs of method.md §3.2, solved for the velocity change by
// conjugate gradients preconditioned with each particle's 3x3 block.
//
// With w = alpha_ij k_ij of an active connection and n its unit direction,
// the spring force's derivative along the pair is -w n n^T (the transverse
// term, (1 - l/|x|) w (I - n n^T), is left out: it is indefinite under
// compression, and the hair's springs carry their load along the pair),
// and the damping's is -gamma w n n^T. Writing L for the graph Laplacian
// with those 3x3 blocks, the step
//
//   (M + (dt^2 + gamma dt) L) dv = dt f - dt^2 L v
//
// (f: every force of the step at the start, springs included) is stable
// for any dt, and its error in the spring modes it cannot resolve is
// damping, which the strain limit and the tethers back up. Roots do not
// move in the head frame: dv = 0 there, and their rows are left out.
//
// Results do not depend on the thread count: each particle's row is summed
// in its connection list's order (the slice layout's lanes), and the dot
// products are summed per sorting window of the layout (kSliceWindow
// particles, 16 slices), then over the windows in order, by every thread
// alike.
#pragma once

#include "solver/connection_slices.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

struct ImplicitSpringReport {
  int iterations = 0;     // conjugate-gradient iterations taken
  float residual = 0.0f;  // final preconditioned residual norm / initial
};

class ImplicitSprings {
 public:
  struct Input {
    const ConnectionSlices* layout = nullptr;
    const float* weight = nullptr;  // alpha_ij k_ij per slice entry (the spring pass's)
    /// The pair's unit direction n per slice entry, and per particle
    /// sum_j alpha_ij k_ij (n . (v_j - v_i)) n (the spring pass's: the
    /// solve gathers no partner).
    const float *unit_x = nullptr, *unit_y = nullptr, *unit_z = nullptr;
    const glm::vec3* pull = nullptr;
    const glm::vec3* force = nullptr;  // every force of the step
    const float* mass = nullptr;
    const std::uint8_t* is_root = nullptr;
    std::size_t particles = 0;
    float dt = 0, gamma = 0;  // step (s), spring damping (s)
    float tolerance = 1e-2f;  // on the preconditioned residual norm, relative to the right-hand side's
    int max_iterations = 50;
    /// The start of the iterations (the last step's dv: warm start), or
    /// null for zero; may be the dv passed to solve. Roots' entries are
    /// ignored.
    const glm::vec3* guess = nullptr;
  };

  /// The velocity change of every particle (0 for roots) into dv. The
  /// iterations stop when the preconditioned residual is `tolerance` times
  /// that of a zero guess (the right-hand side's), whatever the start.
  ImplicitSpringReport solve(const Input& in, int threads, std::vector<glm::vec3>& dv);

 private:
  struct Part {  // a thread's windows [wb, we) and their slices [sb, se)
    std::size_t wb, we, sb, se;
  };
  void setUp(const Input& in, const Part& part, float scale);
  void multiply(const Input& in, const Part& part, const std::vector<glm::vec3>& src);
  // per slice entry: (dt^2 + gamma dt) w, 0 for padding and for the
  // entries of roots
  std::vector<float> c_;
  std::vector<float> precond_;  // per particle: the 6 of the inverse 3x3 block
  std::vector<glm::vec3> r_, z_, p_, ap_;
  std::vector<double> pap_partial_, rz_partial_;  // per window
};

}  // namespace loosehair
