// The per-step sums the solver keeps between passes and steps (solver.cpp;
// snapshots carry the part a step hands to the next, snapshot.cpp).
#pragma once

#include "loosehair/solver.hpp"

#include <glm/vec4.hpp>

#include <cstddef>
#include <vector>

namespace loosehair {

struct SpringScratch {
  std::vector<float> sum_root;     // sum over Nr(i) of l_ij k_ij (eqs. 12-13)
  std::vector<float> sum_tip;      // sum over Nt(i)
  std::vector<float> factor_root;  // a_r,i, eq. 12
  std::vector<float> factor_tip;   // a_t,i, eq. 13
  std::vector<float> weight;       // alpha_ij k_ij of this step (by the spring pass), sliced
  /// The pair's unit direction n = x_ij / |x_ij| (0 for |x_ij| = 0), sliced,
  /// and per particle sum_j alpha_ij k_ij (n . v_ij) n: by the spring pass,
  /// for the implicit solve's matrix and right-hand side.
  std::vector<float> unit_x, unit_y, unit_z;
  std::vector<glm::vec3> pull;
  std::vector<float> k;  // k_ij at the current positions: for the queries only
  /// What the spring pass reads of a partner, two 16-byte records per
  /// particle: (x, a_r) and (v, a_t); one cache line instead of three.
  /// Made by computeSpringFactors, with the factors.
  std::vector<glm::vec4> spring_records;
  std::size_t clamped = 0;         // side factors held at the clamp
  std::size_t active_entries = 0;  // entries with k > 0 (each pair twice)
  /// The sums belong to the current positions: the direction pass of a step
  /// computes them for the next one.
  bool sums_current = false;
};

}  // namespace loosehair
