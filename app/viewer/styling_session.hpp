// The viewer's styling mode (issue: interactive viewer): a style being
// edited with the library's StyleEditor (nothing re-implemented here), the
// brush that paints scalp triangles by ray picking on the head mesh, the
// selection (a wisp, one of its control points, one of the three styling
// directions), and the preview drawn as overlay lines: member strands, the
// key strands with their control points, the three arrows at the selected
// point with the active one highlighted, the brushed triangles, the ties.
//
// The head stays at rest while styling, so world and head frame agree.
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/render/overlay.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"

#include <memory>
#include <optional>
#include <set>
#include <string>

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
  /// Selects the control point nearest the ray within `tolerance` metres
  /// (at its depth), else the wisp whose key strand passes nearest; false
  /// (selection unchanged) when nothing is near.
  bool select(const render::Ray& ray, float tolerance);
  /// Keeps the selection valid after edits, undo and redo.
  void clampSelection();

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
  std::string preview_error;  // why the preview could not be grown ("" if it was)

 private:
  std::size_t requireWisp(const char* what) const;
  void rebuildPreview();

  std::unique_ptr<HeadModel> head_;
  StyleEditor editor_;
  std::set<std::uint32_t> brushed_;
  StrandSet preview_;
  std::optional<Style> preview_of_;  // the style the preview was grown from
};

}  // namespace loosehair::viewer
