#include "loosehair/style_editor.hpp"

#include "init/cantilever.hpp"
#include "init/mesh_scalp.hpp"
#include "style/hair_tie.hpp"
#include "loosehair/strand_brushes.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace loosehair {
namespace {

std::string mm(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f mm", m * 1e3);
  return buf;
}

}  // namespace

StyleEditor::StyleEditor(Style style, const HeadModel& head) : style_(std::move(style)), head_(head) {}

Wisp& StyleEditor::wisp(std::size_t i, const char* what) {
  return const_cast<Wisp&>(static_cast<const StyleEditor&>(*this).wisp(i, what));
}

const Wisp& StyleEditor::wisp(std::size_t i, const char* what) const {
  if (i >= style_.wisps.size())
    throw StyleError(std::string(what) + ": there is no wisp " + std::to_string(i) + " (the style has " +
                     std::to_string(style_.wisps.size()) + ")");
  return style_.wisps[i];
}

void StyleEditor::record() {
  undo_.push_back(style_);
  redo_.clear();
  amendable_.clear();
}

glm::vec3 StyleEditor::keptOutside(glm::vec3 p, float clearance) const { return keptOutsideHead(head_, p, clearance); }

std::vector<glm::vec3> StyleEditor::newKeyStrand(glm::vec2 uv, float length) const {
  if (!(length >= 0.01f && length <= 2.0f))
    throw StyleError("a new wisp's length must be in [0.01, 2] m, got " + std::to_string(length));
  const glm::vec3 root = head_.scalpPoint(uv), n = head_.scalpNormal(uv);
  const glm::vec3 down(0.0f, -1.0f, 0.0f);
  // down the slope of the scalp there, lifted off it a little; on the
  // crown, where the slope is flat, towards the back (-z: the heads face
  // +z), so that it falls rather than standing on end
  const glm::vec3 to_back(0.0f, 0.0f, -1.0f);
  const glm::vec3 slope = down - glm::dot(down, n) * n, back = to_back - glm::dot(to_back, n) * n;
  const float sl = glm::length(slope), bl = glm::length(back);
  const glm::vec3 along = sl > 0.2f ? slope / sl : bl > 1e-3f ? back / bl : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 dir = glm::normalize(along + 0.35f * n);
  UnionBody bodies;
  bodies.add(head_.head());
  if (head_.torso()) bodies.add(head_.torso());
  const SceneDesc defaults;
  const CantileverStrand c(root, dir, down, length, defaults.hair.bending_stiffness, &bodies, kClearance,
                           defaults.hair.layering * 0.25f, 48);
  std::vector<glm::vec3> key;
  constexpr int kPoints = 5;
  for (int k = 0; k < kPoints; ++k)
    key.push_back(k == 0 ? root : keptOutside(c.position(length * static_cast<float>(k) / (kPoints - 1))));
  return key;
}

std::vector<glm::vec3> StyleEditor::dragged(const std::vector<glm::vec3>& key, std::size_t k, glm::vec3 offset,
                                            float falloff) const {
  if (k < 1 || k >= key.size())
    throw StyleError("drag: control point " + std::to_string(k) + " must be in [1, " +
                     std::to_string(key.size() > 0 ? key.size() - 1 : 0) + "] (the root follows the region)");
  if (!std::isfinite(offset.x) || !std::isfinite(offset.y) || !std::isfinite(offset.z) || std::isnan(falloff))
    throw StyleError("drag: the move is not finite");
  std::vector<glm::vec3> out = key;
  float s = 0.0f;
  for (std::size_t j = k; j < key.size(); ++j) {
    if (j > k) s += glm::length(key[j] - key[j - 1]);
    const float w = j == k ? 1.0f : falloff > 0.0f ? std::exp(-s / falloff) : 0.0f;
    if (w <= 0.0f) continue;
    out[j] = keptOutside(key[j] + w * offset);
  }
  return out;
}

void StyleEditor::setKeyStrands(const std::vector<std::vector<glm::vec3>>& keys) {
  if (keys.size() != style_.wisps.size())
    throw StyleError("setKeyStrands: " + std::to_string(keys.size()) + " key strands for " +
                     std::to_string(style_.wisps.size()) + " wisps");
  std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> all;
  for (std::size_t i = 0; i < keys.size(); ++i) all.emplace_back(i, keys[i]);
  setKeyStrandsOf(std::move(all));
}

void StyleEditor::setKeyStrand(std::size_t i, std::vector<glm::vec3> key, bool amend) {
  setKeyStrandsOf({{i, std::move(key)}}, amend);
}

