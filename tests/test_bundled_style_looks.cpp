// How the bundled styles look (issue 44), measured on pictures as a person
// judges them: drawn as styled on the bundled head from the front, three-
// quarters and the back (320 x 320, strands, the command line's 12,000,
// drawn green without shadows), the share of the head's silhouette above
// the brows (in the bare head's picture) where no hair hides it, next to the share of the scalp
// with no root within 5 mm (scalpCoverage). Figures in data/styles/README.md
// (the forehead below each style's hairline counts as showing: a swept-back
// style shows its forehead). Bounds hold the figures where they are.
#include "headless_gl.hpp"
#include "png.hpp"
#include "loosehair/head_landmarks.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/scalp_coverage.hpp"
#include "loosehair/strand_field.hpp"
#include "render_reference.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <cstdlib>
#include <string>

using namespace loosehair;
using namespace loosehair::render;

namespace {

using lhtest::Image;

glm::ivec2 toPixel(const Camera& cam, int w, int h, glm::vec3 p) {
  const glm::vec4 clip =
      cam.projection(static_cast<float>(w) / static_cast<float>(h)) * cam.view() * glm::vec4(p, 1.0f);
  return {static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * static_cast<float>(w)),
          static_cast<int>((0.5f - clip.y / clip.w * 0.5f) * static_cast<float>(h))};
}

struct Looks {
  double scalp_bare = 0;        // share of the scalp with no root within 5 mm
  double shows[3] = {0, 0, 0};  // front, three-quarter, back
};

Looks measure(const std::string& style) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
  scene.hair.style = lhtest::sourceDir() + "/data/styles/" + style + ".json";
  scene.hair.particles = 3000;
  BuildReport build;
  const Solver solver = buildSolver(scene, &build);
  RenderStrandOptions so;
  so.strands = 12000;
  so.points = 16;
  const StrandField field = bindSceneStrands(scene, solver.particles(), build, so, 2);
  FrameInput input = frameFromSolver(solver, build.mean_neighbor_distance);
  field.deformWorld(solver, input.strand_points, 2);
  input.strand_points_each = so.points;
  const TriangleMesh head = decimate(loadMesh(scene.head_mesh.path), 16000);
  const TriangleMesh torso = decimate(loadMesh(scene.torso_mesh.path), 8000);
  const float brows = measureHeadHeights(loadMesh(scene.head_mesh.path)).brows;

  Looks out;
  const Style st = loadStyle(scene.hair.style);
  const HeadModel model = HeadModel::build(st.head, st.source);
  const StrandSet members = buildMemberStrands(st, model);
  std::vector<glm::vec3> roots;
  for (std::size_t k = 0; k < members.size(); ++k) roots.push_back(members.points[members.first[k]]);
  out.scalp_bare = 1.0 - scalpCoverage(model, roots).covered;

  const int w = 320, h = 320;
  app::HeadlessGL gl(w, h);
  Renderer r;
  r.setBodies(&head, &torso);
  // the hair pure green and unshadowed, so that hair is told from skin by
  // its hue however dark it is drawn
  RenderSettings with;
  with.hair = HairGeometry::Strands;
  with.custom_color = glm::vec3(0.0f, 0.8f, 0.0f);
  with.shadows = false;
  RenderSettings bare = with;
  bare.hair = HairGeometry::Billboards;
  bare.hair_opacity = 0.0f;
  const char* cameras[3] = {"front", "three-quarter", "back"};
  for (int c = 0; c < 3; ++c) {
    const Camera cam = Camera::preset(cameras[c]);
    r.render(input, cam, with, w, h);
    const Image hair{w, h, gl.pixels()};
    r.render(input, cam, bare, w, h);
    const Image skin{w, h, gl.pixels()};
    if (std::getenv("LOOSEHAIR_KEEP_IMAGES"))
      app::writePng("/tmp/looks-" + style + "-" + cameras[c] + ".png", hair.rgba, w, h);
    const int brow_row = toPixel(cam, w, h, glm::vec3(0.0f, brows, 0.0f)).y;
    int head_px = 0, showing = 0;
    for (int y = 0; y < std::min(brow_row, h); ++y)
      for (int x = 0; x < w; ++x) {
        if (glm::length(skin.at(x, y) - with.background) < 0.04f) continue;  // not the head
        ++head_px;
        const glm::vec3 c = hair.at(x, y);
        showing += c.g > c.r + 0.03f && c.g > c.b + 0.03f ? 0 : 1;
      }
    out.shows[c] = head_px > 0 ? static_cast<double>(showing) / head_px : 1.0;
  }
  std::printf(
      "%-14s scalp with no root within 5 mm %5.1f%%; head above the brows showing: front %5.1f%%, "
      "three-quarter %5.1f%%, back %5.1f%%\n",
      style.c_str(), 100 * out.scalp_bare, 100 * out.shows[0], 100 * out.shows[1], 100 * out.shows[2]);
  return out;
}

// The figures measured when the styles were remade, a few points above:
// front and three-quarter (the forehead below the hairline counts; the
// styles combed back show most of it), back.
struct Bound {
  const char* style;
  double front, three_quarter, back;
};
constexpr Bound kBounds[] = {{"long-straight", 0.65, 0.33, 0.06}, {"bob", 0.12, 0.12, 0.03},
                             {"side-swept", 0.43, 0.13, 0.06},    {"swept-back", 0.74, 0.48, 0.03},
                             {"wavy", 0.63, 0.33, 0.06},          {"ponytail", 0.92, 0.68, 0.03}};

void PrintTo(const Bound& b, std::ostream* os) { *os << b.style; }

class BundledStyleLooks : public ::testing::TestWithParam<Bound> {};

}  // namespace

TEST_P(BundledStyleLooks, TheScalpIsCoveredAndTheHeadHiddenAboveTheBrows) {
  const Bound b = GetParam();
  const Looks l = measure(b.style);
  EXPECT_LT(l.scalp_bare, 0.03) << "97% of the hair region covered (the issue's goal)";
  EXPECT_LT(l.shows[0], b.front);
  EXPECT_LT(l.shows[1], b.three_quarter);
  EXPECT_LT(l.shows[2], b.back);
}

INSTANTIATE_TEST_SUITE_P(Styles, BundledStyleLooks, ::testing::ValuesIn(kBounds),
                         [](const ::testing::TestParamInfo<Bound>& i) {
                           std::string n = i.param.style;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });
