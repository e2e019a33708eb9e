// Small styles on the sphere head of lhtest::sphereScene (fast enough for the
// sanitizer run), shared by the styling and shape-keeping tests.
#pragma once

#include "loosehair/head_model.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lhtest::styles {

using namespace loosehair;

inline HeadDesc sphereHead() {
  HeadDesc h;
  h.head_kind = HeadKind::Sphere;
  h.head_center = glm::vec3(0.0f);
  h.head_radius = 0.1f;
  h.scalp_kind = ScalpKind::SphereCap;
  h.cap_angle_deg = 100.0f;
  return h;
}

inline const HeadModel& sphereModel() {
  static const HeadModel m = HeadModel::build(sphereHead(), "sphere-test");
  return m;
}

// The largest turn between consecutive spans of a key strand (degrees).
inline float sharpestTurn(const std::vector<glm::vec3>& key) {
  float worst = 0.0f;
  for (std::size_t k = 1; k + 1 < key.size(); ++k) {
    const glm::vec3 a = glm::normalize(key[k] - key[k - 1]), b = glm::normalize(key[k + 1] - key[k]);
    worst = std::max(worst, glm::degrees(std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f))));
  }
  return worst;
}

// A style on the sphere head with no wisps yet, as the styling mode starts one.
inline Style emptyStyle() {
  Style s;
  s.source = "test-style";
  s.name = "empty";
  s.head = sphereHead();
  return s;
}

inline WispRegion square(glm::vec2 lo, glm::vec2 hi) {
  WispRegion r;
  r.polygons.push_back({lo, {hi.x, lo.y}, hi, {lo.x, hi.y}});
  return r;
}

// A strand from the root outwards along the normal, then away from the
// crown and down, clear of the sphere.
inline std::vector<glm::vec3> hangingKey(const HeadModel& h, glm::vec2 uv) {
  const glm::vec3 r = h.scalpPoint(uv), n = h.scalpNormal(uv);
  glm::vec3 out(n.x, 0.0f, n.z);
  out = glm::length(out) > 0.1f ? glm::normalize(out) : glm::vec3(1, 0, 0);
  return {r, r + 0.02f * n, r + 0.03f * n + 0.05f * out, r + 0.03f * n + 0.1f * out + glm::vec3(0, -0.06f, 0)};
}

inline Style twoWispStyle() {
  const HeadModel& h = sphereModel();
  Style s;
  s.source = "test-style";
  s.name = "two";
  s.head = sphereHead();
  StyleEditor ed(s, h);
  WispParams p;
  p.density = 15.0f;
  p.offset_radius = 0.008f;
  ed.createWisp(square({0.15f, 0.3f}, {0.35f, 0.6f}), p);
  ed.createWisp(square({0.45f, 0.45f}, {0.6f, 0.7f}), p);
  Style out = ed.style();
  out.wisps[0].key_strand = hangingKey(h, regionRoot(out.wisps[0].region, h));
  out.wisps[1].key_strand = hangingKey(h, regionRoot(out.wisps[1].region, h));
  return out;
}

// One wisp of a small region whose key strand rises from near the crown
// (translated copies stay off the sphere), without length variation.
inline Style upwardWisp(float offset_radius, int strands) {
  const HeadModel& h = sphereModel();
  Style s = twoWispStyle();
  s.wisps.resize(1);
  Wisp& w = s.wisps[0];
  w.params.offset_radius = offset_radius;
  w.params.length_variation = 0.0f;
  w.params.strands = strands;
  const glm::vec2 uv = regionRoot(w.region, h);
  w.region = square(uv - glm::vec2(0.02f), uv + glm::vec2(0.02f));
  const glm::vec3 r = h.scalpPoint(regionRoot(w.region, h));
  w.key_strand = {r, r + glm::vec3(0, 0.05f, 0), r + glm::vec3(0.01f, 0.1f, 0.0f)};
  return s;
}

// A wisp rooted around the crown whose strands run over the back of the
// head through a tie behind it and hang below: a ponytail on the sphere.
inline Style tiedStyle(float tie_hold) {
  const HeadModel& h = sphereModel();
  Style s;
  s.source = "tied-test-style";
  s.name = "tied";
  s.head = sphereHead();
  HairTie tie;
  tie.name = "tie";
  tie.center = glm::vec3(0.0f, -0.02f, -0.122f);
  tie.axis = glm::vec3(0, -1, 0);
  tie.radius = 0.015f;
  tie.width = 0.01f;
  tie.hold = tie_hold;
  StyleEditor ed(s, h);
  WispParams p;
  p.density = 25.0f;
  p.offset_radius = 0.006f;
  p.length_variation = 0.05f;
  const WispRegion region = square({0.4f, 0.4f}, {0.6f, 0.6f});
  const glm::vec2 uv = regionRoot(region, h);
  const glm::vec3 r = h.scalpPoint(uv), n = h.scalpNormal(uv);
  std::vector<glm::vec3> key{r, r + 0.015f * n};
  for (float deg : {35.0f, 60.0f, 85.0f}) {  // over the back at 11.8 cm from the centre
    const float a = glm::radians(deg);
    key.push_back(0.118f * glm::vec3(0.0f, std::cos(a), -std::sin(a)));
  }
  key.push_back(tie.center);
  for (float y : {-0.07f, -0.12f, -0.17f}) key.push_back(glm::vec3(0.0f, y, -0.128f));
  ed.createWisp(region, p, key, "tail");
  ed.addTie(tie);
  return ed.style();
}

}  // namespace lhtest::styles
