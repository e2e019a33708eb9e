// Strands on software OpenGL (OSMesa), as in CI (issue "strands"): hair over
// the crown with no background through dense hair, shadows that darken the
// far side, Marschner differing from Kajiya-Kay, supersampling nearer a
// finer reference, and a reference image.
#include "headless_gl.hpp"
#include "png.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/strand_field.hpp"
#include "render_reference.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

using namespace loosehair;
using namespace loosehair::render;

namespace {

using lhtest::Image;

// The bundled hang scene with its strands, settled for a moment.
struct HangStrands {
  SceneDesc scene;
  BuildReport build;
  std::unique_ptr<Solver> solver;
  std::unique_ptr<StrandField> field;
  TriangleMesh head, torso;
  FrameInput input;
  HangStrands() {
    scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
    scene.hair.particles = 2500;
    solver = std::make_unique<Solver>(buildSolver(scene, &build));
    RenderStrandOptions so;
    so.strands = 6000;
    so.points = 16;
    field = std::make_unique<StrandField>(bindSceneStrands(scene, solver->particles(), build, so, 2));
    solver->advance(10 * build.substeps);
    head = decimate(loadMesh(scene.head_mesh.path), 16000);
    torso = decimate(loadMesh(scene.torso_mesh.path), 8000);
    input = frameFromSolver(*solver, build.mean_neighbor_distance);
    field->deformWorld(*solver, input.strand_points, 2);
    input.strand_points_each = so.points;
  }
};
const HangStrands& hang() {
  static const HangStrands s;
  return s;
}

RenderSettings strands() {
  RenderSettings st;
  st.hair = HairGeometry::Strands;
  return st;
}

Image draw(int w, int h, const Camera& cam, const RenderSettings& st,
           app::GLProvider provider = app::GLProvider::OSMesa) {
  const HangStrands& s = hang();
  app::HeadlessGL gl(w, h, provider);
  Renderer r;
  r.setBodies(&s.head, &s.torso);
  r.render(s.input, cam, st, w, h);
  return {w, h, gl.pixels()};
}

// The hang strands drawn with each of `settings` by one renderer, three-
// quarter view: the pictures and how many strands the camera drew.
struct Drawn {
  Image image;
  std::size_t strands;
};
std::vector<Drawn> drawEach(int w, int h, const std::vector<RenderSettings>& settings) {
  const HangStrands& s = hang();
  const Camera cam = Camera::preset("three-quarter");
  app::HeadlessGL gl(w, h);
  Renderer r;
  r.setBodies(&s.head, &s.torso);
  std::vector<Drawn> out;
  for (const RenderSettings& st : settings) {
    r.render(s.input, cam, st, w, h);
    out.push_back({Image{w, h, gl.pixels()}, r.lastTimes().strands_drawn});
  }
  return out;
}

glm::ivec2 toPixel(const Camera& cam, int w, int h, glm::vec3 p) {
  const glm::vec4 clip =
      cam.projection(static_cast<float>(w) / static_cast<float>(h)) * cam.view() * glm::vec4(p, 1.0f);
  return {static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * static_cast<float>(w)),
          static_cast<int>((0.5f - clip.y / clip.w * 0.5f) * static_cast<float>(h))};
}

bool isBackground(glm::vec3 c, const RenderSettings& st) { return glm::length(c - st.background) < 0.04f; }

double meanDifference(const Image& a, const Image& b) {
  double sum = 0;
  for (std::size_t k = 0; k < a.rgba.size(); ++k)
    if (k % 4 != 3) sum += std::abs(static_cast<int>(a.rgba[k]) - static_cast<int>(b.rgba[k]));
  return sum / static_cast<double>(a.rgba.size() / 4 * 3);
}

}  // namespace

