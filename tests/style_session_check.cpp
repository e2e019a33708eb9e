// The API side of the viewer's scripted styling session
// (tests/viewer/styling-session.json): the same operations made with the
// library (StyleEditor, ray picking through the same camera) must give the
// style file the viewer saved, byte for byte.
//
//   loosehair_style_session_check SCENE WIDTH HEIGHT VIEWER_STYLE.json
//   loosehair_style_session_check --hair-pixels SIMULATED.png BARE.png
//   loosehair_style_session_check --drags DIR
//   loosehair_style_session_check --tie STYLE.json
//   loosehair_style_session_check --bob STYLE.json
//   loosehair_style_session_check --ponytail STYLE.json
// The third form checks the styles tests/viewer/styling-drag.json saved in
// DIR (drag-0.json ... drag-3.json, drag-settled.json): a new wisp that
// hangs clear of the head; a control point dragged in the view plane with
// the points after it following less and less; one dragged along its normal
// arrow; the whole key strand dragged by its middle; then settled lower.
// The second form checks that a picture shows hair: its share of
// hair-coloured pixels where the bare head's picture (same view) shows
// something else is above 2%.
#include "loosehair/file_io.hpp"
#include "loosehair/head_landmarks.hpp"
#include "loosehair/scalp_coverage.hpp"
#include "loosehair/ray_pick.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/style_editor.hpp"

#include <glm/geometric.hpp>
#include <stb/stb_image.h>

#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace loosehair;

