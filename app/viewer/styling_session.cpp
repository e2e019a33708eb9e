#include "viewer/styling_session.hpp"

#include "loosehair/ray_pick.hpp"
#include "loosehair/strand_brushes.hpp"
#include "loosehair/style_settle.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <thread>
#include <chrono>
#include <cmath>
#include <limits>

namespace loosehair::viewer {
namespace {

// wisp colours of the preview, and the highlight of the selection
const glm::vec4 kPalette[] = {{0.85f, 0.45f, 0.15f, 0.55f}, {0.2f, 0.55f, 0.9f, 0.55f}, {0.3f, 0.75f, 0.3f, 0.55f},
                              {0.8f, 0.3f, 0.7f, 0.55f},    {0.7f, 0.7f, 0.2f, 0.55f},  {0.3f, 0.7f, 0.75f, 0.55f}};
const glm::vec4 kSelected{1.0f, 0.1f, 0.1f, 0.9f};
const glm::vec4 kKey{0.1f, 0.1f, 0.1f, 1.0f};
const glm::vec4 kBrush{0.9f, 0.1f, 0.6f, 0.9f};
const glm::vec4 kAxis[3] = {{0.9f, 0.2f, 0.2f, 1.0f}, {0.2f, 0.8f, 0.2f, 1.0f}, {0.2f, 0.3f, 0.95f, 1.0f}};
const glm::vec4 kHover{1.0f, 0.85f, 0.1f, 1.0f};
// an arrow of the selected point: active and inactive lengths (m)
constexpr float kActiveArrow = 0.05f, kArrow = 0.03f;

// where the ray meets the plane through `p` with normal `n` (in front of
// the ray's origin), if it does
std::optional<glm::vec3> rayMeetsPlane(const render::Ray& ray, glm::vec3 p, glm::vec3 n) {
  const glm::vec3 dir = glm::normalize(ray.direction);
  const float den = glm::dot(dir, n);
  if (!(std::abs(den) > 1e-6f)) return std::nullopt;
  const float t = glm::dot(p - ray.origin, n) / den;
  if (!(t > 0.0f)) return std::nullopt;
  return ray.origin + t * dir;
}

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
  const std::size_t w = editor_.createWisp(region, params, {}, "", new_wisp_length);
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

std::optional<StylingSession::Pick> StylingSession::pick(const render::Ray& ray, float tolerance) const {
  const auto& wisps = style().wisps;
  // the arrows of the selected point first: they lie over everything
  if (wisp && point && *wisp < wisps.size() && *point > 0 && *point < wisps[*wisp].key_strand.size()) {
    const StylingDirections d = stylingDirections(wisps[*wisp], *point, *head_);
    const glm::vec3 p = wisps[*wisp].key_strand[*point];
    float best = tolerance;
    std::optional<StylingAxis> handle;
    for (int a = 0; a < 3; ++a) {
      const float len = a == static_cast<int>(axis) ? kActiveArrow : kArrow;
      for (int s = 2; s <= 8; ++s) {  // the arrow's outer part (its base is the point itself)
        const float dist = distanceToRay(p + (len * static_cast<float>(s) / 8.0f) * d[a], ray.origin, ray.direction);
        if (dist < best) best = dist, handle = static_cast<StylingAxis>(a);
      }
    }
    if (handle) return Pick{*wisp, point, handle};
  }
  float best = tolerance;
  std::optional<Pick> found;
  for (std::size_t w = 0; w < wisps.size(); ++w)
    for (std::size_t k = 0; k < wisps[w].key_strand.size(); ++k) {
      const float d = distanceToRay(wisps[w].key_strand[k], ray.origin, ray.direction);
      if (d < best) best = d, found = Pick{w, k, std::nullopt};
    }
  if (found) return found;
  best = tolerance;
  for (std::size_t w = 0; w < wisps.size(); ++w)
    for (const glm::vec3& p : sampleKeyStrand(wisps[w].key_strand, 8)) {
      const float d = distanceToRay(p, ray.origin, ray.direction);
      if (d < best) best = d, found = Pick{w, std::nullopt, std::nullopt};
    }
  return found;
}

namespace {
const std::vector<glm::vec3>& keyOf(const Style& style, std::size_t w, std::size_t k, std::size_t needed) {
  if (w >= style.wisps.size())
    throw StyleError("there is no wisp " + std::to_string(w) + " (the style has " + std::to_string(style.wisps.size()) +
                     ")");
  const auto& key = style.wisps[w].key_strand;
  if (k + needed >= key.size())
    throw StyleError("wisp " + std::to_string(w) + " has no control point " + std::to_string(k + needed) + " (it has " +
                     std::to_string(key.size()) + ")");
  return key;
}
}  // namespace

glm::vec3 StylingSession::handlePoint(std::size_t w, std::size_t k, StylingAxis a) const {
  const auto& key = keyOf(style(), w, k, 0);
  const StylingDirections d = stylingDirections(style().wisps[w], k, *head_);
  const float len = a == axis ? kActiveArrow : kArrow;
  return key[k] + 0.75f * len * d[static_cast<int>(a)];
}

glm::vec3 StylingSession::strandPoint(std::size_t w, std::size_t k) const {
  const auto& key = keyOf(style(), w, k, 1);
  return sampleKeyStrand(key, 8)[8 * k + 4];  // the middle of the span from k
}

bool StylingSession::beginDrag(const render::Ray& ray, float tolerance) {
  drag_.reset();
  const std::optional<Pick> p = pick(ray, tolerance);
  if (!p) return false;
  wisp = p->wisp;
  point = p->point;
  const std::vector<glm::vec3>& key = style().wisps[p->wisp].key_strand;
  Drag d;
  d.wisp = p->wisp;
  d.start = key;
  d.plane_normal = glm::normalize(ray.direction);
  if (p->handle) {
    axis = *p->handle;
    d.point = *p->point;
    d.grab = key[d.point];
    d.axis = stylingDirections(style().wisps[p->wisp], d.point, *head_)[static_cast<int>(*p->handle)];
  } else if (p->point) {
    if (*p->point == 0) return true;  // the root: selected, not moved
    d.point = *p->point;
    d.grab = key[d.point];
  } else {
    // the strand between its points: the whole of it but the root, grabbed
    // where the ray passes nearest
    d.point = 1;
    d.whole = true;
    float best = std::numeric_limits<float>::max();
    for (const glm::vec3& q : sampleKeyStrand(key, 8)) {
      const float dist = distanceToRay(q, ray.origin, ray.direction);
      if (dist < best) best = dist, d.grab = q;
    }
  }
  drag_ = d;
  return true;
}

void StylingSession::dragTo(const render::Ray& ray) {
  if (!drag_ || drag_->wisp >= style().wisps.size()) return;
  Drag& d = *drag_;
  glm::vec3 offset(0.0f);
  const glm::vec3 dir = glm::normalize(ray.direction);
  if (d.axis) {
    // the point of the line grab + s axis nearest the ray
    const glm::vec3 a = *d.axis, w0 = d.grab - ray.origin;
    const float b = glm::dot(a, dir), den = 1.0f - b * b;
    if (!(den > 1e-6f)) return;  // looking along the arrow
    const float s = (b * glm::dot(w0, dir) - glm::dot(w0, a)) / den;
    offset = s * a;
  } else {
    const std::optional<glm::vec3> at = rayMeetsPlane(ray, d.grab, d.plane_normal);
    if (!at) return;
    offset = *at - d.grab;
  }
  if (!std::isfinite(offset.x) || !std::isfinite(offset.y) || !std::isfinite(offset.z)) return;
  try {
    const float falloff = d.whole ? std::numeric_limits<float>::infinity() : drag_falloff;
    std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> keys;
    keys.emplace_back(d.wisp, editor_.dragged(d.start, d.point, offset, falloff));
    if (mirror_editing)
      if (const std::optional<std::size_t> p = editor_.mirrorPartner(d.wisp))
        keys.emplace_back(*p, editor_.mirroredOnto(keys.front().second, *p));
    editor_.setKeyStrandsOf(std::move(keys), d.moved);
    d.moved = true;
  } catch (const StyleError&) {
    // a move the editor refuses (two points made to coincide): the strand
    // stays as the last move left it
  }
}

void StylingSession::brushDab(const render::Camera& camera, int width, int height, glm::vec2 at, glm::vec2 from,
                              bool invert) {
  if (tool == Tool::Select || tool == Tool::Tie) return;  // not brushes
  const auto& wisps = style().wisps;
  if (wisps.empty()) return;
  const render::Ray ray = camera.ray(at.x, at.y, width, height), before = camera.ray(from.x, from.y, width, height);
  // points behind the head where the pointer is are left alone
  float reach = std::numeric_limits<float>::infinity();
  if (const std::optional<RayHit> hit = intersectRay(head_->headMesh(), ray.origin, ray.direction))
    reach = glm::length(hit->point - ray.origin) + 0.02f;
  const glm::vec3 facing = glm::normalize(ray.direction);
  std::vector<std::vector<glm::vec3>> keys(wisps.size());
  std::vector<bool> touched(wisps.size(), false);
  for (std::size_t w = 0; w < wisps.size(); ++w) {
    const std::vector<glm::vec3>& key = wisps[w].key_strand;
    keys[w] = key;
    BrushDab dab;
    dab.strength = brush_strength;
    dab.grow = invert ? -0.1f : 0.1f;
    dab.weight.assign(key.size(), 0.0f);
    dab.move.assign(key.size(), glm::vec3(0.0f));
    for (std::size_t k = 1; k < key.size(); ++k) {
      const float d = glm::length(camera.pixel(key[k], width, height) - at);
      if (!(d < brush_pixels) || glm::length(key[k] - ray.origin) > reach) continue;
      const float f = 1.0f - d / brush_pixels;
      dab.weight[k] = f * f;
      touched[w] = true;
      // the pointer's move at the point's depth (in the plane through it facing the view)
      const std::optional<glm::vec3> now = rayMeetsPlane(ray, key[k], facing),
                                     was = rayMeetsPlane(before, key[k], facing);
      if (now && was) dab.move[k] = *now - *was;
    }
    if (!touched[w]) continue;
    if (tool == Tool::Curl) {
      stroke_curled_.insert(w);
      continue;
    }
    dab.brush = tool == Tool::Comb     ? StrandBrush::Comb
                : tool == Tool::Length ? StrandBrush::Length
                : tool == Tool::Puff   ? StrandBrush::Puff
                                       : StrandBrush::Smooth;
    keys[w] = brushedKeyStrand(key, dab, *head_, head_->scalpNormal(regionRoot(wisps[w].region, *head_)),
                               StyleEditor::kClearance);
  }
  if (tool == Tool::Curl) return;
  bool any = false;
  for (std::size_t w = 0; w < wisps.size(); ++w) any = any || touched[w];
  if (!any) return;
  if (mirror_editing)
    for (std::size_t w = 0; w < wisps.size(); ++w) {
      if (!touched[w]) continue;
      const std::optional<std::size_t> p = editor_.mirrorPartner(w);
      if (p && !touched[*p]) keys[*p] = editor_.mirroredOnto(keys[w], *p);
    }
  // every wisp, so that each dab of the stroke amends the same edit
  std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> all;
  for (std::size_t w = 0; w < wisps.size(); ++w) all.emplace_back(w, std::move(keys[w]));
  editor_.setKeyStrandsOf(std::move(all), stroke_edited_);
  stroke_edited_ = true;
}

void StylingSession::endStroke() {
  if (tool == Tool::Curl && !stroke_curled_.empty()) {
    std::set<std::size_t> wisps = stroke_curled_;
    if (mirror_editing)
      for (std::size_t w : stroke_curled_)
        if (const auto p = editor_.mirrorPartner(w)) wisps.insert(*p);
    std::vector<std::pair<std::size_t, WispParams>> params;
    for (std::size_t w : wisps) {
      WispParams p = style().wisps[w].params;
      p.curl_radius = curl_radius;
      p.curl_period = curl_period;
      params.emplace_back(w, p);
    }
    stroke_curled_.clear();
    editor_.setParamsOf(params);  // checked as a style file's: throws naming the value
  }
  stroke_curled_.clear();
  stroke_edited_ = false;
}

void StylingSession::startSettle() {
  if (settling()) throw StyleError("a settle is running already");
  if (style().wisps.empty()) throw StyleError("settle: the style has no wisps yet; brush a region and create one");
  if (!(settle_seconds > 0.0f && settle_seconds <= 10.0f))
    throw StyleError("settle: the time must be in (0, 10] s, got " + std::to_string(settle_seconds));
  settle_of_ = style();
  SettleOptions o;
  o.seconds = settle_seconds;
  o.threads = 1;  // the simulation thread and the window keep the other core
  settle_ = std::async(std::launch::async, [style = settle_of_, o] { return settledKeyStrands(style, o); });
}

bool StylingSession::finishSettle(bool wait) {
  if (!settling()) return false;
  if (!wait && settle_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  const std::vector<std::vector<glm::vec3>> keys = settle_.get();  // rethrows the settle's error
  if (!(style() == settle_of_))
    throw StyleError("the style was edited while it settled: the settle was dropped; press Settle again");
  editor_.setKeyStrands(keys);
  clampSelection();
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

std::size_t StylingSession::tieAt(const render::Ray& ray, float reach) {
  const auto& wisps = style().wisps;
  constexpr int kPer = 16;
  struct Hit {
    std::size_t wisp, span;
    glm::vec3 at, along;
  };
  std::vector<Hit> hits;
  for (std::size_t w = 0; w < wisps.size(); ++w) {
    const std::vector<glm::vec3> dense = sampleKeyStrand(wisps[w].key_strand, kPer);
    float best = reach;
    std::optional<std::size_t> hit;
    for (std::size_t j = 1; j + 1 < dense.size(); ++j) {
      const float d = distanceToRay(dense[j], ray.origin, ray.direction);
      if (d < best) best = d, hit = j;
    }
    if (!hit) continue;
    hits.push_back({w, std::min(*hit / kPer, wisps[w].key_strand.size() - 2), dense[*hit],
                    glm::normalize(dense[*hit + 1] - dense[*hit - 1])});
  }
  if (hits.empty())
    throw StyleError(
        "no key strand passes there: click where the wisps' key strands (the dark lines) pass, and "
        "the tie goes round them");
  glm::vec3 centre(0.0f), axis_sum(0.0f);
  for (const Hit& h : hits) {
    centre += h.at;
    axis_sum += glm::dot(h.along, hits[0].along) < 0.0f ? -h.along : h.along;
  }
  centre /= static_cast<float>(hits.size());
  const glm::vec3 axis_dir = glm::length(axis_sum) > 1e-6f ? glm::normalize(axis_sum) : hits[0].along;
  float spread = 0.0f;
  for (const Hit& h : hits) {
    const glm::vec3 d = h.at - centre;
    spread = std::max(spread, glm::length(d - glm::dot(d, axis_dir) * axis_dir));
  }
  HairTie tie;
  tie.axis = axis_dir;
  tie.radius = std::clamp(spread + 0.008f, 0.008f, 0.02f);  // a hand's tie: at most 2 cm
  // Hair lying on the head is gathered off it, as a hand does before
  // tying: the ring is moved out until it clears the head by 2 mm, and each
  // key strand it ties gets a control point inside it (within half its
  // radius of the centre, on the strand's side), its points beyond moved
  // as far.
  float phi = 0.0f;
  glm::vec3 normal(0.0f);
  head_->head()->signedDistance(&centre, 1, &phi, &normal);
  if (phi < tie.radius + 0.002f) centre += (tie.radius + 0.002f - phi) * normal;
  tie.center = centre;
  std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> gathered;
  for (const Hit& h : hits) {
    glm::vec3 off = h.at - centre;
    off -= glm::dot(off, axis_dir) * axis_dir;
    const float len = glm::length(off), most = 0.5f * tie.radius;
    if (len > most) off *= most / len;
    // the rest of the strand comes along (the tail hangs from the ring)
    std::vector<glm::vec3> key = wisps[h.wisp].key_strand;
    const glm::vec3 pulled = centre + off, by = pulled - h.at;
    for (std::size_t k = h.span + 1; k < key.size(); ++k) key[k] = editor_.keptOutside(key[k] + by);
    key.insert(key.begin() + static_cast<std::ptrdiff_t>(h.span + 1), pulled);
    gathered.emplace_back(h.wisp, std::move(key));
  }
  // the ring faces the gathered strands as they now run through it
  glm::vec3 along(0.0f);
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const std::vector<glm::vec3>& key = gathered[i].second;
    const std::size_t at = hits[i].span + 1;
    const glm::vec3 d = key[std::min(at + 1, key.size() - 1)] - key[at - 1];
    if (glm::length(d) > 1e-6f) along += glm::dot(d, axis_dir) < 0.0f ? -glm::normalize(d) : glm::normalize(d);
  }
  if (glm::length(along) > 1e-6f) tie.axis = glm::normalize(along);
  return editor_.addTie(tie, std::move(gathered));
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
    if (w.params.strands > 0)
      w.params.strands = std::max(1, static_cast<int>(static_cast<float>(w.params.strands) * preview_density));
  }
  preview_error.clear();
  try {
    // drawn, not simulated: pushed out of the head by the bodies' grids, on
    // the machine's cores (the same strands for any count)
    const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    preview_ = buildMemberStrands(thin, *head_, 0.006f, {}, threads, false);
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
    const glm::vec4 c =
        wisp && *wisp == w ? glm::vec4(kSelected.r, kSelected.g, kSelected.b, 0.6f) : kPalette[w % std::size(kPalette)];
    line.assign(preview_.points.begin() + preview_.first[s], preview_.points.begin() + preview_.first[s + 1]);
    hidden.polyline(line, c);
  }
  // key strands and control points: the selected wisp's over everything,
  // the others hidden by the head as the hair is; what the pointer is over
  // highlighted (a point, an arrow, or a strand between its points)
  const bool hover_valid =
      hover && hover->wisp < wisps.size() && (!hover->point || *hover->point < wisps[hover->wisp].key_strand.size());
  for (std::size_t w = 0; w < wisps.size(); ++w) {
    const bool sel = wisp && *wisp == w;
    const bool hover_strand = hover_valid && !drag_ && hover->wisp == w && !hover->point;
    render::OverlayLines& out = sel || hover_strand ? on_top : hidden;
    out.polyline(sampleKeyStrand(wisps[w].key_strand, 8), hover_strand ? kHover : sel ? kSelected : kKey);
    for (std::size_t k = 0; k < wisps[w].key_strand.size(); ++k) {
      const bool hovered = hover_valid && !hover->handle && hover->wisp == w && hover->point == k;
      const bool chosen = sel && point && *point == k;
      (hovered ? on_top : out)
          .cross(wisps[w].key_strand[k], hovered || chosen ? 0.006f : 0.003f,
                 hovered  ? kHover
                 : chosen ? kSelected
                          : kKey);
    }
  }
  // the three styling directions at the selected point, the active one bright
  if (wisp && point && *wisp < wisps.size() && *point < wisps[*wisp].key_strand.size()) {
    const StylingDirections d = stylingDirections(wisps[*wisp], *point, *head_);
    const glm::vec3 p = wisps[*wisp].key_strand[*point];
    for (int a = 0; a < 3; ++a) {
      const bool active = a == static_cast<int>(axis);
      const bool hovered = hover_valid && hover->handle && static_cast<int>(*hover->handle) == a;
      glm::vec4 c = hovered ? kHover : kAxis[a];
      if (!active && !hovered) c = glm::vec4(glm::vec3(c) * 0.5f + 0.4f, 0.7f);
      on_top.arrow(p, p + (active ? kActiveArrow : kArrow) * d[a], c);
    }
  }
  // the coverage view: scalp points with no root near, as small red crosses
  if (show_coverage) {
    if (!coverage_of_ || !(*coverage_of_ == style())) {
      coverage_of_ = style();
      try {
        // roots at full density; a coarse point spacing, only the roots count
        const StrandSet full = buildMemberStrands(style(), *head_, 0.05f);
        std::vector<glm::vec3> roots;
        for (std::size_t k = 0; k < full.size(); ++k) roots.push_back(full.points[full.first[k]]);
        coverage_ = scalpCoverage(*head_, roots);
      } catch (const std::exception& e) {
        coverage_ = ScalpCoverage{};
        preview_error = e.what();
      }
    }
    for (const glm::vec3& p : coverage_.bare) hidden.cross(p, 0.002f, glm::vec4(0.95f, 0.1f, 0.1f, 1.0f));
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