TEST(RenderStrands, HairCoversTheCrownAndNoBackgroundShowsThroughDenseHair) {
  const HangStrands& s = hang();
  const int w = 200, h = 150;
  const Camera cam = Camera::preset("front");
  const RenderSettings st = strands();
  const Image img = draw(w, h, cam, st);
  // pixels with many particles around them: dense hair
  std::vector<int> count(static_cast<std::size_t>(w * h), 0);
  for (const glm::vec3& p : s.input.position) {
    const glm::ivec2 q = toPixel(cam, w, h, p);
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = q.x + dx, y = q.y + dy;
        if (x >= 0 && y >= 0 && x < w && y < h) ++count[static_cast<std::size_t>(y * w + x)];
      }
  }
  int dense = 0, see_through = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (count[static_cast<std::size_t>(y * w + x)] < 6) continue;
      ++dense;
      see_through += isBackground(img.at(x, y), st);
    }
  ASSERT_GT(dense, 1000);
  EXPECT_LT(see_through, dense / 100) << see_through << " of " << dense << " dense-hair pixels show the background";
  // the crown: where the bare head shows its scalp, the hair hides it
  RenderSettings bare = st;
  bare.hair = HairGeometry::Billboards;
  bare.hair_opacity = 0.0f;
  const Image head = draw(w, h, cam, bare);
  const glm::ivec2 crown = toPixel(cam, w, h, glm::vec3(0.0f, 0.12f, 0.0f));
  int hair = 0, skin = 0;
  for (int y = crown.y - 6; y <= crown.y + 6; ++y)
    for (int x = crown.x - 10; x <= crown.x + 10; ++x) {
      if (isBackground(head.at(x, y), st)) continue;  // beside the head
      const bool covered = glm::length(img.at(x, y) - head.at(x, y)) > 0.05f;
      hair += covered;
      skin += !covered;
    }
  if (std::getenv("LOOSEHAIR_KEEP_IMAGES")) app::writePng("/tmp/crown.png", img.rgba, w, h);
  EXPECT_GT(hair, 150) << "hair over the crown around pixel " << crown.x << ", " << crown.y;
  EXPECT_LT(skin, hair / 50) << "no bald spot at the crown";
}

TEST(RenderStrands, ShadowsDarkenTheHairAwayFromTheLight) {
  const int w = 200, h = 150;
  const Camera cam = Camera::preset("three-quarter");
  RenderSettings on = strands(), off = strands();
  off.shadows = false;
  const Image a = draw(w, h, cam, on), b = draw(w, h, cam, off);
  double lit_on = 0, lit_off = 0;
  int hair = 0, darker_skin = 0, skin = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 ca = a.at(x, y), cb = b.at(x, y);
      if (isBackground(cb, off)) continue;
      const bool is_skin = cb.r > 0.5f && cb.b > 0.55f * cb.r;
      if (is_skin) {
        ++skin;
        darker_skin += (ca.r + ca.g + ca.b) < 0.9f * (cb.r + cb.g + cb.b);
      } else {
        lit_on += ca.r + ca.g + ca.b;
        lit_off += cb.r + cb.g + cb.b;
        ++hair;
      }
    }
  ASSERT_GT(hair, 2000);
  // measured: 0.91 (0.866 before the slices started at the hair nearest
  // the light, when the lit surface itself fell into later slices and
  // darkened in bands); without shadows it would be 1
  std::printf("hair lit with shadows / without: %.3f\n", lit_on / lit_off);
  EXPECT_LT(lit_on, 0.95 * lit_off) << "self-shadowed strands are darker";
  // (measured: 2.0 % of the skin's pixels, 109 of about 5,450, a tenth or
  // more darker; with the initial strands pushed out along the exact
  // normal the hair hangs a little differently than when this said 2 %)
  // (0.8 % since the slices start at the nearest hair: hair lying on the
  // scalp is thin there and lets more light through)
  std::printf("skin darkened by the hair's shadow: %d of %d pixels\n", darker_skin, skin);
  EXPECT_GT(darker_skin, skin / 200) << "the strands shadow part of the head";
}

TEST(RenderStrands, MarschnerAndKajiyaKayGiveDifferentImages) {
  const Camera cam = Camera::preset("three-quarter");
  RenderSettings kk = strands(), m = strands();
  m.shading = HairShading::Marschner;
  const Image a = draw(160, 120, cam, kk), b = draw(160, 120, cam, m);
  int hair = 0, differ = 0;
  for (int y = 0; y < a.h; ++y)
    for (int x = 0; x < a.w; ++x) {
      if (isBackground(a.at(x, y), kk)) continue;
      ++hair;
      differ += glm::length(a.at(x, y) - b.at(x, y)) > 0.02f;
    }
  // the same mean colour (MarschnerGivesTheSameHairColourAsKajiyaKay), but
  // the highlights and the light through the hair are elsewhere
  ASSERT_GT(hair, 1000);
  std::printf("%d of %d pixels differ\n", differ, hair);
  EXPECT_GT(differ, hair / 10) << differ << " of " << hair << " pixels differ";
}

