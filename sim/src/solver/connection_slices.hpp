// The connections of a ConnectionSet rearranged for the solver's connection
// passes (springs, strain limit, directions): sliced ELLPACK with 16 lanes.
//
// A slice holds 16 particles (lanes). Its rows are 16 entries wide: row r
// holds entry r of each lane's list (root-side entries first, then tip-side,
// as in the ConnectionSet), so a pass visits a slice row by row and lane p
// adds its terms in its list's order: each particle's sums are the same
// sequence of IEEE operations as a loop over its CSR list, and so are their
// bits, whatever the vector width. A slice has as many rows as its longest
// list; shorter lists are padded with entries that the passes mask out.
// Particles are sorted by degree within windows of consecutive particles
// (which are near each other in space: the scene orders them along a Morton
// curve), so a slice's lists have similar lengths and little padding.
//
// Per-entry data are columns of length rows * 16: loads are whole vectors,
// per-lane sums need no shuffles, and the only scattered reads are the
// partners' states (gatherRows3, gatherRecords).
#pragma once

#include "loosehair/connections.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loosehair {

struct ConnectionSlices {
  static constexpr std::size_t kLanes = 16;
  static constexpr std::uint32_t kPadding = 0xffffffffu;

  std::size_t particle_count = 0;
  /// Lane s * 16 + p is particle owner[...]; lanes past the last particle
  /// (only in the last slice) repeat a real particle and have degree 0.
  std::vector<std::uint32_t> owner;
  /// Rows of slice s: [row_begin[s], row_begin[s + 1]).
  std::vector<std::uint32_t> row_begin;
  /// Per lane, as floats for the lane masks: the list's length, and the
  /// number of its root-side entries (rows below it are root-side).
  std::vector<float> degree, root_degree;
  /// Per entry (row * 16 + lane): its index in the ConnectionSet, or
  /// kPadding; and the partner j (the owner itself for padding).
  std::vector<std::uint32_t> entry;
  std::vector<std::uint32_t> partner;

  std::size_t sliceCount() const { return row_begin.empty() ? 0 : row_begin.size() - 1; }
  std::size_t rowCount() const { return row_begin.empty() ? 0 : row_begin.back(); }
  std::size_t entryCount() const { return rowCount() * kLanes; }
  /// A per-entry column of the ConnectionSet in this layout, `pad` in the
  /// padding entries.
  template <class T>
  std::vector<T> arrange(const std::vector<T>& csr, T pad) const {
    std::vector<T> out(entry.size(), pad);
    for (std::size_t k = 0; k < entry.size(); ++k)
      if (entry[k] != kPadding) out[k] = csr[entry[k]];
    return out;
  }
};

/// Particles per sorting window of the solver's layout.
inline constexpr std::size_t kSliceWindow = 256;

/// Slices of `c`, sorting by degree within windows of `window` particles
/// (a multiple of 16).
ConnectionSlices sliceConnections(const ConnectionSet& c, std::size_t window = kSliceWindow);

// The partners' records are scattered over arrays larger than a core's
// caches once there are 100k particles, and which record comes next is in
// the index column, where the hardware cannot see it. So the gathers can
// prefetch the record kGatherAhead entries ahead while they copy one:
// `readable` entries of idx may be read (0: no prefetching, for arrays that
// stay cached, where it only costs), so that a pass whose next work item
// continues the same column finds that item's first records cached too.
inline constexpr std::size_t kGatherAhead = 256;

/// The partners' values of whole rows (count a multiple of 16), for 3-vectors
/// stored as xyz triples: ox/oy/oz[k] = a[idx[k]].
void gatherRows3(const float* a, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* ox,
                 float* oy, float* oz);
/// The same for records of 4 floats: o0..o3[k] = the 4 floats at
/// rec + 4 * idx[k], one 16-byte load each (one cache line per partner for
/// all four values).
void gatherRecords(const float* rec, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* o0,
                   float* o1, float* o2, float* o3);
/// Two adjacent records per index (8 floats at rec + 8 * idx[k]) into the
/// 8 columns out + c * column_stride, c = 0..7: both records of a partner
/// read from one 32-byte run, its index read once.
void gatherRecordPairs(const float* rec, const std::uint32_t* idx, std::size_t count, std::size_t readable, float* out,
                       std::size_t column_stride);

}  // namespace loosehair