void StyleEditor::setKeyStrandsOf(std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> keys, bool amend) {
  const std::vector<std::size_t> which = preparedKeys(keys);
  const bool joins = amend && !which.empty() && amendable_ == which && !undo_.empty();
  if (!joins) record();
  for (auto& [i, key] : keys) style_.wisps[i].key_strand = std::move(key);
  amendable_ = which;
}

std::vector<std::size_t> StyleEditor::preparedKeys(
    std::vector<std::pair<std::size_t, std::vector<glm::vec3>>>& keys) const {
  std::vector<std::size_t> which;
  for (auto& [i, key] : keys) {
    const Wisp& w = wisp(i, "setKeyStrand");
    if (key.size() < 2) throw StyleError("setKeyStrand: a key strand needs at least two control points");
    key[0] = w.key_strand[0];
    for (std::size_t k = 1; k < key.size(); ++k) {
      checkPoint(i, k, key[k]);
      if (glm::length(key[k] - key[k - 1]) < 1e-5f)
        throw StyleError("setKeyStrand: control points " + std::to_string(k - 1) + " and " + std::to_string(k) +
                         " would coincide");
    }
    // the given points are outside (checked): only the spline between
    // them is mended, with points pushed out (no two of them coincide)
    key = keyStrandKeptOutside(std::move(key), head_, kClearance);
    which.push_back(i);
  }
  std::sort(which.begin(), which.end());
  if (std::adjacent_find(which.begin(), which.end()) != which.end())
    throw StyleError("setKeyStrand: a wisp given twice in one edit");
  return which;
}

std::optional<std::size_t> StyleEditor::mirrorPartner(std::size_t i, float tolerance) const {
  if (i >= style_.wisps.size()) throw StyleError("mirrorPartner: there is no wisp " + std::to_string(i));
  const float c = head_.mirrorPlaneX();
  const glm::vec3 r = style_.wisps[i].key_strand[0], m(c - (r.x - c), r.y, r.z);
  std::optional<std::size_t> best;
  float best_d = tolerance;
  for (std::size_t j = 0; j < style_.wisps.size(); ++j) {
    if (j == i) continue;
    const float d = glm::length(style_.wisps[j].key_strand[0] - m);
    if (d <= best_d) best_d = d, best = j;
  }
  return best;
}

std::vector<glm::vec3> StyleEditor::mirroredOnto(const std::vector<glm::vec3>& from, std::size_t p) const {
  if (p >= style_.wisps.size()) throw StyleError("mirroredOnto: there is no wisp " + std::to_string(p));
  if (from.size() < 2) throw StyleError("mirroredOnto: a key strand needs at least two control points");
  const glm::vec3 root = style_.wisps[p].key_strand[0];
  std::vector<glm::vec3> out(from.size());
  out[0] = root;
  for (std::size_t k = 1; k < from.size(); ++k) {
    const glm::vec3 d = from[k] - from[0];
    out[k] = keptOutside(root + glm::vec3(-d.x, d.y, d.z));
  }
  return out;
}

void StyleEditor::checkPoint(std::size_t w, std::size_t k, glm::vec3 p) const {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    throw StyleError("wisps[" + std::to_string(w) + "].key_strand[" + std::to_string(k) + "]: not a finite point");
  if (glm::length(p) > kMaxStyleCoordinate)
    throw StyleError("wisps[" + std::to_string(w) + "].key_strand[" + std::to_string(k) + "]: would lie " +
                     std::to_string(static_cast<int>(std::min(glm::length(p), 1e9f))) +
                     " m from the head's origin, beyond the " + std::to_string(static_cast<int>(kMaxStyleCoordinate)) +
                     " m a style allows");
  const float phi = head_.headDistance(p);
  if (phi < -1e-3f)
    throw StyleError("wisps[" + std::to_string(w) + "].key_strand[" + std::to_string(k) + "]: would lie " + mm(-phi) +
                     " inside the head");
}

