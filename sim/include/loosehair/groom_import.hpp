// Grooms made elsewhere as the initial state of a simulation (method.md §6.2
// import): polylines from a .hair, OBJ or PLY file become a style with one
// wisp a strand (no clustering: the groom's own strands are kept exactly,
// each a key strand with a single member of offset 0).
#pragma once

#include "loosehair/strand_files.hpp"
#include "loosehair/style.hpp"

#include <string>

namespace loosehair {

struct GroomImportOptions {
  /// Applied to the file's coordinates first (for example 0.01 for a groom
  /// in centimetres); must be finite and positive.
  float scale = 1.0f;
  /// Strands whose root lies farther than this from the scalp are left out
  /// (m). A groom with no root that close is refused.
  float max_root_distance = 0.02f;
  /// Each strand is resampled to at most this many control points, evenly
  /// along its arc length (2..256).
  int max_control_points = 32;
  std::string name = "imported";
};

struct GroomImportReport {
  std::size_t strands_read = 0;
  std::size_t strands_kept = 0;
  std::size_t skipped_far = 0;      // root too far from the scalp
  std::size_t skipped_short = 0;    // fewer than two distinct points
  std::size_t skipped_beyond = 0;   // a point beyond kMaxStyleCoordinate
  std::size_t reversed = 0;         // stored tip first: turned round
  float largest_root_distance = 0;  // of the kept strands (m)
};

/// The groom as a style on `head` (built from `head_desc`). A strand's root
/// is its first point, or its last when only that end is near the scalp;
/// the root moves onto the nearest scalp point and the rest of the strand
/// is pushed out of the head by 2 mm where it dips in. `source` names the
/// groom in messages. Throws StyleError naming the file and the strand.
Style importGroom(const Polylines& groom, const HeadDesc& head_desc, const HeadModel& head, const std::string& source,
                  const GroomImportOptions& options = {}, GroomImportReport* report = nullptr);

}  // namespace loosehair
