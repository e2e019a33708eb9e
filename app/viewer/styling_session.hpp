// The viewer's styling mode (issue: interactive viewer): a style being
// edited with the library's StyleEditor (nothing re-implemented here), the
// brush that paints scalp triangles by ray picking on the head mesh, the
// selection (a wisp, one of its control points, one of the three styling
// directions), direct manipulation (issue 44: what is under the pointer is
// highlighted; a left drag moves a control point in the view plane, or
// along a styling direction when it grabs that arrow, or the whole key
// strand when it grabs the strand between its points; one undo step a
// drag), and the preview drawn as overlay lines: member strands, the key
// strands with their control points, the three arrows at the selected point
// with the active one highlighted, the brushed triangles, the ties.
//
// The head stays at rest while styling, so world and head frame agree.
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/scalp_coverage.hpp"
#include "loosehair/render/overlay.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"

#include <future>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace loosehair::viewer {

class StylingSession {
 public:
  /// Edits `style` on its head (built here: throws SceneError / StyleError).
  explicit StylingSession(Style style);

  const Style& style() const { return editor_.style(); }
  StyleEditor& editor() { return editor_; }
  const HeadModel& head() const { return *head_; }

  // ---- the brush ----------------------------------------------------------
  float brush_radius = 0.015f;  // m on the scalp
  /// Paints the scalp triangles around where the ray meets the head mesh;
  /// false if it misses the head.
  bool brush(const render::Ray& ray);
  const std::set<std::uint32_t>& brushed() const { return brushed_; }
  void clearBrush() { brushed_.clear(); }
  /// A new wisp over the brushed triangles with `params` (selected; the
  /// brush is cleared). Throws StyleError (nothing brushed, ...).
  std::size_t createWispFromBrush(const WispParams& params);
  /// The selected wisp's region becomes the brushed triangles.
  void setRegionFromBrush();

  // ---- selection ------------------------------------------------------------
  std::optional<std::size_t> wisp;   // selected wisp
  std::optional<std::size_t> point;  // its selected control point (>= 1 to move)
  StylingAxis axis = StylingAxis::Normal;
  /// Keeps the selection valid after edits, undo and redo.
  void clampSelection();

  // ---- direct manipulation ------------------------------------------------
  /// What a ray picks: an arrow of the selected control point (`handle`),
  /// else a control point (`point`), else a key strand between its points.
  struct Pick {
    std::size_t wisp = 0;
    std::optional<std::size_t> point;
    std::optional<StylingAxis> handle;
    bool operator==(const Pick&) const = default;
  };
  /// The pick nearest the ray within `tolerance` metres (at its depth).
  std::optional<Pick> pick(const render::Ray& ray, float tolerance) const;
  /// What the pointer is over (highlighted in the overlay).
  std::optional<Pick> hover;
  void hoverAt(const render::Ray& ray, float tolerance) { hover = pick(ray, tolerance); }
  /// Arc length (m) over which the points after a dragged control point
  /// follow it (StyleEditor::dragged); 0: the point alone.
  float drag_falloff = 0.06f;
  /// A press: picks (and selects) what is under the ray and starts
  /// dragging it; false when nothing is there (the brush or the camera
  /// then take the press). The root only selects: it follows the region.
  bool beginDrag(const render::Ray& ray, float tolerance);
  /// The pointer moved while dragging: the grabbed point goes where the ray
  /// meets the plane through it facing the press's ray, or along the
  /// grabbed arrow's direction. Each move is computed from where the drag
  /// started and joins the same undo step.
  void dragTo(const render::Ray& ray);
  void endDrag() { drag_.reset(); }
  bool dragging() const { return drag_.has_value(); }
  /// Where a person presses to grab control point k's arrow `a` (on the
  /// selected point's arrows), or the key strand between points k and
  /// k + 1: for scripts that drag them. Throws StyleError naming what does
  /// not exist.
  glm::vec3 handlePoint(std::size_t wisp, std::size_t k, StylingAxis a) const;
  glm::vec3 strandPoint(std::size_t wisp, std::size_t k) const;
  // ---- strand brushes and mirrored editing ------------------------------
  /// What a left drag does: select and drag (a press on the scalp paints
  /// the region brush), or a brush over the key strands.
  enum class Tool { Select, Comb, Length, Puff, Smooth, Curl, Tie };
  Tool tool = Tool::Select;
  float brush_pixels = 60.0f;   // the strand brushes' radius on screen
  float brush_strength = 0.5f;  // 0..1, a dab's share of the full effect
  /// What the curl brush gives the wisps it touches (m).
  float curl_radius = 0.01f, curl_period = 0.03f;
  /// Every edit of a key strand also shapes its partner's (the wisp rooted
  /// at its mirror image, StyleEditor::mirrorPartner), mirrored.
  bool mirror_editing = false;
  /// One dab of the strand brush `tool` where the pointer is (window pixel
  /// `at`; it came from `from`), seen by `camera` in a width x height view:
  /// control points within brush_pixels of it on screen, in front of the
  /// head there, are touched, the nearer the more (StrandBrush,
  /// brushedKeyStrand). All dabs of a stroke are one undo step; a curl
  /// stroke sets the touched wisps' curl when it ends. `invert` (Shift):
  /// the length brush cuts instead of growing.
  void brushDab(const render::Camera& camera, int width, int height, glm::vec2 at, glm::vec2 from, bool invert = false);
  void endStroke();

