// Wisp-based hairstyles (method.md §6.2, Zhang & Wünsche 2007): a style is a
// head, a hair colour hint and a list of wisps; each wisp grows member
// strands over a region of the scalp that copy its key strand. Ties gather
// the wisps that pass through them (a ponytail, a bun). Style files are
// JSON, documented in data/styles/README.md.
//
//   Style style = loadStyle("data/styles/bob.json");
//   HeadModel head = HeadModel::build(style.head, style.source);
//   checkStyle(style, head);                     // throws StyleError
//   StrandSet strands = buildMemberStrands(style, head);
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/scene.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace loosehair {

/// A style file or edit that cannot be used. what() names the file, the
/// field and the value, e.g. "bob.json: wisps[2].key_strand[3]: lies 4.1 mm
/// inside the head".
class StyleError : public SceneError {
 public:
  using SceneError::SceneError;
};

/// What a style file's control points may be: within this distance of the
/// head frame's origin (m), and each this far at least from the one before.
inline constexpr float kMaxStyleCoordinate = 100.0f;
inline constexpr float kMinControlPointGap = 1e-5f;

/// Where a wisp's strands grow. A point of the scalp square is in the region
/// if it lies in one of the listed scalp triangles or inside one of the
/// polygons in (u, v) (even-odd rule per polygon). Both may be given; a
/// region must not be empty. Triangle indices refer to the scalp of the
/// style's own head (HeadModel::scalpTriangles); polygons work on any head.
struct WispRegion {
  std::vector<std::uint32_t> triangles;          // sorted, unique
  std::vector<std::vector<glm::vec2>> polygons;  // each at least 3 points in [0,1]^2
  bool empty() const { return triangles.empty() && polygons.empty(); }
  bool operator==(const WispRegion&) const = default;
};

/// How member strands vary around the key strand (Zhang & Wünsche §3.2).
struct WispParams {
  /// Member strands per square centimetre of scalp in the region.
  float density = 20.0f;
  /// Exactly this many member strands instead of the density (0: use the
  /// density). One strand with offset 0 is the key strand itself (imported
  /// grooms are one wisp a strand).
  int strands = 0;
  /// Largest offset of a member from the key strand, reached at the tip (m):
  /// small gives a smooth wisp, large a fuzzy one. The offset grows
  /// linearly with arc length from 0 at the root.
  float offset_radius = 0.01f;
  /// Members are shorter than the key strand by up to this fraction (0..0.9).
  float length_variation = 0.1f;
  /// Curls: a helix of this radius (m) around each member's own path in the
  /// key strand's rotation-minimising frame (0: straight).
  float curl_radius = 0.0f;
  /// Length of one turn of the curl along the strand (m).
  float curl_period = 0.03f;
  /// How far members near the wisp's border take the shapes of the
  /// neighbouring wisps' key strands (0..1), so that adjacent wisps meet as
  /// one head of hair: 0 keeps the seed's translated copies of the own key
  /// strand; 1 blends over about a third of the way between two wisps'
  /// roots (buildMemberStrands). A wisp through a tie is not blended, nor
  /// across a parting (neighbours whose tips, from their roots, lie more
  /// than half the strand apart). Style
  /// files without the field mean 0 (as they grew before); new wisps 1.
  float blend = 1.0f;
  /// The hairline (m, 0..0.05): members rooted within this distance of the
  /// edge of the hair (the boundary of all wisps' regions together, not the
  /// borders between wisps) are thinned, the nearer the edge the more
  /// (kept with probability distance / edge_ramp), so the front edge is not
  /// a row of bristles. 0: no ramp (files without the field).
  float edge_ramp = 0.0f;
  std::uint64_t seed = 1;
  bool operator==(const WispParams&) const = default;
};

struct Wisp {
  std::string name;
  WispRegion region;
  /// Control points of the key strand's Catmull-Rom spline, head frame (m).
  /// The first is the root, on the scalp at the region's root point
  /// (regionRoot); at least two.
  std::vector<glm::vec3> key_strand;
  WispParams params;
  bool operator==(const Wisp&) const = default;
};

/// A hair tie: a ring fixed in the head frame. Member strands of the wisps
/// whose key strand passes through it are gathered into it; in the
/// simulation the particles inside it are held like roots (they move with
/// the head) and the hair beyond swings freely.
struct HairTie {
  std::string name;
  glm::vec3 center{0.0f};    // head frame (m)
  glm::vec3 axis{0, -1, 0};  // the ring's axis (unit; hair runs along it)
  float radius = 0.015f;     // inner radius of the ring (m)
  float width = 0.012f;      // extent along the axis (m)
  /// Shape-keeping strength (Hz) of the hair the tie gathers, between the
  /// scalp and the ring: a tie pulls that hair taut against the head, which
  /// LCP, without bending or tension, cannot represent (docs/design.md).
  /// Applies when shape keeping is on; the stronger of this and the style's
  /// strength holds that hair.
  float hold = 4.0f;
  bool operator==(const HairTie&) const = default;
};

struct Style {
  std::string source;  // the file it came from (for messages and relative paths)
  std::string name = "style";
  HeadDesc head;
  glm::vec3 colour{0.22f, 0.13f, 0.07f};  // hair colour hint, linear RGB in [0,1]
  /// Default shape-keeping strength for simulations of this style (Hz), see
  /// SimParams::shape_keeping.
  float shape_keeping = 1.0f;
  std::vector<Wisp> wisps;
  std::vector<HairTie> ties;
  /// Equal wisps, ties and head (source is not compared).
  bool operator==(const Style& o) const;
};

/// Reads a style file (data/styles/README.md). Only the file's syntax and
/// ranges are checked here; checkStyle checks it against its head.
/// Throws StyleError.
Style loadStyle(const std::string& path);
Style parseStyle(const std::string& text, const std::string& source);
/// The style as a style file (mesh paths relative to the folder of `path`
/// when `path` is given). Numbers are written so that they read back
/// bit-exactly; equal styles give equal text.
std::string styleText(const Style& style, const std::string& path = "");
/// A wisp parameter typed into the viewer or set by a script ("density",
/// "strands", "offset_radius", "length_variation", "curl_radius",
/// "curl_period", "seed"), checked exactly as a style file's wisp is.
/// Returns the value as a wisp holds it; throws StyleError naming `source`,
/// the field and the value.
double checkWispValue(const std::string& field, double value, const std::string& source);
/// Writes styleText to `path` (the whole file or nothing). Throws StyleError.
void saveStyle(const Style& style, const std::string& path);

/// Checks the style against its head: regions on the scalp and not empty,
/// roots on the scalp, control points not inside the head, every tie with
/// at least one wisp passing through it. Throws StyleError naming the field.
void checkStyle(const Style& style, const HeadModel& head);

/// The (u, v) where a wisp's strands start from: the region's point nearest
/// to its area-weighted centre (in (u, v)).
glm::vec2 regionRoot(const WispRegion& region, const HeadModel& head);
/// Whether (u, v) lies in the region.
bool regionContains(const WispRegion& region, const HeadModel& head, glm::vec2 uv);
/// The region's area on the scalp (m^2), estimated on its triangles.
double regionArea(const WispRegion& region, const HeadModel& head);

/// The key strand sampled densely along its Catmull-Rom spline.
std::vector<glm::vec3> sampleKeyStrand(const std::vector<glm::vec3>& control, int per_span = 16);

/// `control` with control points added where its spline would pass 3 mm
/// or more inside the head (what the style file refuses, though every
/// control point lies outside: a strand dragged across the head, say):
/// each the spline's own point halfway along such a span, kept `clearance`
/// (m) outside the head and torso; a few rounds. What the editor stores
/// (StyleEditor::setKeyStrand) goes through it, so an edit never makes a
/// style its file would refuse.
std::vector<glm::vec3> keyStrandKeptOutside(std::vector<glm::vec3> control, const HeadModel& head, float clearance);

/// The three styling directions at control point k (Zhang & Wünsche Fig. 4):
/// the curve's unit tangent, the unit scalp normal at the scalp point
/// nearest to the control point, and the unit cross product tangent x normal.
struct StylingDirections {
  glm::vec3 tangent, normal, binormal;
  const glm::vec3& operator[](int k) const { return k == 0 ? tangent : k == 1 ? normal : binormal; }
};
StylingDirections stylingDirections(const Wisp& wisp, std::size_t k, const HeadModel& head);

/// The local frame of a root at (u, v): orthonormal columns (the scalp's
/// tangent along u, the scalp normal, their cross product), right-handed.
/// Copy/paste keeps a key strand's shape in this frame.
glm::mat3 rootFrame(const HeadModel& head, glm::vec2 uv);

/// A key strand moved to a new root: each control point keeps its
/// coordinates in the root frame (rootFrame), from `from_uv` on `from` to
/// `to_uv` on `to` (the same head for a paste).
std::vector<glm::vec3> reRootKeyStrand(const std::vector<glm::vec3>& control, const HeadModel& from, glm::vec2 from_uv,
                                       const HeadModel& to, glm::vec2 to_uv);

/// Member strands of a style, as polylines.
struct StrandSet {
  std::vector<glm::vec3> points;     // all strands' points, strand after strand
  std::vector<std::uint32_t> first;  // strand k is points[first[k], first[k+1])
  std::vector<std::uint32_t> wisp;   // per strand: the wisp it belongs to
  std::vector<glm::vec2> root_uv;    // per strand: (u, v) of its root
  std::size_t size() const { return wisp.size(); }
  std::size_t pointCount(std::size_t k) const { return first[k + 1] - first[k]; }
};

/// The distance between a member strand's points unless told (m).
inline constexpr float kStrandSpacing = 0.004f;

/// Grows every wisp's member strands (Zhang & Wünsche §3.2): roots spread by
/// Poisson-disc sampling over the region at the density, each a copy of the
/// key strand translated to its root, plus an offset that grows linearly
/// from 0 at the root to at most offset_radius at the tip, expressed in the
/// key strand's rotation-minimising frame; shortened by up to
/// length_variation; curled if asked; gathered into the ties the key strand
/// passes through; kept out of the head. `spacing` is the distance between
/// polyline points (m). Deterministic for the wisps' seeds. Throws
/// StyleError, naming the style and its largest wisp, when the strands or
/// their points could exceed `budget` (StrandBudget, scene.hpp). The wisps
/// are grown on `threads` threads; the strands are the same for any count.
/// `exact` false: the members are pushed out of the head and torso by the
/// bodies' fast approximation (Body::roughDistanceBelow) instead of exact
/// distances, for a preview that is drawn, not simulated or saved (the
/// styling mode's; a third of the time where the hair lies close to the
/// head): all but a few points in ten thousand land within a voxel of the
/// exact push.
StrandSet buildMemberStrands(const Style& style, const HeadModel& head, float spacing = kStrandSpacing,
                             const StrandBudget& budget = {}, int threads = 1, bool exact = true);

/// Re-roots every wisp on another head by (u, v): triangle regions become
/// the (u, v) polygons of their triangles, and each key strand leaves its
/// new root as it left the old one (in the root's local frame, as paste
/// does), turning over its first 5 cm to hang in the head frame as it did
/// on the old head, draped over the new one with the clearance it had.
/// Segment lengths are kept. The result uses `to`'s head description.
Style retargetStyle(const Style& style, const HeadModel& from, const HeadModel& to);

}  // namespace loosehair