// Marschner's lobes and Kajiya-Kay give the same hair colour (blonde with
// Marschner looked olive: its light scattered many times was half of
// Kajiya-Kay's diffuse): over the hair seen from the back, the mean
// colour's hue within 6 degrees, its saturation within 0.06 and its value
// within 10 %, for every preset colour.
TEST(RenderStrands, MarschnerGivesTheSameHairColourAsKajiyaKay) {
  const Camera cam = Camera::preset("back");
  auto hsv = [](glm::vec3 c) {
    const float mx = std::max({c.r, c.g, c.b}), mn = std::min({c.r, c.g, c.b}), d = mx - mn;
    float h = 0.0f;
    if (d > 0.0f) {
      if (mx == c.r)
        h = 60.0f * std::fmod((c.g - c.b) / d, 6.0f);
      else if (mx == c.g)
        h = 60.0f * ((c.b - c.r) / d + 2.0f);
      else
        h = 60.0f * ((c.r - c.g) / d + 4.0f);
    }
    if (h < 0.0f) h += 360.0f;
    return glm::vec3(h, mx > 0.0f ? d / mx : 0.0f, mx);
  };
  for (HairColor colour : {HairColor::Black, HairColor::Brown, HairColor::Blonde, HairColor::Red}) {
    RenderSettings kk = strands();
    kk.color = colour;
    kk.light_direction = cam.keyLight();
    RenderSettings m = kk;
    m.shading = HairShading::Marschner;
    const Image a = draw(160, 120, cam, kk), b = draw(160, 120, cam, m);
    glm::dvec3 sa(0.0), sb(0.0);
    int n = 0;
    for (int y = 0; y < a.h * 55 / 100; ++y)  // the head of hair, above the shoulders
      for (int x = 0; x < a.w; ++x) {
        if (isBackground(a.at(x, y), kk)) continue;
        sa += glm::dvec3(a.at(x, y));
        sb += glm::dvec3(b.at(x, y));
        ++n;
      }
    ASSERT_GT(n, 1000);
    const glm::vec3 ha = hsv(glm::vec3(sa / static_cast<double>(n))), hb = hsv(glm::vec3(sb / static_cast<double>(n)));
    std::printf("colour %d: Kajiya-Kay hue %.1f sat %.3f value %.3f, Marschner hue %.1f sat %.3f value %.3f\n",
                static_cast<int>(colour), ha.x, ha.y, ha.z, hb.x, hb.y, hb.z);
    EXPECT_NEAR(ha.x, hb.x, 6.0f);
    EXPECT_NEAR(ha.y, hb.y, 0.06f);
    // (measured 1.03-1.08; with the multiple scattering at half of
    // Kajiya-Kay's diffuse, 0.86-0.99, blonde the darkest)
    EXPECT_NEAR(hb.z / ha.z, 1.0f, 0.10f);
  }
}

// Level of detail: hair small in the picture draws every k-th strand, k
// times as opaque; the picture stays the same to within a fraction of a
// grey level, the camera pass draws half the strands or fewer; hair large
// in the picture draws them all.
TEST(RenderStrands, SmallHairDrawsFewerStrandsAndLooksTheSame) {
  EXPECT_EQ(strandLevelOfDetail(12000, 0.25f, 1.5e-4f, 0.3f, 0.75f, 1300.0f), 1u) << "large on screen";
  const std::size_t far = strandLevelOfDetail(12000, 0.25f, 1.5e-4f, 0.3f, 3.0f, 1300.0f);
  const std::size_t farther = strandLevelOfDetail(12000, 0.25f, 1.5e-4f, 0.3f, 6.0f, 1300.0f);
  EXPECT_GT(far, 1u);
  EXPECT_GT(farther, far) << "smaller on screen, fewer strands";
  EXPECT_EQ(strandLevelOfDetail(0, 0.25f, 1.5e-4f, 0.3f, 6.0f, 1300.0f), 1u);
  const HangStrands& s = hang();
  RenderSettings lod = strands(), all = strands();
  all.strand_lod = false;
  const std::vector<Drawn> d = drawEach(200, 150, {all, lod});
  const std::size_t drawn_all = d[0].strands, drawn_lod = d[1].strands;
  const double diff = meanDifference(d[0].image, d[1].image);
  std::printf("strands drawn: %zu of %zu; mean difference %.2f grey levels\n", drawn_lod, drawn_all, diff);
  EXPECT_EQ(drawn_all, s.field->strandCount());
  EXPECT_LE(2 * drawn_lod, drawn_all + 1);
  EXPECT_LT(diff, 1.0);
}

