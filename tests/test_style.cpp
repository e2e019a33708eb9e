// The styling library (method.md §6.2): frames, member strands, editing with
// undo, style files, seeding and strand files, on a sphere head (fast enough
// for the sanitizer run).
#include "loosehair/groom_import.hpp"
#include "loosehair/strand_files.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"
#include "style/hair_tie.hpp"
#include "style/rotation_minimizing_frame.hpp"
#include "style/style_seeding.hpp"
#include "style_fixtures.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

std::filesystem::path tempDir() {
  auto d = std::filesystem::temp_directory_path() /
           ("loosehair-style-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

// ---- rotation-minimising frames ---------------------------------------------
TEST(StyleFrames, RotationMinimisingFramesTwistLessThanFrenetOnAHelix) {
  std::vector<glm::vec3> helix;
  const float a = 0.02f, b = 0.01f;  // radius, pitch / 2 pi
  for (int k = 0; k <= 400; ++k) {
    const float t = 0.05f * static_cast<float>(k);
    helix.emplace_back(a * std::cos(t), b * t, a * std::sin(t));
  }
  const auto rmf = rotationMinimizingFrames(helix, glm::vec3(1, 0, 0));
  ASSERT_EQ(rmf.size(), helix.size());
  double twist_rmf = 0, twist_frenet = 0;
  glm::vec3 prev_fn(0.0f);
  for (std::size_t k = 0; k < rmf.size(); ++k) {
    const CurveFrame& f = rmf[k];
    EXPECT_NEAR(glm::length(f.tangent), 1.0f, 1e-4f);
    EXPECT_NEAR(glm::length(f.normal), 1.0f, 1e-4f);
    EXPECT_NEAR(glm::dot(f.tangent, f.normal), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(glm::cross(f.tangent, f.normal) - f.binormal), 0.0f, 1e-4f);
    // Frenet normal: towards the helix axis
    const glm::vec3 p = helix[k];
    const glm::vec3 fn = glm::normalize(glm::vec3(-p.x, 0.0f, -p.z));
    if (k > 0) {
      // rotation about the tangent between consecutive frames
      twist_rmf += std::abs(glm::dot(rmf[k].normal - rmf[k - 1].normal, rmf[k].binormal));
      const glm::vec3 fb = glm::cross(f.tangent, fn);
      twist_frenet += std::abs(glm::dot(fn - prev_fn, fb));
    }
    prev_fn = fn;
  }
  EXPECT_LT(twist_rmf, 0.1 * twist_frenet) << "RMF twist " << twist_rmf << ", Frenet " << twist_frenet;
}

TEST(StyleFrames, NoFlipWhereTheCurvatureVanishes) {
  // straight, then a bend one way, straight, a bend the other way: the
  // Frenet normal flips at the inflection, the rotation-minimising one not
  std::vector<glm::vec3> s;
  for (int k = 0; k <= 20; ++k) s.emplace_back(0, 0.005f * static_cast<float>(k), 0);
  for (int k = 1; k <= 20; ++k) {
    const float t = 0.05f * static_cast<float>(k);
    s.emplace_back(0.1f * (1 - std::cos(t)), 0.1f + 0.1f * std::sin(t), 0);
  }
  const glm::vec3 e = s.back();
  for (int k = 1; k <= 20; ++k) {
    const float t = 0.05f * static_cast<float>(k);
    s.emplace_back(e.x + 0.1f * (std::cos(1.0f - t) - std::cos(1.0f)),
                   e.y + 0.1f * (std::sin(1.0f) - std::sin(1.0f - t)), 0);
  }
  const auto f = rotationMinimizingFrames(s, glm::vec3(0, 0, 1));
  for (std::size_t k = 1; k < f.size(); ++k) {
    EXPECT_GT(glm::dot(f[k].normal, f[k - 1].normal), 0.99f) << "at point " << k;
    EXPECT_NEAR(std::abs(f[k].normal.z), 1.0f, 1e-3f) << "a planar curve keeps its out-of-plane normal";
  }
}

// ---- member strands -----------------------------------------------------------
TEST(StyleStrands, OffsetZeroReproducesTheKeyStrandAtEachRoot) {
  const HeadModel& h = sphereModel();
  const Style s = upwardWisp(0.0f, 25);
  const StrandSet strands = buildMemberStrands(s, h);
  ASSERT_GE(strands.size(), 10u);
  const std::size_t n0 = strands.pointCount(0);
  const glm::vec3* key = &strands.points[strands.first[0]];
  // the first member starts at the region's root: it is the key strand's
  // spline itself, through every control point
  for (const glm::vec3& c : s.wisps[0].key_strand) {
    float nearest = INFINITY;
    for (std::size_t j = 0; j < n0; ++j) nearest = std::min(nearest, glm::length(key[j] - c));
    EXPECT_LT(nearest, 1e-6f) << "the key strand misses a control point";
  }
  for (std::size_t k = 0; k < strands.size(); ++k) {
    ASSERT_EQ(strands.pointCount(k), n0);
    const glm::vec3* m = &strands.points[strands.first[k]];
    const glm::vec3 delta = m[0] - key[0];
    EXPECT_NEAR(glm::length(m[0] - h.scalpPoint(strands.root_uv[k])), 0.0f, 1e-6f);
    for (std::size_t j = 0; j < n0; ++j) EXPECT_NEAR(glm::length(m[j] - (key[j] + delta)), 0.0f, 2e-6f);
  }
}

TEST(StyleStrands, OffsetsStayWithinABoundGrowingLinearlyAlongTheStrand) {
  const HeadModel& h = sphereModel();
  const Style s = upwardWisp(0.012f, 0);
  const StrandSet strands = buildMemberStrands(s, h);
  // the same roots without offsets: the key strand translated to each root
  Style plain = s;
  plain.wisps[0].params.offset_radius = 0.0f;
  const StrandSet ref = buildMemberStrands(plain, h);
  ASSERT_GE(strands.size(), 10u);
  ASSERT_EQ(ref.size(), strands.size());
  const glm::vec3* key = &ref.points[ref.first[0]];
  const std::size_t n = ref.pointCount(0);
  std::vector<float> sk(n, 0.0f);
  for (std::size_t j = 1; j < n; ++j) sk[j] = sk[j - 1] + glm::length(key[j] - key[j - 1]);
  float largest_tip = 0;
  for (std::size_t k = 0; k < strands.size(); ++k) {
    // a member is cut to the key strand's length along its own (longer) arc
    ASSERT_LE(strands.pointCount(k), n);
    const glm::vec3* m = &strands.points[strands.first[k]];
    const glm::vec3* r = &ref.points[ref.first[k]];
    for (std::size_t j = 0; j + 1 < strands.pointCount(k); ++j) {
      const float off = glm::length(m[j] - r[j]);
      EXPECT_LE(off, 0.012f * sk[j] / sk.back() + 1e-5f) << "strand " << k << " point " << j;
    }
    const std::size_t last = strands.pointCount(k) - 2;
    largest_tip = std::max(largest_tip, glm::length(m[last] - r[last]) * sk.back() / sk[last]);
  }
  EXPECT_GT(largest_tip, 0.006f) << "the offsets use the radius";
}

TEST(StyleStrands, DeterministicForASeedAndDifferentForAnother) {
  const HeadModel& h = sphereModel();
  Style s = twoWispStyle();
  const StrandSet a = buildMemberStrands(s, h), b = buildMemberStrands(s, h);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(0, std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(glm::vec3)));
  // the wisps grown on three threads: the same strands in the same order
  const StrandSet t = buildMemberStrands(s, h, kStrandSpacing, {}, 3);
  ASSERT_EQ(a.points.size(), t.points.size());
  EXPECT_EQ(a.first, t.first);
  EXPECT_EQ(a.wisp, t.wisp);
  EXPECT_EQ(0, std::memcmp(a.points.data(), t.points.data(), a.points.size() * sizeof(glm::vec3)));
  s.wisps[0].params.seed = 99;
  const StrandSet c = buildMemberStrands(s, h);
  EXPECT_TRUE(c.points.size() != a.points.size() ||
              std::memcmp(a.points.data(), c.points.data(), a.points.size() * sizeof(glm::vec3)) != 0);
}

TEST(StyleStrands, AStyleAboveTheBudgetIsRefusedBeforeItIsBuilt) {
  const HeadModel& h = sphereModel();
  Style s = twoWispStyle();
  const StrandSet fits = buildMemberStrands(s, h);
  ASSERT_GT(fits.size(), 10u);
  // a budget below what the style grows: refused naming the style, the
  // wisp that grows most and the way out
  s.wisps[1].params.density = 1000.0f;
  const StrandBudget small{fits.size(), 1'000'000};
  try {
    (void)buildMemberStrands(s, h, kStrandSpacing, small);
    FAIL() << "a style above the budget was built";
  } catch (const StyleError& e) {
    const std::string what = e.what();
    for (const char* part : {"test-style", "wisps[1]", "lower its density", "limit of", "--allow-expensive"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " in: " << what;
  }
  // the densest a style file allows, over the whole cap: millions of
  // strands, refused by the default budget at once
  for (Wisp& w : s.wisps) {
    w.params.density = 10000.0f;
    w.region = square({0.0f, 0.0f}, {1.0f, 1.0f});
  }
  EXPECT_THROW((void)buildMemberStrands(s, h), StyleError);
  // a budget just above what the style grows is not refused (the estimate
  // is not far above the count), and the count keeps within it
  Style fitting = twoWispStyle();
  fitting.wisps[0].params.strands = 40;
  const StrandSet built = buildMemberStrands(fitting, h, kStrandSpacing, {fits.size() + 40, fits.points.size() * 4});
  EXPECT_LE(built.size(), fits.size() + 40);
}

// ---- editing -----------------------------------------------------------------
TEST(StyleEditing, MirrorTwiceIsTheIdentity) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  const std::size_t m = ed.mirrorWisp(0);
  const Wisp& once = ed.style().wisps[m];
  const Wisp& orig = ed.style().wisps[0];
  // the mirror image is on the other side
  EXPECT_LT(orig.key_strand.back().x * once.key_strand.back().x, 0.0f);
  const std::size_t mm = ed.mirrorWisp(m);
  const Wisp& twice = ed.style().wisps[mm];
  ASSERT_EQ(twice.key_strand.size(), orig.key_strand.size());
  for (std::size_t k = 0; k < orig.key_strand.size(); ++k)
    EXPECT_NEAR(glm::length(twice.key_strand[k] - orig.key_strand[k]), 0.0f, 1e-6f) << k;
  ASSERT_EQ(twice.region.polygons.size(), orig.region.polygons.size());
  for (std::size_t p = 0; p < orig.region.polygons.size(); ++p)
    for (std::size_t k = 0; k < orig.region.polygons[p].size(); ++k)
      EXPECT_NEAR(glm::length(twice.region.polygons[p][k] - orig.region.polygons[p][k]), 0.0f, 1e-6f);
  EXPECT_EQ(twice.params, orig.params);
}

TEST(StyleEditing, CopyPasteKeepsTheShapeInTheNewRootsFrame) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  ed.copyKeyStrand(0);
  ed.pasteKeyStrand(1);
  const Wisp& a = ed.style().wisps[0];
  const Wisp& b = ed.style().wisps[1];
  const glm::vec2 ua = regionRoot(a.region, h), ub = regionRoot(b.region, h);
  const glm::mat3 fa = rootFrame(h, ua), fb = rootFrame(h, ub);
  ASSERT_EQ(a.key_strand.size(), b.key_strand.size());
  EXPECT_NEAR(glm::length(b.key_strand[0] - h.scalpPoint(ub)), 0.0f, 1e-6f);
  for (std::size_t k = 0; k < a.key_strand.size(); ++k) {
    const glm::vec3 la = glm::transpose(fa) * (a.key_strand[k] - a.key_strand[0]);
    const glm::vec3 lb = glm::transpose(fb) * (b.key_strand[k] - b.key_strand[0]);
    EXPECT_NEAR(glm::length(la - lb), 0.0f, 1e-5f) << "control point " << k;
  }
}

TEST(StyleEditing, EachStylingDirectionMovesAlongItsVector) {
  const HeadModel& h = sphereModel();
  StyleEditor ed(twoWispStyle(), h);
  for (int axis = 0; axis < 3; ++axis) {
    const StylingDirections d = stylingDirections(ed.style().wisps[0], 2, h);
    EXPECT_LT(std::abs(glm::dot(d.tangent, d.normal)), 0.99f);  // not parallel in this strand
    EXPECT_NEAR(glm::dot(d.binormal, d.tangent), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(d.binormal, d.normal), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(d[axis]), 1.0f, 1e-5f);
    const glm::vec3 before = ed.style().wisps[0].key_strand[2];
    ed.moveControlPoint(0, 2, static_cast<StylingAxis>(axis), 0.004f);
    const glm::vec3 moved = ed.style().wisps[0].key_strand[2] - before;
    EXPECT_NEAR(glm::length(moved - 0.004f * d[axis]), 0.0f, 1e-6f) << "axis " << axis;
  }
  const StylingDirections d = stylingDirections(ed.style().wisps[0], 1, h);
  EXPECT_NEAR(glm::length(glm::cross(d.tangent, d.normal) - d.binormal * glm::length(glm::cross(d.tangent, d.normal))),
              0.0f, 1e-5f);
}

TEST(StyleEditing, UndoRestoresTheFileByteForByteAndRedoReapplies) {
  const HeadModel& h = sphereModel();
  const Style start = twoWispStyle();
  StyleEditor ed(start, h);
  const std::string text0 = styleText(ed.style());
  ed.moveControlPoint(0, 2, StylingAxis::Binormal, 0.01f);
  ed.addControlPoint(0, 2);
  ed.deleteControlPoint(1, 1);
  ed.setControlPoint(1, 1, ed.style().wisps[1].key_strand[1] + glm::vec3(0, 0, 0.01f));
  const std::size_t m = ed.mirrorWisp(1);
  ed.copyKeyStrand(0);
  ed.pasteKeyStrand(m);
  WispParams p = ed.style().wisps[0].params;
  p.density = 30.0f;
  p.curl_radius = 0.004f;
  ed.setParams(0, p);
  ed.setRegion(0, square({0.1f, 0.25f}, {0.3f, 0.5f}));
  ed.renameWisp(0, "renamed");
  ed.createWisp(square({0.7f, 0.4f}, {0.8f, 0.6f}));
  ed.deleteWisp(1);
  ed.setColour(glm::vec3(0.5f, 0.4f, 0.3f));
  ed.setShapeKeeping(2.0f);
  const std::string text_end = styleText(ed.style());
  int undone = 0;
  while (ed.undo()) ++undone;
  EXPECT_EQ(undone, 13);  // copying is not an edit
  EXPECT_TRUE(styleText(ed.style()) == text0);
  while (ed.redo()) {
  }
  EXPECT_TRUE(styleText(ed.style()) == text_end);
  // a failed operation changes nothing and records nothing
  EXPECT_THROW(ed.deleteControlPoint(0, 0), StyleError);
  EXPECT_THROW(ed.moveControlPoint(0, 1, StylingAxis::Normal, -0.04f), StyleError);  // into the head
  EXPECT_TRUE(styleText(ed.style()) == text_end);
  ASSERT_TRUE(ed.undo());
  EXPECT_FALSE(styleText(ed.style()) == text_end);
}

// ---- files ---------------------------------------------------------------------
TEST(StyleFiles, SaveThenLoadGivesAnIdenticalStyle) {
  const auto dir = tempDir();
  Style s = twoWispStyle();
  s.wisps[0].region.triangles = {3, 5, 8};
  s.wisps[1].params.curl_radius = 0.0031f;
  s.colour = glm::vec3(0.1f, 0.2f, 0.3f);
  s.ties.push_back(HairTie{"tie", glm::vec3(0.01f, -0.15f, -0.12f), glm::normalize(glm::vec3(0.1f, -1, 0.2f)), 0.0151f,
                           0.0123f, 2.75f});
  const std::string path = (dir / "a.json").string();
  saveStyle(s, path);
  const Style back = loadStyle(path);
  EXPECT_TRUE(back == s);
  EXPECT_TRUE(styleText(back, path) == styleText(s, path));
  std::filesystem::remove_all(dir);
}

TEST(StyleFiles, BadStylesAreRejectedNamingTheField) {
  const HeadModel& h = sphereModel();
  const std::string good = styleText(twoWispStyle());
  auto expectError = [&](const std::string& text, const std::string& needle, bool check) {
    try {
      const Style s = parseStyle(text, "bad.json");
      if (check) checkStyle(s, h);
      ADD_FAILURE() << "accepted; expected an error naming " << needle;
    } catch (const StyleError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
  };
  // unknown field
  std::string t = good;
  t.replace(t.find("\"name\""), 6, "\"nmae\"");
  expectError(t, "nmae", false);
  // a control point inside the head
  Style s = twoWispStyle();
  s.wisps[1].key_strand[2] = glm::vec3(0.0f, 0.05f, 0.0f);
  expectError(styleText(s), "wisps[1].key_strand[2]", true);
  // a region off the scalp
  s = twoWispStyle();
  s.wisps[0].region.polygons.clear();
  s.wisps[0].region.triangles = {1000000};
  expectError(styleText(s), "wisps[0].region", true);
  // a tie no wisp passes through
  s = twoWispStyle();
  s.ties.push_back(HairTie{"t", glm::vec3(0.3f, 0.3f, 0.3f), glm::vec3(0, -1, 0), 0.01f, 0.01f});
  expectError(styleText(s), "ties[0]", true);
  // out of range and non-finite values
  t = good;
  t.replace(t.find("\"density\": 15.0"), 15, "\"density\": -3.0");
  expectError(t, "density", false);
  s = twoWispStyle();
  s.ties.push_back(HairTie{"t", glm::vec3(0.3f, 0.3f, 0.3f), glm::vec3(0, -1, 0), 0.01f, 0.01f, -1.0f});
  expectError(styleText(s), "ties[0].hold", false);
  expectError("{\"wisps\": []", "bad.json", false);
}

TEST(StrandFiles, ObjPlyAndHairReadBackExactly) {
  const auto dir = tempDir();
  const StrandSet strands = buildMemberStrands(twoWispStyle(), sphereModel());
  ASSERT_GT(strands.size(), 10u);
  for (const char* ext : {".obj", ".ply", ".hair"}) {
    const std::string path = (dir / (std::string("strands") + ext)).string();
    writeStrands(strands, path);
    const Polylines back = readPolylines(path);
    ASSERT_EQ(back.size(), strands.size()) << ext;
    ASSERT_EQ(back.first, strands.first) << ext;
    ASSERT_EQ(back.points.size(), strands.points.size()) << ext;
    for (std::size_t k = 0; k < back.points.size(); ++k)
      ASSERT_EQ(back.points[k], strands.points[k]) << ext << " point " << k;
  }
  EXPECT_THROW(writeStrands(strands, (dir / "x.txt").string()), FileError);
  std::filesystem::remove_all(dir);
}

TEST(StrandFiles, BrokenFilesAreRefusedNamingTheFile) {
  const auto dir = tempDir();
  auto write = [&](const std::string& name, const std::string& bytes) {
    const std::string p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  };
  const std::string cases[] = {
      write("short.hair", "HAIR\x01\x00"),
      write("bad.obj", "v 0 0 0\nv 1 1 1\nl 1 7\n"),
      write("bad.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n0\n"),
      write("nan.obj", "v 0 0 nan\nv 1 1 1\nl 1 2\n"),
  };
  for (const std::string& p : cases) {
    try {
      (void)readPolylines(p);
      ADD_FAILURE() << p << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(GroomImport, ImportedStrandsKeepTheirShapeAndRoots) {
  const HeadModel& h = sphereModel();
  const StrandSet strands = buildMemberStrands(twoWispStyle(), h);
  Polylines groom;
  groom.points = strands.points;
  groom.first = strands.first;
  // one stored tip first, one far from the head
  std::reverse(groom.points.begin() + groom.first[1], groom.points.begin() + groom.first[2]);
  groom.points.push_back(glm::vec3(1, 1, 1));
  groom.points.push_back(glm::vec3(1, 1.1f, 1));
  groom.first.push_back(static_cast<std::uint32_t>(groom.points.size()));
  GroomImportReport rep;
  const Style s = importGroom(groom, sphereHead(), h, "groom.hair", {}, &rep);
  EXPECT_EQ(rep.strands_read, strands.size() + 1);
  EXPECT_EQ(rep.strands_kept, strands.size());
  EXPECT_EQ(rep.skipped_far, 1u);
  EXPECT_EQ(rep.reversed, 1u);
  checkStyle(s, h);
  const StrandSet back = buildMemberStrands(s, h);
  ASSERT_EQ(back.size(), strands.size());
  for (std::size_t k = 0; k < back.size(); ++k) {
    const glm::vec3 a0 = strands.points[strands.first[k]], b0 = back.points[back.first[k]];
    EXPECT_LT(glm::length(a0 - b0), 2e-3f) << "root of strand " << k;
    const glm::vec3 a1 = strands.points[strands.first[k + 1] - 1], b1 = back.points[back.first[k + 1] - 1];
    EXPECT_LT(glm::length(a1 - b1), 3e-3f) << "tip of strand " << k;
  }
  Polylines far;
  far.points = {glm::vec3(5, 5, 5), glm::vec3(5, 6, 5)};
  far.first = {0, 2};
  EXPECT_THROW(importGroom(far, sphereHead(), h, "far.hair"), StyleError);
}

// ---- seeding the simulation ------------------------------------------------------
TEST(StyleSeeding, ParticlesFollowTheStrandsAndStayOutOfTheHead) {
  const HeadModel& h = sphereModel();
  const StrandSet strands = buildMemberStrands(twoWispStyle(), h);
  const StrandSeeding seeded = seedFromStrands(strands, 1500, 7);
  ASSERT_NEAR(static_cast<double>(seeded.samples.size()), 1500.0, 1500 * 0.05);
  double angle_sum = 0;
  std::size_t hair = 0;
  for (const StrandSample& q : seeded.samples) {
    EXPECT_NEAR(glm::length(q.direction), 1.0f, 1e-4f);
    if (q.s < 0.0f) continue;
    ++hair;
    EXPECT_GT(h.headDistance(q.position), -1e-4f) << "a hair particle inside the head";
    EXPECT_LE(glm::length(q.position - q.root), q.s + 1e-5f) << "farther from its root than its arc length";
    // the strand's own tangent at the nearest polyline segment
    const std::uint32_t a = strands.first[q.strand], b = strands.first[q.strand + 1];
    float best = INFINITY;
    glm::vec3 tangent(0.0f);
    for (std::uint32_t j = a + 1; j < b; ++j) {
      const glm::vec3 p0 = strands.points[j - 1], p1 = strands.points[j];
      const glm::vec3 d = p1 - p0;
      const float t = std::clamp(glm::dot(q.position - p0, d) / glm::dot(d, d), 0.0f, 1.0f);
      const float dist = glm::length(q.position - (p0 + t * d));
      if (dist < best) best = dist, tangent = glm::normalize(d);
    }
    EXPECT_LT(best, 1e-4f) << "a particle off its strand";
    angle_sum += std::acos(std::clamp(static_cast<double>(glm::dot(tangent, q.direction)), -1.0, 1.0));
  }
  ASSERT_GT(hair, 1000u);
  EXPECT_LT(angle_sum / static_cast<double>(hair) * 180.0 / M_PI, 15.0);
}

// Through a tie only the tail beyond the ring is shortened by the length
// variation: a member ending before the ring would not be held by it.
TEST(StyleStrands, EveryMemberOfATiedWispPassesItsRingWhateverItsLength) {
  const HeadModel& h = lhtest::styles::sphereModel();
  Style s = lhtest::styles::tiedStyle(4.0f);
  for (Wisp& w : s.wisps) w.params.length_variation = 0.9f;
  const StrandSet m = buildMemberStrands(s, h);
  ASSERT_GT(m.size(), 50u);
  std::size_t held = 0;
  float shortest = INFINITY, longest = 0.0f;
  for (std::size_t k = 0; k < m.size(); ++k) {
    const std::vector<glm::vec3> p(m.points.begin() + m.first[k], m.points.begin() + m.first[k + 1]);
    held += crossTie(p, s.ties[0]) ? 1 : 0;
    float len = 0.0f;
    for (std::size_t j = 1; j < p.size(); ++j) len += glm::length(p[j] - p[j - 1]);
    shortest = std::min(shortest, len), longest = std::max(longest, len);
  }
  EXPECT_EQ(held, m.size());
  EXPECT_LT(shortest, 0.8f * longest) << "the tails still vary in length";
}

// The styling mode's preview pushes members out of the head by the bodies'
// grids (buildMemberStrands with exact = false): the same strands but for
// the push: all but a few points in ten thousand within a voxel of where
// the exact push puts them (a point deep in the head can be pushed out
// along another normal: 32 of 87,802 here, 35 mm at most).
TEST(StyleStrands, APreviewPushedByTheGridsIsWithinAVoxelOfTheExactStrands) {
  Style s = loadStyle(lhtest::sourceDir() + "/data/styles/bob.json");
  for (Wisp& w : s.wisps) w.params.density *= 0.2f;
  const HeadModel head = HeadModel::build(s.head, s.source);
  const StrandSet exact = buildMemberStrands(s, head, 0.006f, {}, 2, true);
  const StrandSet rough = buildMemberStrands(s, head, 0.006f, {}, 2, false);
  ASSERT_EQ(exact.first, rough.first) << "the same strands, point for point";
  const float voxel = head.head()->roughError();
  ASSERT_GT(voxel, 0.0f);
  float worst = 0.0f;
  std::size_t moved = 0, far = 0;
  for (std::size_t q = 0; q < exact.points.size(); ++q) {
    const float d = glm::length(exact.points[q] - rough.points[q]);
    worst = std::max(worst, d);
    moved += d > 0.0f ? 1 : 0;
    far += d > voxel ? 1 : 0;
  }
  std::printf("%zu of %zu points pushed differently, %zu beyond the grid's error bound (%.2f mm), at most %.2f mm\n",
              moved, exact.points.size(), far, 1e3f * voxel, 1e3f * worst);
  EXPECT_LT(far, exact.points.size() / 1000);
}
