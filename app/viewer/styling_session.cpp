#include "viewer/styling_session.hpp"

#include "loosehair/ray_pick.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <limits>

namespace loosehair::viewer {
namespace {

// wisp colours of the preview, and the highlight of the selection
const glm::vec4 kPalette[] = {{0.85f, 0.45f, 0.15f, 0.55f}, {0.2f, 0.55f, 0.9f, 0.55f}, {0.3f, 0.75f, 0.3f, 0.55f},
                              {0.8f, 0.3f, 0.7f, 0.55f},   {0.7f, 0.7f, 0.2f, 0.55f}, {0.3f, 0.7f, 0.75f, 0.55f}};
const glm::vec4 kSelected{1.0f, 0.1f, 0.1f, 0.9f};
const glm::vec4 kKey{0.1f, 0.1f, 0.1f, 1.0f};
const glm::vec4 kBrush{0.9f, 0.1f, 0.6f, 0.9f};
const glm::vec4 kAxis[3] = {{0.9f, 0.2f, 0.2f, 1.0f}, {0.2f, 0.8f, 0.2f, 1.0f}, {0.2f, 0.3f, 0.95f, 1.0f}};

}  // namespace

StylingSession::StylingSession(Style style)
    : head_(std::make_unique<HeadModel>(HeadModel::build(style.head, style.source))),
      editor_(std::move(style), *head_) {}

bool StylingSession::brush(const render::Ray& ray) {
  const std::optional<RayHit> hit = intersectRay(head_->headMesh(), ray.origin, ray.direction);
  if (!hit) return false;
  for (std::uint32_t t : scalpTrianglesWithin(*head_, hit->point, brush_radius)) brushed_.insert(t);
  return true;
}

std::size_t StylingSession::createWispFromBrush(const WispParams& params) {
  if (brushed_.empty()) throw StyleError("brush the scalp first: the new wisp needs a region");
  WispRegion region;
  region.triangles.assign(brushed_.begin(), brushed_.end());
  const std::size_t w = editor_.createWisp(region, params);
  brushed_.clear();
  wisp = w;
  point = style().wisps[w].key_strand.size() - 1;
  return w;
}

void StylingSession::setRegionFromBrush() {
  const std::size_t w = requireWisp("change its region");
  if (brushed_.empty()) throw StyleError("brush the scalp first: the wisp needs a new region");
  WispRegion region;
  region.triangles.assign(brushed_.begin(), brushed_.end());
  editor_.setRegion(w, region);
  brushed_.clear();
}

bool StylingSession::select(const render::Ray& ray, float tolerance) {
  const auto& wisps = style().wisps;
  float best = std::numeric_limits<float>::max();
  std::optional<std::pair<std::size_t, std::size_t>> pick;
  for (std::size_t w = 0; w < wisps.size(); ++w)
    for (std::size_t k = 0; k < wisps[w].key_strand.size(); ++k) {
      const float d = distanceToRay(wisps[w].key_strand[k], ray.origin, ray.direction);
      if (d < tolerance && d < best) best = d, pick = std::make_pair(w, k);
    }
  if (pick) {
    wisp = pick->first;
    point = pick->second;
    return true;
  }
  best = std::numeric_limits<float>::max();
  std::optional<std::size_t> strand;
  for (std::size_t w = 0; w < wisps.size(); ++w)
    for (const glm::vec3& p : sampleKeyStrand(wisps[w].key_strand, 8)) {
      const float d = distanceToRay(p, ray.origin, ray.direction);
      if (d < tolerance && d < best) best = d, strand = w;
    }
  if (!strand) return false;
  wisp = strand;
  point.reset();
  return true;
}

void StylingSession::clampSelection() {
  const auto& wisps = style().wisps;
  if (wisp && *wisp >= wisps.size()) wisp = wisps.empty() ? std::nullopt : std::optional<std::size_t>(wisps.size() - 1);
  if (!wisp) point.reset();
  if (wisp && point && *point >= wisps[*wisp].key_strand.size()) point = wisps[*wisp].key_strand.size() - 1;
}

std::size_t StylingSession::requireWisp(const char* what) const {
  if (!wisp) throw StyleError(std::string("select a wisp first to ") + what);
  return *wisp;
}

void StylingSession::moveSelected(float distance) {
  const std::size_t w = requireWisp("move a control point");
  if (!point || *point == 0) throw StyleError("select a control point other than the root to move it");
  editor_.moveControlPoint(w, *point, axis, distance);
}

void StylingSession::addPointAfterSelected() {
  const std::size_t w = requireWisp("add a control point");
  const std::size_t n = style().wisps[w].key_strand.size();
  const std::size_t k = point ? std::min(*point + 1, n) : n;
  editor_.addControlPoint(w, k);
  point = k;
}

void StylingSession::deleteSelectedPoint() {
  const std::size_t w = requireWisp("delete a control point");
  if (!point) throw StyleError("select a control point to delete it");
  editor_.deleteControlPoint(w, *point);
  clampSelection();
}

void StylingSession::deleteSelectedWisp() {
  editor_.deleteWisp(requireWisp("delete it"));
  point.reset();
  clampSelection();
}

void StylingSession::copySelected() { editor_.copyKeyStrand(requireWisp("copy its key strand")); }

void StylingSession::pasteOnSelected() { editor_.pasteKeyStrand(requireWisp("paste a key strand onto it")); }

std::size_t StylingSession::mirrorSelected() {
  const std::size_t m = editor_.mirrorWisp(requireWisp("mirror it"));
  wisp = m;
  clampSelection();
  return m;
}

std::size_t StylingSession::tieAtSelected(float radius) {
  const std::size_t w = requireWisp("place a tie on it");
  if (!point) throw StyleError("select the control point the tie goes around");
  HairTie tie;
  tie.center = style().wisps[w].key_strand[*point];
  tie.axis = stylingDirections(style().wisps[w], *point, *head_).tangent;
  tie.radius = radius;
  return editor_.addTie(tie);
}

bool StylingSession::undo() {
  const bool done = editor_.undo();
  clampSelection();
  return done;
}

bool StylingSession::redo() {
  const bool done = editor_.redo();
  clampSelection();
  return done;
}

void StylingSession::rebuildPreview() {
  Style thin = style();
  for (Wisp& w : thin.wisps) {
    w.params.density *= preview_density;
    if (w.params.strands > 0) w.params.strands = std::max(1, static_cast<int>(static_cast<float>(w.params.strands) * preview_density));
  }
  preview_error.clear();
  try {
    preview_ = buildMemberStrands(thin, *head_, 0.006f);
  } catch (const std::exception& e) {
    preview_ = StrandSet{};
    preview_error = e.what();
  }
  preview_of_ = style();
}

void StylingSession::overlay(render::OverlayLines& hidden, render::OverlayLines& on_top) {
  if (!preview_of_ || !(*preview_of_ == style())) rebuildPreview();
  const auto& wisps = style().wisps;
  std::vector<glm::vec3> line;
  for (std::size_t s = 0; s < preview_.size(); ++s) {
    const std::uint32_t w = preview_.wisp[s];
    const glm::vec4 c = wisp && *wisp == w ? glm::vec4(kSelected.r, kSelected.g, kSelected.b, 0.6f)
                                           : kPalette[w % std::size(kPalette)];
    line.assign(preview_.points.begin() + preview_.first[s], preview_.points.begin() + preview_.first[s + 1]);
    hidden.polyline(line, c);
  }
  // key strands and control points: the selected wisp's over everything,
  // the others hidden by the head as the hair is
  for (std::size_t w = 0; w < wisps.size(); ++w) {
    const bool sel = wisp && *wisp == w;
    render::OverlayLines& out = sel ? on_top : hidden;
    out.polyline(sampleKeyStrand(wisps[w].key_strand, 8), sel ? kSelected : kKey);
    for (std::size_t k = 0; k < wisps[w].key_strand.size(); ++k)
      out.cross(wisps[w].key_strand[k], sel && point && *point == k ? 0.006f : 0.003f,
                sel && point && *point == k ? kSelected : kKey);
  }
  // the three styling directions at the selected point, the active one bright
  if (wisp && point && *wisp < wisps.size() && *point < wisps[*wisp].key_strand.size()) {
    const StylingDirections d = stylingDirections(wisps[*wisp], *point, *head_);
    const glm::vec3 p = wisps[*wisp].key_strand[*point];
    for (int a = 0; a < 3; ++a) {
      const bool active = a == static_cast<int>(axis);
      glm::vec4 c = kAxis[a];
      if (!active) c = glm::vec4(glm::vec3(c) * 0.5f + 0.4f, 0.7f);
      on_top.arrow(p, p + (active ? 0.05f : 0.03f) * d[a], c);
    }
  }
  // brushed triangles (outlines) and ties (rings)
  const ScalpTriangles& st = head_->scalpTriangles();
  for (std::uint32_t t : brushed_) {
    const glm::vec3 a = st.positions[st.triangles[t][0]], b = st.positions[st.triangles[t][1]],
                    c = st.positions[st.triangles[t][2]];
    const glm::vec3 n = 0.001f * glm::normalize(glm::cross(b - a, c - a));
    hidden.line(a + n, b + n, kBrush);
    hidden.line(b + n, c + n, kBrush);
    hidden.line(c + n, a + n, kBrush);
  }
  for (const HairTie& tie : style().ties) {
    const glm::vec3 ax = glm::normalize(tie.axis);
    const glm::vec3 helper = std::abs(ax.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 u = glm::normalize(glm::cross(ax, helper)), v = glm::cross(ax, u);
    std::vector<glm::vec3> ring;
    for (int k = 0; k <= 24; ++k) {
      const float a = 6.2831853f * static_cast<float>(k) / 24.0f;
      ring.push_back(tie.center + tie.radius * (std::cos(a) * u + std::sin(a) * v));
    }
    on_top.polyline(ring, glm::vec4(0.95f, 0.75f, 0.1f, 1.0f));
  }
}

}  // namespace loosehair::viewer