namespace {
void checkRegion(const WispRegion& r, const HeadModel& head, const std::string& field) {
  const std::size_t n = head.scalpTriangles().triangles.size();
  for (std::uint32_t t : r.triangles)
    if (t >= n)
      throw StyleError(field + ": triangle " + std::to_string(t) + " is off the scalp (" + std::to_string(n) +
                       " triangles)");
  for (const auto& poly : r.polygons) {
    if (poly.size() < 3) throw StyleError(field + ": a polygon needs at least 3 points");
    for (const glm::vec2 q : poly)
      if (!(q.x >= 0 && q.x <= 1 && q.y >= 0 && q.y <= 1))
        throw StyleError(field + ": a polygon point lies off the scalp square");
  }
  if (r.empty() || !(regionArea(r, head) > 0.0)) throw StyleError(field + ": covers no part of the scalp");
}
WispRegion normalised(WispRegion r) {
  std::sort(r.triangles.begin(), r.triangles.end());
  r.triangles.erase(std::unique(r.triangles.begin(), r.triangles.end()), r.triangles.end());
  return r;
}
// A wisp's parameters as a style file's wisp must have them (the reader's
// own checks, checkWispValue), so that nothing a file refuses gets in here.
void checkParams(const WispParams& p, const std::string& where) {
  checkWispValue("density", p.density, where);
  checkWispValue("strands", p.strands, where);
  checkWispValue("offset_radius", p.offset_radius, where);
  checkWispValue("length_variation", p.length_variation, where);
  checkWispValue("curl_radius", p.curl_radius, where);
  checkWispValue("curl_period", p.curl_period, where);
  checkWispValue("blend", p.blend, where);
  checkWispValue("edge_ramp", p.edge_ramp, where);
}

}  // namespace

std::size_t StyleEditor::createWisp(const WispRegion& region_in, const WispParams& params,
                                    const std::vector<glm::vec3>& key, const std::string& name, float length) {
  const WispRegion region = normalised(region_in);
  const std::size_t index = style_.wisps.size();
  checkRegion(region, head_, "createWisp: region");
  const glm::vec2 uv = regionRoot(region, head_);
  const glm::vec3 root = head_.scalpPoint(uv);
  Wisp w;
  w.name = name.empty() ? "wisp " + std::to_string(index) : name;
  w.region = region;
  checkParams(params, "createWisp");
  w.params = params;
  if (key.empty()) {
    w.key_strand = newKeyStrand(uv, length);
    w.key_strand[0] = root;
  } else {
    if (key.size() < 2) throw StyleError("createWisp: a key strand needs at least two control points");
    for (const glm::vec3& c : key) w.key_strand.push_back(c - key[0] + root);
    w.key_strand[0] = root;
  }
  for (std::size_t k = 1; k < w.key_strand.size(); ++k) checkPoint(index, k, w.key_strand[k]);
  w.key_strand = keyStrandKeptOutside(std::move(w.key_strand), head_, kClearance);
  record();
  style_.wisps.push_back(std::move(w));
  return index;
}

void StyleEditor::deleteWisp(std::size_t i) {
  wisp(i, "deleteWisp");
  record();
  style_.wisps.erase(style_.wisps.begin() + static_cast<std::ptrdiff_t>(i));
}

void StyleEditor::setRegion(std::size_t i, const WispRegion& region_in) {
  Wisp& w = wisp(i, "setRegion");
  const WispRegion region = normalised(region_in);
  checkRegion(region, head_, "setRegion: region");
  const glm::vec2 from = regionRoot(w.region, head_), to = regionRoot(region, head_);
  const std::vector<glm::vec3> key = reRootKeyStrand(w.key_strand, head_, from, head_, to);
  for (std::size_t k = 1; k < key.size(); ++k) checkPoint(i, k, key[k]);
  record();
  Wisp& v = style_.wisps[i];
  v.region = region;
  v.key_strand = keyStrandKeptOutside(key, head_, kClearance);
}

void StyleEditor::setParams(std::size_t i, const WispParams& p) {
  wisp(i, "setParams");
  const std::string f = "wisps[" + std::to_string(i) + "]";
  checkParams(p, f);
  record();
  style_.wisps[i].params = p;
}

void StyleEditor::setParamsOf(const std::vector<std::pair<std::size_t, WispParams>>& params) {
  for (const auto& [i, p] : params) {
    wisp(i, "setParams");
    checkParams(p, "wisps[" + std::to_string(i) + "]");
  }
  if (params.empty()) return;
  record();
  for (const auto& [i, p] : params) style_.wisps[i].params = p;
}

void StyleEditor::renameWisp(std::size_t i, const std::string& name) {
  wisp(i, "renameWisp");
  record();
  style_.wisps[i].name = name;
}

