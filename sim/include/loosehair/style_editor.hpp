// Editing a style (method.md §6.2): the operations the viewer, the command line
// and the tests share, each undoable. Every operation checks its arguments
// and either applies whole or throws StyleError leaving the style as it was.
//
//   StyleEditor ed(loadStyle("bob.json"), head);
//   std::size_t w = ed.createWisp(region);
//   ed.moveControlPoint(w, 2, StylingAxis::Normal, 0.01f);  // 1 cm off the scalp
//   ed.undo();
//   saveStyle(ed.style(), "bob.json");
#pragma once

#include "loosehair/style.hpp"

#include <optional>
#include <vector>

namespace loosehair {

/// The three styling directions at a control point (stylingDirections).
enum class StylingAxis { Tangent = 0, Normal = 1, Binormal = 2 };

class StyleEditor {
 public:
  /// `head` is the style's head, built from style.head; it must outlive the editor.
  StyleEditor(Style style, const HeadModel& head);

  const Style& style() const { return style_; }
  const HeadModel& head() const { return head_; }

  // ---- wisps --------------------------------------------------------------
  /// Length of a new wisp's key strand when none is given (m).
  static constexpr float kNewWispLength = 0.2f;
  /// How far outside the head and torso drags and new points are kept (m).
  static constexpr float kClearance = 0.003f;
  /// A new wisp over `region`. Its key strand is `key` moved so that it
  /// starts at the region's root (translated), or, if `key` is empty, one
  /// of `length` metres that hangs as hair does (newKeyStrand). Returns its
  /// index (the last).
  std::size_t createWisp(const WispRegion& region, const WispParams& params = {},
                         const std::vector<glm::vec3>& key = {}, const std::string& name = "",
                         float length = kNewWispLength);
  /// The key strand a new wisp rooted at scalp point `uv` starts with: it
  /// leaves the scalp tilted down the slope (on the flat crown, towards the
  /// back, -z), bends under gravity (-y, the
  /// style's head at rest) as a cantilever of the scenes' default hair
  /// stiffness (method.md §6.1) and stays kClearance outside the head and the
  /// torso; five control points along its `length` (m, in [0.01, 2]).
  std::vector<glm::vec3> newKeyStrand(glm::vec2 uv, float length) const;
  void deleteWisp(std::size_t wisp);
  /// A new region; the key strand moves to the new root keeping its shape
  /// in the root's local frame.
  void setRegion(std::size_t wisp, const WispRegion& region);
  void setParams(std::size_t wisp, const WispParams& params);
  void renameWisp(std::size_t wisp, const std::string& name);
  /// A mirrored copy of the wisp on the other side of the head (through the
  /// plane x = HeadModel::mirrorPlaneX()): triangles go to the triangles
  /// under their mirrored centres, (u, v) polygons to u -> 1 - u, control
  /// points to their mirror images. Returns the new wisp's index.
  std::size_t mirrorWisp(std::size_t wisp);

  // ---- control points (index 0 is the root: it follows the region) ------
  /// Inserts a control point before index k (1 <= k <= count): at `point`
  /// if given, else halfway along the spline between k-1 and k (so the
  /// shape barely changes), or beyond the tip when k == count (along the
  /// last span, as long as it, moved out of the head and torso where it
  /// would lie inside).
  void addControlPoint(std::size_t wisp, std::size_t k, std::optional<glm::vec3> point = std::nullopt);
  /// Removes control point k (k >= 1; a key strand keeps at least two).
  void deleteControlPoint(std::size_t wisp, std::size_t k);
  /// Moves control point k (k >= 1) by `distance` metres along one of its
  /// styling directions as they are before the move.
  void moveControlPoint(std::size_t wisp, std::size_t k, StylingAxis axis, float distance);
  /// Puts control point k (k >= 1) at `point`.
  void setControlPoint(std::size_t wisp, std::size_t k, glm::vec3 point);