  // ---- letting the physics finish the style ------------------------------
  /// Simulated time of a settle (s).
  float settle_seconds = 1.5f;
  /// Starts a settle (settledKeyStrands: the style's hair simulated on a
  /// still head, the key strands read back) on a thread of its own; the
  /// view and the panel go on. Throws StyleError if one is running.
  void startSettle();
  bool settling() const { return settle_.valid(); }
  /// Applies a finished settle to the key strands, one undo step; true when
  /// it did. `wait`: until it finishes (scripts). A settle of a style edited
  /// since it started is dropped with a StyleError saying so; the settle's
  /// own errors are thrown here.
  bool finishSettle(bool wait = false);

  /// Length of the key strand of a wisp the brush creates (m).
  float new_wisp_length = StyleEditor::kNewWispLength;

  // ---- edits of the selection (StyleEditor operations) ------------------
  void moveSelected(float distance);  // along `axis`
  void addPointAfterSelected();
  void deleteSelectedPoint();
  void deleteSelectedWisp();
  void copySelected();
  void pasteOnSelected();
  std::size_t mirrorSelected();
  /// A tie ring at the selected control point, along the key strand.
  std::size_t tieAtSelected(float radius);
  /// A tie where the ray passes the key strands (the tie tool's click): it
  /// snaps around every key strand passing within `reach` metres of the ray
  /// (at its depth), centred on them, along them, 8 mm wider than they lie
  /// apart (8 to 20 mm), moved off the head until it clears it, and gathers
  /// them: each gets a control point inside the ring, the rest of the strand
  /// moved as far. One undo step.
  /// Throws StyleError saying what to do where none passes.
  std::size_t tieAt(const render::Ray& ray, float reach);
  bool undo();
  bool redo();
  void save(const std::string& path) const { saveStyle(style(), path); }

  // ---- preview ----------------------------------------------------------------
  /// Member strands grown at this fraction of each wisp's density for the
  /// preview (the simulation uses them all).
  float preview_density = 0.35f;
  void overlay(render::OverlayLines& hidden, render::OverlayLines& on_top);
  /// Member strands in the preview.
  std::size_t previewStrands() const { return preview_.size(); }
  /// The coverage view: the scalp's points with no member root (at full
  /// density) within 5 mm, drawn red; and the covered share of the scalp.
  bool show_coverage = false;
  /// The covered share (scalpCoverage) of the style as last previewed with
  /// the coverage view on; negative before it was measured.
  double covered() const { return coverage_of_ ? coverage_.covered : -1.0; }
  std::string preview_error;  // why the preview could not be grown ("" if it was)

 private:
  std::size_t requireWisp(const char* what) const;
  void rebuildPreview();

  struct Drag {
    std::size_t wisp = 0, point = 1;  // the point moved (1 with an infinite falloff: the whole strand)
    bool whole = false;
    std::vector<glm::vec3> start;  // the key strand when the drag began
    glm::vec3 grab{0.0f};          // the point grabbed
    glm::vec3 plane_normal{0.0f, 0.0f, 1.0f};
    std::optional<glm::vec3> axis;  // along a styling direction only
    bool moved = false;
  };
  std::optional<Drag> drag_;
  bool stroke_edited_ = false;           // the stroke made its undo step
  std::set<std::size_t> stroke_curled_;  // the wisps the curl stroke touched
  std::future<std::vector<std::vector<glm::vec3>>> settle_;
  Style settle_of_;  // the style the running settle started from

  std::unique_ptr<HeadModel> head_;
  StyleEditor editor_;
  std::set<std::uint32_t> brushed_;
  StrandSet preview_;
  std::optional<Style> preview_of_;  // the style the preview was grown from
  ScalpCoverage coverage_;
  std::optional<Style> coverage_of_;  // the style coverage_ was measured on
};

}  // namespace loosehair::viewer