// The viewer on software OpenGL draws a third of the strands while the hair
// moves (RenderSettings::strand_budget): the hair must cover what it did.
TEST(RenderStrands, ABudgetDrawsFewerStrandsAndTheHairCoversTheSame) {
  EXPECT_EQ(strandBudgetStride(12000, 0), 1u);
  EXPECT_EQ(strandBudgetStride(12000, 20000), 1u);
  EXPECT_EQ(strandBudgetStride(12000, 4000), 3u);
  EXPECT_EQ(strandBudgetStride(12001, 4000), 4u) << "at most the budget";
  const HangStrands& s = hang();
  RenderSettings all = strands(), budget = strands();
  budget.strand_budget = s.field->strandCount() / 3;
  const std::vector<Drawn> d = drawEach(320, 240, {all, budget});
  const Image& full = d[0].image;
  const Image& fewer = d[1].image;
  const std::size_t drawn_all = d[0].strands, drawn = d[1].strands;
  auto covered = [&](const Image& img) {
    std::size_t n = 0;
    for (int y = 0; y < img.h; ++y)
      for (int x = 0; x < img.w; ++x) n += isBackground(img.at(x, y), all) ? 0 : 1;
    return n;
  };
  const double diff = meanDifference(full, fewer);
  const double cover_all = static_cast<double>(covered(full)), cover = static_cast<double>(covered(fewer));
  std::printf("strands drawn: %zu of %zu; mean difference %.2f grey levels; covered %.0f of %.0f pixels\n", drawn,
              drawn_all, diff, cover, cover_all);
  EXPECT_EQ(drawn_all, s.field->strandCount());
  EXPECT_LE(drawn, budget.strand_budget);
  EXPECT_GE(3 * drawn + 3, drawn_all);
  EXPECT_NEAR(cover / cover_all, 1.0, 0.03);
  EXPECT_LT(diff, 4.0);
}

// Strands a pixel wide or less are drawn as lines (half the vertices);
// wider ones as ribbons. On either side of the switch the picture is the
// same, up to the small change of width.
TEST(RenderStrands, ThinStrandsDrawnAsLinesLookAsRibbonsDo) {
  const HangStrands& s = hang();
  const int w = 200, h = 150;
  const Camera cam = Camera::preset("three-quarter");
  app::HeadlessGL gl(w, h);
  Renderer r;
  r.setBodies(&s.head, &s.torso);
  RenderSettings st = strands();
  st.strand_lod = false;
  auto asLines = [&](float radius) {
    st.strand_radius = radius;
    r.render(s.input, cam, st, w, h);
    return r.lastTimes().strands_as_lines;
  };
  float thin = 1e-4f, wide = 1e-2f;  // lines at 0.1 mm, ribbons at 1 cm
  ASSERT_TRUE(asLines(thin));
  ASSERT_FALSE(asLines(wide));
  while (wide / thin > 1.02f) {
    const float mid = std::sqrt(thin * wide);
    (asLines(mid) ? thin : wide) = mid;
  }
  // the same opacity per pixel on both sides: the width only changes by 2 %
  st.strand_opacity = 0.3f;
  ASSERT_TRUE(asLines(thin));
  const Image lines{w, h, gl.pixels()};
  ASSERT_FALSE(asLines(wide));
  const Image ribbons{w, h, gl.pixels()};
  const double diff = meanDifference(lines, ribbons);
  std::printf("lines up to a radius of %.3f mm; lines against ribbons: %.2f grey levels\n", 1e3 * thin, diff);
  EXPECT_LT(diff, 1.5);
}

TEST(RenderStrands, SupersamplingComesNearerAFinerReference) {
  const Camera cam = Camera::preset("three-quarter");
  RenderSettings st = strands();
  st.supersample = 4;
  const Image reference = draw(160, 120, cam, st);
  st.supersample = 1;
  const Image aliased = draw(160, 120, cam, st);
  st.supersample = 2;
  const Image smooth = draw(160, 120, cam, st);
  const double d1 = meanDifference(aliased, reference), d2 = meanDifference(smooth, reference);
  std::printf("mean difference from 4x4: 1x1 %.2f, 2x2 %.2f (of 255)\n", d1, d2);
  EXPECT_LT(d2, 0.75 * d1);
}

TEST(RenderStrands, StillFrameMatchesTheReferenceImage) {
  const int w = 96, h = 72;
  const Image img = draw(w, h, Camera::preset("three-quarter"), strands());
  lhtest::expectMatchesReference(img.rgba, w, h, "render_hang_strands_96x72.png");
}

// method.md §7.4: the same executable draws with EGL (here Mesa's surfaceless
// platform or a device, on llvmpipe) and OSMesa, to the same picture.
TEST(RenderStrands, EglAndOSMesaDrawTheSameImages) {
  const Camera cam = Camera::preset("three-quarter");
  RenderSettings billboards = strands();
  billboards.hair = HairGeometry::Billboards;
  for (const RenderSettings& st : {strands(), billboards}) {
    const Image b = draw(160, 120, cam, st, app::GLProvider::EGL);
    const Image a = draw(160, 120, cam, st, app::GLProvider::OSMesa);
    int worst = 0;
    for (std::size_t k = 0; k < a.rgba.size(); ++k)
      worst = std::max(worst, std::abs(static_cast<int>(a.rgba[k]) - static_cast<int>(b.rgba[k])));
    EXPECT_LT(meanDifference(a, b), 1.0) << (st.hair == HairGeometry::Strands ? "strands" : "billboards");
    EXPECT_LE(worst, 64);
  }
}