  // ---- dragging in the view ---------------------------------------------
  /// The key strand `key` as a drag leaves it (a pure function: a drag
  /// computed from where it started does not depend on the mouse's path):
  /// control point k (>= 1) moved by `offset`, each point after it by
  /// offset * exp(-s / falloff), s its distance from k along the strand
  /// (falloff <= 0: point k alone), the points before k unchanged, and
  /// every moved point then kept kClearance outside the head and torso.
  /// So the strand bends instead of kinking. k = 1 with an infinite
  /// falloff moves the whole strand but its root.
  std::vector<glm::vec3> dragged(const std::vector<glm::vec3>& key, std::size_t k, glm::vec3 offset,
                                 float falloff) const;
  /// Every edit that changes a key strand adds control points where its
  /// spline would cut into the head (keyStrandKeptOutside), so the style
  /// always passes checkStyle.
  ///
  /// Replaces the wisp's key strand (control point 0 stays the region's
  /// root). With `amend` the change joins the previous one if that was a
  /// setKeyStrand of the same wisp with no other edit, undo or redo
  /// between: one undo step for a whole drag.
  void setKeyStrand(std::size_t wisp, std::vector<glm::vec3> key, bool amend = false);
  /// Several wisps' key strands replaced in one edit (a brush stroke, a
  /// drag mirrored onto the partner), each as setKeyStrand; `amend` joins
  /// the previous such edit of the same wisps.
  void setKeyStrandsOf(std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> keys, bool amend = false);
  /// The wisp whose root lies nearest the mirror image of wisp w's root
  /// (across x = HeadModel::mirrorPlaneX()), if it is another wisp and
  /// within `tolerance` metres: its partner for mirrored editing.
  std::optional<std::size_t> mirrorPartner(std::size_t w, float tolerance = 0.01f) const;
  /// A key strand mirrored and moved onto wisp p's root (the partner's key
  /// strand in mirrored editing), kept out of the head.
  std::vector<glm::vec3> mirroredOnto(const std::vector<glm::vec3>& key, std::size_t p) const;
  /// Several wisps' parameters set in one edit (a curl brush stroke).
  void setParamsOf(const std::vector<std::pair<std::size_t, WispParams>>& params);
  /// Replaces every wisp's key strand at once, one undo step (what a
  /// settle gives: settledKeyStrands); each checked as setKeyStrand, the
  /// roots kept on their regions.
  void setKeyStrands(const std::vector<std::vector<glm::vec3>>& keys);
  /// `p` pushed out of the head and the torso to `clearance` (m) where it
  /// is nearer (along the surfaces' normals, a few rounds for creases).
  glm::vec3 keptOutside(glm::vec3 p, float clearance = kClearance) const;

  // ---- copy and paste of key strands ----------------------------------
  /// Remembers the wisp's key strand in its root frame (not an edit).
  void copyKeyStrand(std::size_t wisp);
  bool hasClipboard() const { return clipboard_.has_value(); }
  /// Replaces the wisp's key strand by the copied one, re-rooted at the
  /// wisp's root with its shape kept in the root's local frame.
  void pasteKeyStrand(std::size_t wisp);

  // ---- ties and the style's own fields --------------------------------
  /// A tie; refused (StyleError saying where to put it) when no key
  /// strand passes through its ring or the ring reaches into the head, as
  /// the style's check would refuse it. `gathered`: key strands replaced in
  /// the same edit (as setKeyStrandsOf; the tie tool pulls the strands it
  /// ties into the ring), one undo step with the tie.
  std::size_t addTie(const HairTie& tie, std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> gathered = {});
  void deleteTie(std::size_t tie);
  void setTie(std::size_t tie, const HairTie& value);
  void setColour(glm::vec3 colour);
  void setShapeKeeping(float hz);

  // ---- history ---------------------------------------------------------
  bool canUndo() const { return !undo_.empty(); }
  bool canRedo() const { return !redo_.empty(); }
  /// Back to the style before the last operation (false: nothing to undo).
  bool undo();
  /// Reapplies the last undone operation (false: nothing to redo).
  bool redo();

 private:
  Wisp& wisp(std::size_t i, const char* what);
  const Wisp& wisp(std::size_t i, const char* what) const;
  /// setKeyStrandsOf's checks and mending of the keys (roots put back on
  /// their regions); the wisps they replace, sorted.
  std::vector<std::size_t> preparedKeys(std::vector<std::pair<std::size_t, std::vector<glm::vec3>>>& keys) const;
  /// The tie checks of the style file (values, a key strand through the
  /// ring, the ring out of the head) against `style`.
  void checkTie(const char* what, const HairTie& tie, const Style& style) const;
  void checkPoint(std::size_t wisp, std::size_t k, glm::vec3 p) const;
  /// Records the current style for undo and clears the redo list.
  void record();
  Style style_;
  std::vector<std::size_t> amendable_;  // the wisps the last edit (setKeyStrandsOf) may be amended on
  const HeadModel& head_;
  std::vector<Style> undo_, redo_;
  struct Clip {
    std::vector<glm::vec3> key;
    glm::vec2 root_uv;
  };
  std::optional<Clip> clipboard_;
};

}  // namespace loosehair