namespace {

struct Picture {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
};

Picture readPng(const char* path) {
  Picture p;
  int n = 0;
  unsigned char* px = stbi_load(path, &p.w, &p.h, &n, 3);
  if (!px) throw std::runtime_error(std::string(path) + ": cannot read the PNG");
  p.rgb.assign(px, px + 3 * p.w * p.h);
  stbi_image_free(px);
  return p;
}

// Pixels of `a` that are hair-coloured (brown: red well over blue, green
// between, darker than lit skin) where `b` (the same view without hair)
// shows something else.
double newHairShare(const Picture& a, const Picture& b) {
  if (a.w != b.w || a.h != b.h) throw std::runtime_error("the two pictures differ in size");
  std::size_t hair = 0;
  for (int i = 0; i < a.w * a.h; ++i) {
    const int r = a.rgb[3 * i], g = a.rgb[3 * i + 1], bl = a.rgb[3 * i + 2];
    const int diff = std::abs(r - b.rgb[3 * i]) + std::abs(g - b.rgb[3 * i + 1]) + std::abs(bl - b.rgb[3 * i + 2]);
    hair += (r >= 20 && r <= 180 && 10 * r > 14 * bl && g <= r && g >= bl && diff > 40) ? 1 : 0;
  }
  return static_cast<double>(hair) / static_cast<double>(std::max(1, a.w * a.h));
}

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

// The drags of tests/viewer/styling-drag.json, checked on the styles saved
// after each.
int checkDrags(const std::string& dir) {
  const Style s0 = loadStyle(dir + "/drag-0.json"), s1 = loadStyle(dir + "/drag-1.json"),
              s2 = loadStyle(dir + "/drag-2.json"), s3 = loadStyle(dir + "/drag-3.json");
  const HeadModel head = HeadModel::build(s0.head, s0.source);
  if (s0.wisps.size() != 1) fail("drag-0.json: one wisp expected, got " + std::to_string(s0.wisps.size()));
  const auto& k0 = s0.wisps[0].key_strand;
  const auto& k1 = s1.wisps.at(0).key_strand;
  const auto& k2 = s2.wisps.at(0).key_strand;
  const auto& k3 = s3.wisps.at(0).key_strand;
  if (k0.size() < 5 || k1.size() != k0.size() || k2.size() != k0.size() || k3.size() != k0.size())
    fail("the key strands should keep " + std::to_string(k0.size()) + " (>= 5) control points");
  // a new wisp hangs: below its root at the tip, clear of the head
  if (!(k0.back().y < k0.front().y - 0.05f)) fail("drag-0.json: the new wisp's tip is not below its root");
  for (const auto* k : {&k0, &k1, &k2, &k3})
    for (std::size_t j = 1; j < k->size(); ++j)
      if (!(head.headDistance((*k)[j]) > 0.0f)) fail("a control point inside the head after a drag");
  auto moved = [](const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b, std::size_t j) {
    return glm::length(b[j] - a[j]);
  };
  // 1: point 2 dragged across the view, the points after it following less and less
  for (std::size_t j = 0; j < 2; ++j)
    if (moved(k0, k1, j) != 0.0f) fail("drag 1 moved point " + std::to_string(j) + ", before the dragged one");
  if (!(moved(k0, k1, 2) > 0.01f)) fail("drag 1 moved point 2 by only " + std::to_string(moved(k0, k1, 2)) + " m");
  for (std::size_t j = 3; j < k0.size(); ++j)
    if (!(moved(k0, k1, j) > 0.0f && moved(k0, k1, j) < moved(k0, k1, j - 1)))
      fail("drag 1: point " + std::to_string(j) + " did not follow point " + std::to_string(j - 1) + " with less");
  // 2: point 3 along its normal arrow only
  const glm::vec3 n = stylingDirections(s1.wisps[0], 3, head).normal;
  const glm::vec3 d2 = k2[3] - k1[3];
  if (!(glm::length(d2) > 0.005f)) fail("drag 2 moved point 3 by only " + std::to_string(glm::length(d2)) + " m");
  if (!(glm::length(glm::cross(d2, n)) < 0.02f * glm::length(d2)))
    fail("drag 2 moved point 3 off its normal direction");
  for (std::size_t j = 0; j < 3; ++j)
    if (moved(k1, k2, j) != 0.0f) fail("drag 2 moved point " + std::to_string(j));
  // 3: the whole strand but its root, by one offset
  if (moved(k2, k3, 0) != 0.0f) fail("drag 3 moved the root");
  const glm::vec3 d3 = k3[1] - k2[1];
  if (!(glm::length(d3) > 0.005f)) fail("drag 3 did not move the strand");
  for (std::size_t j = 2; j < k0.size(); ++j)
    if (glm::length((k3[j] - k2[j]) - d3) > 1e-4f)
      fail("drag 3 moved point " + std::to_string(j) + " by another offset");
  // the settle: the strand's hair came to rest under gravity, lower
  const Style s4 = loadStyle(dir + "/drag-settled.json");
  const auto& k4 = s4.wisps.at(0).key_strand;
  // (it may add control points where the settled spline would cut into the head)
  if (k4.size() < k3.size() || k4[0] != k3[0]) fail("the settle changed the root or lost control points");
  for (std::size_t j = 1; j < k4.size(); ++j)
    if (!(head.headDistance(k4[j]) > 0.0f)) fail("a settled control point inside the head");
  if (!(k4.back().y < k3.back().y)) fail("the settled tip is not lower than the dragged one");
  // mirrored editing: the partner is the mirror image after a drag and a
  // comb stroke; the comb kept the spans and moved the strand
  const Style s5 = loadStyle(dir + "/drag-mirror.json"), s6 = loadStyle(dir + "/drag-comb.json");
  // (the partner's root is its own region's, near the mirror image of wisp
  // 0's; the shape from the root is the mirror image)
  for (const Style* s : {&s5, &s6}) {
    if (s->wisps.size() != 2) fail("mirrored editing: two wisps expected");
    const auto& a = s->wisps[0].key_strand;
    const auto& b = s->wisps[1].key_strand;
    for (std::size_t j = 1; j < a.size(); ++j) {
      const glm::vec3 da = a[j] - a[0], db = b[j] - b[0];
      if (glm::length(db - glm::vec3(-da.x, da.y, da.z)) > 2e-3f)
        fail("mirrored editing: wisp 1's point " + std::to_string(j) + " is not wisp 0's mirror image");
    }
  }
  const auto& m0 = s5.wisps[0].key_strand;
  const auto& c0 = s6.wisps[0].key_strand;
  float combed = 0.0f;
  for (std::size_t j = 1; j < c0.size(); ++j) {
    combed = std::max(combed, glm::length(c0[j] - m0[j]));
    if (std::abs(glm::length(c0[j] - c0[j - 1]) - glm::length(m0[j] - m0[j - 1])) > 5e-4f)
      fail("the comb changed span " + std::to_string(j) + "'s length");
  }
  if (!(combed > 0.002f)) fail("the comb did not move the strand");
  std::printf(
      "drags: point 2 by %.1f mm (point %zu by %.1f mm), point 3 along its normal by %.1f mm, the strand by "
      "%.1f mm; the settle lowered the tip by %.1f mm; mirrored; the comb moved a point by %.1f mm\n",
      1e3f * moved(k0, k1, 2), k0.size() - 1, 1e3f * moved(k0, k1, k0.size() - 1), 1e3f * glm::length(d2),
      1e3f * glm::length(d3), 1e3f * (k3.back().y - k4.back().y), 1e3f * combed);
  return 0;
}

// The member strands that cross the tie's plane inside its ring (those of
// each wisp, if asked).
std::size_t heldByTie(const StrandSet& m, const HairTie& t, std::vector<std::size_t>* missed = nullptr) {
  const glm::vec3 a = glm::normalize(t.axis);
  std::size_t held = 0;
  for (std::size_t k = 0; k < m.size(); ++k) {
    bool through = false;
    for (std::uint32_t q = m.first[k] + 1; q < m.first[k + 1] && !through; ++q) {
      const float d0 = glm::dot(m.points[q - 1] - t.center, a), d1 = glm::dot(m.points[q] - t.center, a);
      if ((d0 < 0.0f) == (d1 < 0.0f)) continue;
      const glm::vec3 x = m.points[q - 1] + (d0 / (d0 - d1)) * (m.points[q] - m.points[q - 1]);
      through = glm::length(x - t.center) <= t.radius;
    }
    held += through ? 1 : 0;
    if (!through && missed) {
      if (missed->size() <= m.wisp[k]) missed->resize(m.wisp[k] + 1, 0);
      ++(*missed)[m.wisp[k]];
    }
  }
  return held;
}

// tests/viewer/styling-tie.json: the style's tie, placed with the tie tool,
// holds every member strand of its two wisps (each crosses the ring's plane
// inside the ring).
int checkTie(const std::string& path) {
  const Style s = loadStyle(path);
  if (s.ties.size() != 1 || s.wisps.size() != 2) fail(path + ": one tie and two wisps expected");
  const HeadModel head = HeadModel::build(s.head, s.source);
  const StrandSet m = buildMemberStrands(s, head);
  const HairTie& t = s.ties[0];
  const std::size_t held = heldByTie(m, t);
  std::printf("the tie holds %zu of %zu member strands (ring radius %.1f mm)\n", held, m.size(), 1e3f * t.radius);
  if (held != m.size()) fail("the tie does not hold every member strand");
  return 0;
}

// The share of the scalp with a member root within 5 mm.
float coveredShare(const HeadModel& head, const StrandSet& m) {
  std::vector<glm::vec3> roots;
  for (std::size_t k = 0; k < m.size(); ++k) roots.push_back(m.points[m.first[k]]);
  return static_cast<float>(scalpCoverage(head, roots).covered);
}

// How far the member strands stand off the head and torso: the largest
// distance of any of their points (m).
float standOff(const HeadModel& head, const StrandSet& m) {
  float worst = 0.0f;
  for (const glm::vec3& p : m.points) {
    float d = head.headDistance(p);
    if (head.torso()) {
      float phi;
      glm::vec3 n;
      head.torso()->signedDistance(&p, 1, &phi, &n);
      d = std::min(d, phi);
    }
    worst = std::max(worst, d);
  }
  return worst;
}

// tests/viewer/styling-bob.json: a bob made with the mouse from an empty
// style. The strands ending in front of the face (the fringe: within
// 4.5 cm of the middle, 6 cm forward) end above the ears' top; of the others (the style has no level cut: a member
// follows its key strand from its own root, so the ends spread with the roots' heights) 90% end between 2 cm below the
// chin and the ears' bottom and all above the shoulders (10 cm below the chin); nothing stands more than 5 cm off the
// head; the hair covers 75% of the scalp (the script leaves the very top and a band behind the ears bare).
int checkBob(const std::string& path) {
  const Style s = loadStyle(path);
  const HeadModel head = HeadModel::build(s.head, s.source);
  const HeadHeights at = measureHeadHeights(head.headMesh());
  const StrandSet m = buildMemberStrands(s, head);
  std::size_t fringe_low = 0;
  std::vector<float> ends, fringe;
  for (std::size_t k = 0; k < m.size(); ++k) {
    const glm::vec3 tip = m.points[m.first[k + 1] - 1];
    if (tip.z > 0.06f && std::abs(tip.x) < 0.045f) {  // in front of the face
      fringe.push_back(tip.y);
      fringe_low += tip.y < at.ear_top ? 1 : 0;
    } else {
      ends.push_back(tip.y);
    }
  }
  if (ends.empty() || fringe.empty()) fail("a bob with a fringe is made of both");
  std::sort(ends.begin(), ends.end());
  const auto share = [&](float from, float to) {
    return static_cast<double>(std::count_if(ends.begin(), ends.end(), [&](float y) { return y >= from && y <= to; })) /
           static_cast<double>(ends.size());
  };
  const double in_line = share(at.chin - 0.02f, at.ear_bottom);
  const float off = standOff(head, m);
  const float covered = coveredShare(head, m);
  std::printf(
      "bob: %zu wisps, %zu strands (%zu of the fringe, %zu of them below the ears' top); the others end at "
      "%.3f..%.3f m, %.1f%% between %.3f (2 cm below the chin) and %.3f (the ears' bottom); at most %.1f mm "
      "off the head; scalp covered %.1f%%\n",
      s.wisps.size(), m.size(), fringe.size(), fringe_low, ends.front(), ends.back(), 100 * in_line, at.chin - 0.02f,
      at.ear_bottom, 1e3f * off, 100.0f * covered);
  if (fringe_low > 0) fail("the fringe reaches below the ears' top");
  if (in_line < 0.9) fail("fewer than 90% of the ends lie between the chin and the ears");
  if (ends.front() < at.chin - 0.1f) fail("ends reach the shoulders");
  if (off > 0.05f) fail("hair stands more than 5 cm off the head");
  if (covered < 0.75f) fail("the hair covers less than 75% of the scalp");
  return 0;
}

// tests/viewer/styling-ponytail.json: a ponytail made with the mouse from
// an empty style: every member strand passes through the tie's ring, the
// ring is behind the head, and the hair covers 75% of the scalp (the
// script leaves the nape below the ears bare).
int checkPonytail(const std::string& path) {
  const Style s = loadStyle(path);
  if (s.ties.size() != 1) fail(path + ": one tie expected");
  const HeadModel head = HeadModel::build(s.head, s.source);
  const StrandSet m = buildMemberStrands(s, head);
  const HairTie& t = s.ties[0];
  std::vector<std::size_t> missed;
  const std::size_t held = heldByTie(m, t, &missed);
  for (std::size_t w = 0; w < missed.size(); ++w)
    if (missed[w] > 0) std::printf("  wisp %zu: %zu member strands miss the ring\n", w, missed[w]);
  const float covered = coveredShare(head, m);
  std::printf(
      "ponytail: %zu wisps; the tie (centre %.3f %.3f %.3f, radius %.1f mm) holds %zu of %zu member strands; "
      "scalp covered %.1f%%\n",
      s.wisps.size(), t.center.x, t.center.y, t.center.z, 1e3f * t.radius, held, m.size(), 100.0f * covered);
  if (held != m.size()) fail("the tie does not hold every member strand");
  if (!(t.center.z < -0.05f)) fail("the tie is not behind the head");
  if (covered < 0.75f) fail("the hair covers less than 75% of the scalp");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && (std::string(argv[1]) == "--bob" || std::string(argv[1]) == "--ponytail")) {
    try {
      return std::string(argv[1]) == "--bob" ? checkBob(argv[2]) : checkPonytail(argv[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  if (argc == 3 && std::string(argv[1]) == "--tie") {
    try {
      return checkTie(argv[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  if (argc == 3 && std::string(argv[1]) == "--drags") {
    try {
      return checkDrags(argv[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  if (argc == 4 && std::string(argv[1]) == "--hair-pixels") {
    try {
      const double share = newHairShare(readPng(argv[2]), readPng(argv[3]));
      std::printf("hair-coloured pixels over the bare head's picture: %.1f%%\n", 100 * share);
      return share > 0.02 ? 0 : 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s SCENE WIDTH HEIGHT VIEWER_STYLE.json\n", argv[0]);
    return 2;
  }
  try {
    const SceneDesc scene = loadScene(argv[1]);
    const int width = std::stoi(argv[2]), height = std::stoi(argv[3]);
    // a new style on the scene's head, as the viewer starts one
    Style style;
    style.head = scene;
    style.source = scene.source;
    style.name = scene.name + "-style";
    const HeadModel head = HeadModel::build(style.head, style.source);
    StyleEditor editor(style, head);
    // the brush stroke of the script, seen by the front camera
    // (the viewer centres the view in what its panel, 450 pixels wide when
    // it opens, leaves free)
    render::Camera camera = render::Camera::preset("front");
    camera.shift_x = 450.0f / static_cast<float>(width);
    const double stroke[][2] = {{825, 200}, {840, 200}, {855, 200}, {855, 212}, {840, 212}, {825, 212}};
    std::set<std::uint32_t> brushed;
    for (const auto& p : stroke) {
      const render::Ray r = camera.ray(p[0], p[1], width, height);
      if (const auto hit = intersectRay(head.headMesh(), r.origin, r.direction))
        for (std::uint32_t t : scalpTrianglesWithin(head, hit->point, 0.015f)) brushed.insert(t);
    }
    WispRegion region;
    region.triangles.assign(brushed.begin(), brushed.end());
    const std::size_t w = editor.createWisp(region, WispParams{});
    editor.moveControlPoint(w, editor.style().wisps[w].key_strand.size() - 1, StylingAxis::Normal, 0.020f);
    const std::size_t m = editor.mirrorWisp(w);
    editor.undo();
    editor.redo();
    editor.addControlPoint(m, 3);
    editor.deleteControlPoint(m, 3);
    editor.copyKeyStrand(w);
    editor.pasteKeyStrand(m);
    WispParams denser;
    denser.density = 30.0f;
    editor.setParams(m, denser);
    HairTie tie;
    tie.center = editor.style().wisps[w].key_strand[2];
    tie.axis = stylingDirections(editor.style().wisps[w], 2, head).tangent;
    tie.radius = 0.015f;
    editor.addTie(tie);
    editor.deleteWisp(m);
    editor.undo();
    const std::string want = styleText(editor.style(), argv[4]);
    const std::string got = readRegularFile(argv[4], kMaxTextFileBytes);
    if (got != want) {
      std::fprintf(stderr, "the viewer's style differs from the API's:\n--- viewer\n%s\n--- API\n%s\n", got.c_str(),
                   want.c_str());
      return 1;
    }
    std::printf("the viewer's style equals the API's: %zu wisps, %zu ties, %zu brushed triangles, %zu bytes\n",
                editor.style().wisps.size(), editor.style().ties.size(), region.triangles.size(), got.size());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
