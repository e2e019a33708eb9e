// The strands drawn for a scene (issue "strands", method.md §7.5): thousands of
// thin strands, independent of the particle count, whose shape the
// particles carry (loosehair/strand_field.hpp). A styled scene draws its
// style's member strands (an imported groom: its own strands); a scene
// without a style draws one strand per scalp sample, hung by the same
// cantilever as its particles (method.md §6.1).
#pragma once

#include "loosehair/style.hpp"

#include <cstddef>
#include <cstdint>

namespace loosehair {

struct SceneDesc;
class HeadModel;

struct RenderStrandOptions {
  /// About this many strands (a style's member density is scaled to it;
  /// one-strand wisps, such as an imported groom's, are kept as they are).
  std::size_t strands = 20000;
  /// Points a strand, root included, evenly spaced in arc length (2..256).
  int points = 24;
  /// A scene without a style: the Poisson radius its particles were sampled
  /// with (BuildReport::poisson_radius), so that its strands hang as the
  /// particles' do; 0 estimates it from the particle count.
  float poisson_radius = 0.0f;
};

/// The rest strands of `scene` on its head `model` (head frame), each with
/// exactly options.points points, in a fixed order for the scene's seed,
/// grown on `threads` threads (the same strands for any count). Throws
/// SceneError (or StyleError) naming the scene and field, and
/// std::invalid_argument for options out of range.
StrandSet growRenderStrands(const SceneDesc& scene, const HeadModel& model, const RenderStrandOptions& options = {},
                            int threads = 1);

struct Particles;
class StrandField;
struct StrandFieldOptions;
struct BuildReport;
/// The render strands of `scene` bound to its particles' rest state `rest`
/// (Solver::particles() right after buildSolver(scene, &build); where the
/// scene settles, BuildReport::grown, the state before it), with a
/// binding radius of twice the mean particle spacing. Builds the scene's
/// head again. Throws as growRenderStrands.
StrandField bindSceneStrands(const SceneDesc& scene, const Particles& rest, const BuildReport& build,
                             RenderStrandOptions options = {}, int threads = 1);

/// `strands` resampled to `points` points each, evenly in arc length
/// (strands of zero length are dropped).
StrandSet resampleStrands(const StrandSet& strands, int points);

}  // namespace loosehair