std::size_t StyleEditor::mirrorWisp(std::size_t i) {
  const Wisp& w = wisp(i, "mirrorWisp");
  const float c = head_.mirrorPlaneX();
  auto mirror = [c](glm::vec3 p) { return glm::vec3(c - (p.x - c), p.y, p.z); };
  Wisp m = w;
  m.name = w.name + " (mirrored)";
  m.region.triangles.clear();
  const ScalpTriangles& s = head_.scalpTriangles();
  for (std::uint32_t t : w.region.triangles) {
    const auto tr = s.triangles[t];
    const glm::vec3 centre = (s.positions[tr.x] + s.positions[tr.y] + s.positions[tr.z]) / 3.0f;
    m.region.triangles.push_back(head_.scalpTriangleAt(head_.nearestScalpUv(mirror(centre))));
  }
  m.region = normalised(m.region);
  for (auto& poly : m.region.polygons) {
    for (glm::vec2& q : poly) q.x = 1.0f - q.x;
    std::reverse(poly.begin(), poly.end());
  }
  for (glm::vec3& p : m.key_strand) p = mirror(p);
  m.key_strand[0] = head_.scalpPoint(regionRoot(m.region, head_));
  const std::size_t index = style_.wisps.size();
  for (std::size_t k = 1; k < m.key_strand.size(); ++k) checkPoint(index, k, m.key_strand[k]);
  m.key_strand = keyStrandKeptOutside(std::move(m.key_strand), head_, kClearance);
  record();
  style_.wisps.push_back(std::move(m));
  return index;
}

void StyleEditor::addControlPoint(std::size_t i, std::size_t k, std::optional<glm::vec3> point) {
  const Wisp& w = wisp(i, "addControlPoint");
  const std::size_t n = w.key_strand.size();
  if (k < 1 || k > n)
    throw StyleError("addControlPoint: index " + std::to_string(k) + " must be in [1, " + std::to_string(n) +
                     "] (the root stays first)");
  glm::vec3 p;
  if (point) {
    p = *point;
  } else if (k == n) {
    p = keptOutside(w.key_strand[n - 1] + (w.key_strand[n - 1] - w.key_strand[n - 2]));
  } else {
    const std::vector<glm::vec3> dense = catmullRom(w.key_strand, 2);  // midpoints of the spans
    p = dense[2 * (k - 1) + 1];
  }
  checkPoint(i, k, p);
  record();
  auto& key = style_.wisps[i].key_strand;
  key.insert(key.begin() + static_cast<std::ptrdiff_t>(k), p);
  key = keyStrandKeptOutside(std::move(key), head_, kClearance);
}

void StyleEditor::deleteControlPoint(std::size_t i, std::size_t k) {
  const Wisp& w = wisp(i, "deleteControlPoint");
  if (k < 1 || k >= w.key_strand.size())
    throw StyleError("deleteControlPoint: index " + std::to_string(k) + " must be in [1, " +
                     std::to_string(w.key_strand.size() - 1) + "] (the root follows the region)");
  if (w.key_strand.size() <= 2) throw StyleError("deleteControlPoint: a key strand keeps at least two control points");
  record();
  auto& key = style_.wisps[i].key_strand;
  key.erase(key.begin() + static_cast<std::ptrdiff_t>(k));
}

void StyleEditor::moveControlPoint(std::size_t i, std::size_t k, StylingAxis axis, float distance) {
  const Wisp& w = wisp(i, "moveControlPoint");
  if (k < 1 || k >= w.key_strand.size())
    throw StyleError("moveControlPoint: index " + std::to_string(k) + " must be in [1, " +
                     std::to_string(w.key_strand.size() - 1) + "] (the root follows the region)");
  if (!std::isfinite(distance)) throw StyleError("moveControlPoint: the distance is not finite");
  const StylingDirections d = stylingDirections(w, k, head_);
  setControlPoint(i, k, w.key_strand[k] + distance * d[static_cast<int>(axis)]);
}

void StyleEditor::setControlPoint(std::size_t i, std::size_t k, glm::vec3 p) {
  const Wisp& w = wisp(i, "setControlPoint");
  if (k < 1 || k >= w.key_strand.size())
    throw StyleError("setControlPoint: index " + std::to_string(k) + " must be in [1, " +
                     std::to_string(w.key_strand.size() - 1) + "] (the root follows the region)");
  if (glm::length(p - w.key_strand[k - 1]) < 1e-5f)
    throw StyleError("setControlPoint: the point would coincide with the previous control point");
  checkPoint(i, k, p);
  record();
  auto& key = style_.wisps[i].key_strand;
  key[k] = p;
  key = keyStrandKeptOutside(std::move(key), head_, kClearance);
}

void StyleEditor::copyKeyStrand(std::size_t i) {
  const Wisp& w = wisp(i, "copyKeyStrand");
  clipboard_ = Clip{w.key_strand, regionRoot(w.region, head_)};
}

