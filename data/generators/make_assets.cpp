// Generates the bundled assets of data/ (run by `loosehair_make_assets DIR`;
// the committed files are its output, and a test checks that they still are):
//
//   meshes/head.ply   a human head with a neck, closed, outward-facing,
//                     metres, +Y up, face towards +Z, origin on the neck axis
//                     at ear height (the pivot of head turns and nods)
//   meshes/torso.ply  shoulders and chest (a bust), same frame
//   maps/hair_length.png  default hair-length map over the scalp square
//                     (u left to right ear, v forehead to nape): a short
//                     fringe, longer sides, longest at the back
//
// Each body is the zero set of a smooth signed-distance-like function built
// from ellipsoids and capsules joined by smooth minima. It is meshed as a
// star-shaped surface: every vertex of a finely subdivided icosahedron is
// pushed along its direction from a centre to the outermost crossing of the
// zero set, so the mesh is closed, manifold and keeps the icosahedron's
// outward orientation by construction.
#include "loosehair/mesh.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <vector>

namespace {

using glm::dvec3;

double ellipsoid(dvec3 p, dvec3 c, dvec3 r) {
  const dvec3 q = (p - c) / r;
  const double k0 = glm::length(q);
  const double k1 = glm::length(q / r);
  return k1 > 0 ? k0 * (k0 - 1.0) / k1 : -std::min({r.x, r.y, r.z});
}

double capsule(dvec3 p, dvec3 a, dvec3 b, double r) {
  const dvec3 pa = p - a, ba = b - a;
  const double h = std::clamp(glm::dot(pa, ba) / glm::dot(ba, ba), 0.0, 1.0);
  return glm::length(pa - h * ba) - r;
}

double roundBox(dvec3 p, dvec3 c, dvec3 half, double round) {
  const dvec3 q = glm::abs(p - c) - half;
  return glm::length(glm::max(q, dvec3(0.0))) + std::min(std::max({q.x, q.y, q.z}), 0.0) - round;
}

// Polynomial smooth minimum / maximum with blend width k (m).
double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

// A mannequin's head (as wig makers use), adult proportions: 23 cm from
// chin to crown, 15 cm across, 19 cm deep; the eyes halfway down, in
// sockets under a brow; the nose's tip a third of the way from the brows to
// the chin, the mouth a third of the way from the nose to the chin; the
// ears between the brows' and the nose tip's heights, just behind the
// middle of the head; a jaw narrowing to the chin; a neck that goes down
// into the torso with the torso's own neck just inside it, so no seam
// shows where they meet.
double head(dvec3 p) {
  double d = ellipsoid(p, {0, 0.045, -0.012}, {0.074, 0.088, 0.096});          // cranium
  d = smin(d, ellipsoid(p, {0, 0.000, 0.030}, {0.062, 0.080, 0.068}), 0.025);  // face
  for (double s : {-1.0, 1.0}) {
    d = smin(d, capsule(p, {s * 0.047, -0.050, -0.004}, {s * 0.014, -0.088, 0.066}, 0.011), 0.022);  // jaw
    d = smin(d, ellipsoid(p, {s * 0.046, 0.008, 0.066}, {0.016, 0.013, 0.014}), 0.015);              // cheekbones
    d = smin(d, ellipsoid(p, {s * 0.038, -0.020, 0.064}, {0.018, 0.019, 0.015}), 0.018);             // cheeks
    d = smin(d, ellipsoid(p, {s * 0.071, 0.000, -0.010}, {0.011, 0.030, 0.019}), 0.006);             // ears
  }
  d = smin(d, ellipsoid(p, {0, -0.086, 0.072}, {0.021, 0.015, 0.016}), 0.015);  // chin
  d = smin(d, ellipsoid(p, {0, 0.046, 0.078}, {0.054, 0.012, 0.016}), 0.015);   // brow
  for (double s : {-1.0, 1.0}) {
    d = smax(d, -ellipsoid(p, {s * 0.031, 0.026, 0.095}, {0.017, 0.011, 0.012}), 0.006);    // eye sockets
    d = smin(d, ellipsoid(p, {s * 0.031, 0.025, 0.077}, {0.0122, 0.0115, 0.0122}), 0.003);  // eyes, lids half shut
  }
  d = smin(d, capsule(p, {0, 0.032, 0.096}, {0, -0.010, 0.111}, 0.0075), 0.012);  // nose bridge
  d = smin(d, ellipsoid(p, {0, -0.015, 0.110}, {0.012, 0.010, 0.011}), 0.006);    // nose tip
  for (double s : {-1.0, 1.0})
    d = smin(d, ellipsoid(p, {s * 0.012, -0.019, 0.101}, {0.008, 0.007, 0.008}), 0.005);  // nostril wings
  d = smin(d, ellipsoid(p, {0, -0.038, 0.066}, {0.032, 0.030, 0.024}), 0.02);             // between nose and chin
  d = smin(d, ellipsoid(p, {0, -0.043, 0.090}, {0.020, 0.0060, 0.008}), 0.006);           // upper lip
  d = smin(d, ellipsoid(p, {0, -0.0535, 0.088}, {0.017, 0.0065, 0.008}), 0.006);          // lower lip
  d = smax(d, -ellipsoid(p, {0, -0.0485, 0.096}, {0.016, 0.0008, 0.006}), 0.0015);        // mouth
  // the neck ends inside the shoulders (its tip 2 cm above the bust's
  // bottom edge would be too low: cut flat there, the bust let hair in
  // under it onto the neck's tip), and a shorter neck swings less through
  // the torso when the head nods
  d = smin(d, capsule(p, {0, -0.03, -0.014}, {0, -0.20, -0.014}, 0.051), 0.03);  // neck
  return d;
}

double torso(dvec3 p) {
  double d = roundBox(p, {0, -0.45, -0.012}, {0.10, 0.14, 0.04}, 0.06);     // chest
  d = smin(d, ellipsoid(p, {0, -0.34, -0.012}, {0.16, 0.13, 0.10}), 0.06);  // rib cage
  for (double s : {-1.0, 1.0})                                              // shoulders
    d = smin(d, capsule(p, {s * 0.05, -0.205, -0.015}, {s * 0.165, -0.245, -0.015}, 0.05), 0.05);
  d = smin(d, capsule(p, {0, -0.17, -0.014}, {0, -0.28, -0.014}, 0.048), 0.07);  // base of the neck, inside the head's
  return d;
}

// Unit directions of an icosahedron subdivided `levels` times.
loosehair::TriangleMesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<dvec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& x : v) x = glm::normalize(x);
  std::vector<glm::u32vec3> f = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      const auto idx = static_cast<std::uint32_t>(v.size() - 1);
      mid.emplace(key, idx);
      return idx;
    };
    std::vector<glm::u32vec3> g;
    g.reserve(4 * f.size());
    for (const auto& tri : f) {
      const std::uint32_t a = midpoint(tri.x, tri.y), b = midpoint(tri.y, tri.z), c = midpoint(tri.z, tri.x);
      g.emplace_back(tri.x, a, c);
      g.emplace_back(tri.y, b, a);
      g.emplace_back(tri.z, c, b);
      g.emplace_back(a, b, c);
    }
    f = std::move(g);
  }
  loosehair::TriangleMesh m;
  for (const auto& x : v) m.vertices.emplace_back(glm::vec3(x));
  m.triangles = std::move(f);
  return m;
}

