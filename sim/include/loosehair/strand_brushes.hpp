// Brushes over key strands (issue 44): what one dab of the styling mode's
// comb, length, puff and smooth brushes does to a key strand, given how
// much the brush touches each control point (the viewer weighs them by
// their distance from the brush on screen). Pure functions of their
// arguments, so a stroke replays exactly; the root never moves (it follows
// the wisp's region) and every moved point is kept out of the head and
// torso. The comb and the puff keep the strand's span lengths, as a comb
// through real hair bends it without stretching it.
#pragma once

#include "loosehair/head_model.hpp"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace loosehair {

enum class StrandBrush { Comb, Length, Puff, Smooth };

/// "comb", "length", "puff", "smooth"; throws StyleError otherwise.
StrandBrush parseStrandBrush(const std::string& name);
const char* strandBrushName(StrandBrush brush);

struct BrushDab {
  StrandBrush brush = StrandBrush::Comb;
  /// Per control point, how much the brush touches it (0..1; the root's is
  /// ignored): as many as the key strand has points.
  std::vector<float> weight;
  /// 0..1: the share of the full effect one dab has.
  float strength = 0.5f;
  /// Comb: per control point, where the brush moved over it (m; as many as
  /// the points).
  std::vector<glm::vec3> move;
  /// Length: the relative change of a fully touched strand's length per
  /// dab at strength 1 (+: grow at the tip, -: cut).
  float grow = 0.1f;
};

/// `key` after one dab (see the header comment): comb drags each point by
/// weight x strength x its move, more towards the tip (by its share of the
/// arc length from the root), then restores the span lengths from the root
/// out; length scales the strand from the root by 1 + grow x strength x
/// (the tip's weight), cut to at most two spans' worth of its length and
/// no shorter than 1 cm; puff lifts the points along the scalp normal at
/// the root, most near the root, by up to a fifth of the strand's length;
/// smooth moves each inner point towards the middle of its neighbours.
/// Throws StyleError for a weight or move list of the wrong size or a
/// value that is not finite. `clearance` as StyleEditor::keptOutside.
std::vector<glm::vec3> brushedKeyStrand(const std::vector<glm::vec3>& key, const BrushDab& dab, const HeadModel& head,
                                        glm::vec3 root_normal, float clearance);

/// `p` pushed out of the head and the torso to `clearance` (m) where it is
/// nearer (along the surfaces' normals, a few rounds for creases).
glm::vec3 keptOutsideHead(const HeadModel& head, glm::vec3 p, float clearance);

}  // namespace loosehair