void StyleEditor::pasteKeyStrand(std::size_t i) {
  const Wisp& w = wisp(i, "pasteKeyStrand");
  if (!clipboard_) throw StyleError("pasteKeyStrand: nothing was copied");
  const std::vector<glm::vec3> key =
      reRootKeyStrand(clipboard_->key, head_, clipboard_->root_uv, head_, regionRoot(w.region, head_));
  for (std::size_t k = 1; k < key.size(); ++k) checkPoint(i, k, key[k]);
  record();
  style_.wisps[i].key_strand = keyStrandKeptOutside(key, head_, kClearance);
}

namespace {
// The ranges of a tie's numbers, as the style file has them.
void checkTieValues(const char* operation, const HairTie& tie) {
  if (!(tie.radius >= 1e-3f && tie.radius <= 0.2f) || !(tie.width >= 1e-3f && tie.width <= 0.2f) ||
      !(glm::length(tie.axis) > 0.5f && glm::length(tie.axis) < 1.5f) || !(tie.hold >= 0.0f && tie.hold <= 50.0f))
    throw StyleError(std::string(operation) +
                     ": radius and width must be in [0.001, 0.2] m, the axis a unit vector and the hold in [0, 50] Hz");
}
}  // namespace

void StyleEditor::checkTie(const char* what, const HairTie& tie, const Style& style) const {
  checkTieValues(what, tie);
  HairTie t = tie;
  t.axis = glm::normalize(t.axis);
  if (!tieHoldsAKeyStrand(style, t))
    throw StyleError(
        "a tie must hold hair: no wisp's key strand passes through a ring there; place it where the "
        "key strands pass (the tie tool: click on them), not at a strand's tip");
  const float phi = head_.headDistance(t.center);
  if (phi < t.radius)
    throw StyleError(std::string(what) + ": the ring (radius " + mm(t.radius) +
                     ") would reach into the head, its centre " + "being " + mm(phi) +
                     " from it; gather the hair away from the head first, or use a smaller ring");
}

std::size_t StyleEditor::addTie(const HairTie& tie,
                                std::vector<std::pair<std::size_t, std::vector<glm::vec3>>> gathered) {
  (void)preparedKeys(gathered);
  Style with = style_;
  for (auto& [i, key] : gathered) with.wisps[i].key_strand = key;
  checkTie("addTie", tie, with);
  HairTie t = tie;
  t.axis = glm::normalize(t.axis);
  record();
  for (auto& [i, key] : gathered) style_.wisps[i].key_strand = std::move(key);
  if (t.name.empty()) t.name = "tie " + std::to_string(style_.ties.size());
  style_.ties.push_back(t);
  return style_.ties.size() - 1;
}

void StyleEditor::deleteTie(std::size_t j) {
  if (j >= style_.ties.size()) throw StyleError("deleteTie: there is no tie " + std::to_string(j));
  record();
  style_.ties.erase(style_.ties.begin() + static_cast<std::ptrdiff_t>(j));
}

void StyleEditor::setTie(std::size_t j, const HairTie& value) {
  if (j >= style_.ties.size()) throw StyleError("setTie: there is no tie " + std::to_string(j));
  Style without = style_;
  without.ties.erase(without.ties.begin() + static_cast<std::ptrdiff_t>(j));
  checkTie("setTie", value, without);
  record();
  style_.ties[j] = value;
  style_.ties[j].axis = glm::normalize(value.axis);
}

void StyleEditor::setColour(glm::vec3 c) {
  if (!(c.x >= 0 && c.x <= 1 && c.y >= 0 && c.y <= 1 && c.z >= 0 && c.z <= 1))
    throw StyleError("setColour: the colour must be linear RGB in [0, 1]");
  record();
  style_.colour = c;
}

void StyleEditor::setShapeKeeping(float hz) {
  if (!(hz >= 0 && hz <= 100)) throw StyleError("setShapeKeeping: must be in [0, 100] Hz");
  record();
  style_.shape_keeping = hz;
}

bool StyleEditor::undo() {
  amendable_.clear();
  if (undo_.empty()) return false;
  redo_.push_back(std::move(style_));
  style_ = std::move(undo_.back());
  undo_.pop_back();
  return true;
}

bool StyleEditor::redo() {
  amendable_.clear();
  if (redo_.empty()) return false;
  undo_.push_back(std::move(style_));
  style_ = std::move(redo_.back());
  redo_.pop_back();
  return true;
}

}  // namespace loosehair
