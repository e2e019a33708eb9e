// The API side of the viewer's scripted styling session
// (tests/viewer/styling-session.json): the same operations made with the
// library (StyleEditor, ray picking through the same camera) must give the
// style file the viewer saved, byte for byte.
//
//   loosehair_style_session_check SCENE WIDTH HEIGHT VIEWER_STYLE.json
//   loosehair_style_session_check --hair-pixels SIMULATED.png BARE.png
// The second form checks that a picture shows hair: its share of
// hair-coloured pixels where the bare head's picture (same view) shows
// something else is above 2%.
#include "loosehair/file_io.hpp"
#include "loosehair/ray_pick.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/style_editor.hpp"

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

}  // namespace

int main(int argc, char** argv) {
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