// Pushes every direction of `sphere` from `centre` to the outermost zero
// crossing of `sdf` within `reach` metres.
loosehair::TriangleMesh starMesh(const std::function<double(dvec3)>& sdf, dvec3 centre, double reach, int levels) {
  loosehair::TriangleMesh m = icosphere(levels);
  const double step = 0.0005;
  for (auto& vert : m.vertices) {
    const dvec3 d(vert);
    double last_inside = 0;
    for (double r = 0; r <= reach; r += step)
      if (sdf(centre + r * d) < 0) last_inside = r;
    double a = last_inside, b = last_inside + step;  // inside at a, outside at b
    for (int it = 0; it < 40; ++it) {
      const double c = 0.5 * (a + b);
      (sdf(centre + c * d) < 0 ? a : b) = c;
    }
    vert = glm::vec3(centre + 0.5 * (a + b) * d);
  }
  return m;
}

bool writeLengthMap(const std::string& path, int size) {
  std::vector<unsigned char> img(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;  // row y is v
      const double back = std::clamp(v / 0.75, 0.0, 1.0);
      const double smooth_back = back * back * (3.0 - 2.0 * back);
      const double side = std::abs(2.0 * u - 1.0);  // 0 at the parting, 1 at the ears
      double len = 0.30 + 0.70 * smooth_back;       // fringe 30%, back 100%
      len = std::max(len, 0.55 * side * side);      // sides reach below the ears
      img[static_cast<std::size_t>(y * size + x)] =
          static_cast<unsigned char>(std::lround(255.0 * std::clamp(len, 0.0, 1.0)));
    }
  const std::string tmp = path + ".tmp";
  if (!stbi_write_png(tmp.c_str(), size, size, 1, img.data(), size)) return false;
  std::filesystem::rename(tmp, path);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr,
                 "usage: %s DATA_DIR\n  writes DATA_DIR/meshes/{head,torso}.ply and DATA_DIR/maps/hair_length.png\n",
                 argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  try {
    std::filesystem::create_directories(dir / "meshes");
    std::filesystem::create_directories(dir / "maps");
    loosehair::TriangleMesh h = starMesh(head, {0, 0.0, 0.0}, 0.40, 6);
    auto rh = loosehair::checkMesh(h, "head");
    loosehair::writeBinaryPly(h, (dir / "meshes/head.ply").string());
    loosehair::TriangleMesh t = starMesh(torso, {0, -0.40, -0.01}, 0.45, 5);
    auto rt = loosehair::checkMesh(t, "torso");
    loosehair::writeBinaryPly(t, (dir / "meshes/torso.ply").string());
    if (!writeLengthMap((dir / "maps/hair_length.png").string(), 128)) {
      std::fprintf(stderr, "cannot write %s\n", (dir / "maps/hair_length.png").c_str());
      return 1;
    }
    std::printf("head: %zu vertices, %zu triangles, %.2f l, box (%.3f %.3f %.3f)-(%.3f %.3f %.3f)\n", rh.vertices,
                rh.triangles, rh.volume * 1e3, rh.lower.x, rh.lower.y, rh.lower.z, rh.upper.x, rh.upper.y, rh.upper.z);
    std::printf("torso: %zu vertices, %zu triangles, %.2f l\n", rt.vertices, rt.triangles, rt.volume * 1e3);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
