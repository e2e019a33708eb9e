// The fixed set of connections built once at initialisation (method.md §3.1).
// Stored per particle (CSR), each pair twice: once in each partner's list,
// with the quantities as seen from that particle, so that every force loop
// can gather for one particle without writing to another. A particle's list
// holds its root-side partners first, then its tip-side ones, each part in
// partner order, so loops over one side need no test per entry. (The
// solver's passes run over a copy in a 16-lane layout that keeps each
// list's order, sim/src/solver/connection_slices.hpp.)
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace loosehair {

struct ConnectionSet {
  std::vector<std::uint32_t> offset;      // entries of particle i: [offset[i], offset[i+1])
  std::vector<std::uint32_t> tip_offset;  // first tip-side entry of particle i
  std::vector<std::uint32_t> partner;     // j
  std::vector<float> rest_length;         // l_ij (m)
  std::vector<float> strength;            // c_ij = a_ij * l_ij (m)
  std::vector<float> cos_rest;            // cos(theta_ij), theta_ij = angle(t_i, x_ij) at rest
  std::vector<float> sin_rest;            // sin(theta_ij)
  std::vector<std::uint8_t> tip_side;     // 1: j in Nt(i) (towards the tip), 0: j in Nr(i)

  std::size_t particleCount() const { return offset.empty() ? 0 : offset.size() - 1; }
  std::size_t entryCount() const { return partner.size(); }
  std::size_t pairCount() const { return partner.size() / 2; }
  std::uint32_t begin(std::size_t i) const { return offset[i]; }
  std::uint32_t end(std::size_t i) const { return offset[i + 1]; }
  /// Entries [begin(i), tipBegin(i)) are root-side, [tipBegin(i), end(i)) tip-side.
  std::uint32_t tipBegin(std::size_t i) const { return tip_offset[i]; }
  std::uint32_t degree(std::size_t i) const { return offset[i + 1] - offset[i]; }
};

}  // namespace loosehair
