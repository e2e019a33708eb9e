#include "loosehair/head_model.hpp"

#include "bodies/head_orientation.hpp"
#include "init/mesh_scalp.hpp"
#include "init/scalp_surface.hpp"
#include "loosehair/json_checks.hpp"
#include "mesh/nearest_triangle.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>

namespace loosehair {
namespace {

// The float spacing of positions at a mesh's farthest point, against its
// size, above which the build warns (a 0.2 m head 17 m from the origin:
// 2 um, twice the 1 um contact skin) and refuses (1.7 km: 0.2 mm; at 17 km
// the scalp's harmonic map was singular).
constexpr float kWarnPositionSpacing = 1e-5f;
constexpr float kMaxPositionSpacing = 1e-3f;

std::string num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Handles (the genus summed over the closed parts), from Euler's formula
// V - E + F = 2 (parts - handles): a torus has one.
std::size_t handles(const TriangleMesh& mesh) {
  std::vector<char> used(mesh.vertices.size(), 0);
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const glm::u32vec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      used[a] = 1;
      edges.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  const auto e = static_cast<long long>(std::unique(edges.begin(), edges.end()) - edges.begin());
  const auto v = static_cast<long long>(std::count(used.begin(), used.end(), 1));
  const auto f = static_cast<long long>(mesh.triangles.size());
  const auto parts = static_cast<long long>(meshParts(mesh).count());
  const long long twice = 2 * parts - (v - e + f);
  return twice > 0 ? static_cast<std::size_t>(twice / 2) : 0;
}

TriangleMesh sphereMesh(glm::vec3 c, float r) {
  TriangleMesh m;
  const int rings = 24, sectors = 48;
  for (int i = 0; i <= rings; ++i) {
    const double th = std::numbers::pi * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double ph = 2.0 * std::numbers::pi * j / sectors;
      m.vertices.push_back(
          c + r * glm::vec3(glm::dvec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph))));
    }
  }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * sectors + (j % sectors)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      if (i > 0) m.triangles.emplace_back(at(i, j), at(i, j + 1), at(i + 1, j));
      if (i + 1 < rings) m.triangles.emplace_back(at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
    }
  return m;
}

// The pieces a mesh collides as: each separate part at least a tenth of
// the mesh's size a piece of its own (up to kMaxPieces, the largest by
// triangles), the other parts with the largest one; one piece (the mesh
// itself) when there is nothing to separate.
constexpr std::size_t kMaxPieces = 8;
std::vector<TriangleMesh> collisionPieces(const TriangleMesh& mesh) {
  const MeshParts parts = meshParts(mesh);
  if (parts.count() < 2) return {mesh};
  std::vector<glm::vec3> lo(parts.count(), glm::vec3(INFINITY)), hi(parts.count(), glm::vec3(-INFINITY));
  glm::vec3 all_lo(INFINITY), all_hi(-INFINITY);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 v = mesh.vertices[mesh.triangles[t][c]];
      const std::uint32_t q = parts.of_triangle[t];
      lo[q] = glm::min(lo[q], v);
      hi[q] = glm::max(hi[q], v);
      all_lo = glm::min(all_lo, v);
      all_hi = glm::max(all_hi, v);
    }
  const auto extent = [](glm::vec3 a, glm::vec3 b) {
    const glm::vec3 e = b - a;
    return std::max({e.x, e.y, e.z});
  };
  const float size = extent(all_lo, all_hi);
  std::vector<std::uint32_t> large;
  for (std::uint32_t q = 0; q < parts.count(); ++q)
    if (extent(lo[q], hi[q]) >= 0.1f * size) large.push_back(q);
  std::stable_sort(large.begin(), large.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return parts.triangles[a] > parts.triangles[b]; });
  if (large.size() > kMaxPieces) large.resize(kMaxPieces);
  if (large.size() < 2) return {mesh};
  // each part's piece: its own, or the first (largest) piece
  std::vector<std::uint32_t> piece_of(parts.count(), 0);
  for (std::uint32_t k = 0; k < large.size(); ++k) piece_of[large[k]] = k;
  std::vector<TriangleMesh> pieces(large.size());
  // a vertex belongs to one part (the parts are joined through vertices),
  // so to one piece: its index there
  std::vector<std::uint32_t> index(mesh.vertices.size(), UINT32_MAX);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t k = piece_of[parts.of_triangle[t]];
    glm::u32vec3 tri;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = mesh.triangles[t][c];
      if (index[v] == UINT32_MAX) {
        index[v] = static_cast<std::uint32_t>(pieces[k].vertices.size());
        pieces[k].vertices.push_back(mesh.vertices[v]);
      }
      tri[c] = index[v];
    }
    pieces[k].triangles.push_back(tri);
  }
  return pieces;
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

std::string metres(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.3g m", v);
  return std::string(buf);
}

// A head or torso mesh as the scene names it (`field`), refused where the
// collision structures would take too much memory (about 360 bytes a
// triangle: 5 million took 1.8 GB and half a minute; refused from the
// file's header where it has one, before the mesh is read).
TriangleMesh loadBodyMesh(const MeshSpec& spec, const std::string& field, const std::string& source,
                          const MeshLimits& limits, BuildReport& rep) {
  TriangleMesh mesh;
  const auto t0 = Clock::now();
  MeshReport mesh_report;
  MeshLoadOptions load = spec.load;
  load.max_faces = limits.max_triangles;
  try {
    mesh = loadMesh(spec.path, load, &mesh_report);
  } catch (const MeshTooLargeError& e) {
    throw SceneError(source + ": " + field + ".mesh: " + e.what() +
                     " (about 360 bytes of memory a triangle): decimate it (or --allow-expensive)");
  } catch (const MeshError& e) {
    throw SceneError(source + ": " + field + ".mesh: " + e.what());
  }
  rep.seconds_meshes += since(t0);
  if (mesh_report.parts_dropped > 0)
    rep.warnings.push_back(field + ".mesh: dropped " + std::to_string(mesh_report.parts_dropped) +
                           " open part(s) besides the largest (" + std::to_string(mesh_report.triangles_dropped) +
                           " triangles: eyes, teeth or helper geometry enclose no volume); the hair "
                           "collides with the rest");
  return mesh;
}

// The mesh's size and placement checked (no size, far from the origin, a
// head far from human size, a distance grid too large); warnings into
// `rep`. Returns the mesh's bounding box extent.
glm::vec3 checkBodyMesh(const TriangleMesh& mesh, const MeshSpec& spec, const std::string& field,
                        const std::string& source, const MeshLimits& limits, BuildReport& rep) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& v : mesh.vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::vec3 extent = hi - lo;
  const float size = std::max({extent.x, extent.y, extent.z});
  // A head or body of no size (a tiny scale) has no surface to hang hair on
  if (!(size >= 1e-3f))
    throw SceneError(source + ": " + field + ".scale: the mesh is " + metres(size) + " across after scaling (scale " +
                     num(spec.load.scale) + "); a " + field + " is tenths of a metre: set " + field +
                     ".scale to the mesh's unit in metres (0.01 for centimetres, 0.001 for millimetres)");
  // Positions are single precision: far from the origin they are coarse
  // against the mesh (at its bounding box's farthest corner)
  const float reach = glm::length(glm::max(glm::abs(lo), glm::abs(hi)));
  const float spacing = reach * std::numeric_limits<float>::epsilon();
  if (spacing > kWarnPositionSpacing * size) {
    const glm::vec3 mid = 0.5f * (lo + hi);
    const std::string text = std::filesystem::path(spec.path).filename().string() + ": the mesh lies " + metres(reach) +
                             " from the origin, where positions are " + metres(spacing) + " apart (" +
                             num(spacing / size) + " of its " + metres(size) + " size): move it near the origin with " +
                             field + ".offset [" + num(-mid.x) + ", " + num(-mid.y) + ", " + num(-mid.z) + "]";
    if (spacing > kMaxPositionSpacing * size) throw SceneError(source + ": " + field + ".mesh: " + text);
    rep.warnings.push_back(field + ".mesh: " + text);
  }
  if (field == "head")
    for (std::string& w : headOrientationWarnings(mesh, field)) rep.warnings.push_back(std::move(w));
  // a whole body in metres (1.2-2.3 m tall, and taller than wide or deep)
  // is a head with a body below it, not a head in the wrong unit
  const bool whole_body = extent.y >= 1.2f && extent.y <= 2.3f && extent.y >= std::max(extent.x, extent.z);
  // The head's own width: across the top 30% of the mesh's height, where a
  // bust's or a body's head is (a bust with arms is 0.8 m across, its head
  // 0.2 m); for a head alone, the width of its crown
  glm::vec2 top_lo(INFINITY), top_hi(-INFINITY);
  for (const glm::vec3& v : mesh.vertices)
    if (v.y >= hi.y - 0.3f * extent.y) {
      top_lo = glm::min(top_lo, glm::vec2(v.x, v.z));
      top_hi = glm::max(top_hi, glm::vec2(v.x, v.z));
    }
  const float head_width = std::max(top_hi.x - top_lo.x, top_hi.y - top_lo.y);
  if (field == "head" && (head_width < 0.08f || (head_width > 0.6f && !whole_body)))
    rep.warnings.push_back(field + ": the mesh's head is " + metres(head_width) + " across (the whole mesh " +
                           metres(size) + "), far from a human head (about 0.2 m); if its unit is not the metre, set " +
                           field + ".scale (0.01 for centimetres, 0.001 for millimetres, 0.0254 for inches)");
  if (spec.sdf_voxel > 0.0f) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::ceil(extent[a] / spec.sdf_voxel) + 8.0;
    if (cells > limits.max_sdf_cells)
      throw SceneError(source + ": " + field + ".sdf_voxel: " + metres(spec.sdf_voxel) + " makes a distance grid of " +
                       std::to_string(static_cast<long long>(cells / 1e6)) + " million cells (" +
                       std::to_string(static_cast<long long>(cells * 4 / 1e9)) + " GB), above the limit of " +
                       std::to_string(static_cast<long long>(limits.max_sdf_cells / 1e6)) +
                       " million: use a larger sdf_voxel or \"auto\" (or --allow-expensive)");
  }
  return extent;
}

// The collision body of a mesh: its signed-distance grid (baked, or from
// the cache) under the exact triangles; separate parts that may overlap (a
// neck pushed into a bust) each a body of their own, the union of them the
// body (body.hpp's UnionBody); small parts stay with the largest.
std::shared_ptr<const Body> bakeBody(const TriangleMesh& mesh, const MeshSpec& spec, const std::string& field,
                                     const std::string& source, float size, BuildReport& rep) {
  const std::string cache = GridSdfBody::defaultCacheDir();
  const auto t0 = Clock::now();
  SdfBakeOptions opt;
  opt.voxel_size = spec.sdf_voxel;
  // 4 cm around a head, less around a tiny one (a mesh in the wrong unit):
  // its automatic voxels are tiny too, and a 4 cm margin of them made a
  // 2 cm head bake for a minute
  opt.margin = std::min(opt.margin, 0.25f * size);
  opt.cache_dir = cache;
  bool all_cached = true;
  auto bodyOf = [&](const TriangleMesh& piece) {
    bool cached = false;
    std::shared_ptr<GridSdfBody> grid;
    try {
      grid = GridSdfBody::bake(piece, opt, &cached);
    } catch (const MeshError& e) {
      throw SceneError(source + ": " + field + ".sdf_voxel: " + e.what());
    } catch (const std::bad_alloc&) {
      throw SceneError(source + ": " + field + ".sdf_voxel: not enough memory for the distance grid");
    } catch (const std::exception& e) {
      throw SceneError(source + ": " + field + ": the signed-distance bake failed (" + clipped(e.what(), 200) + ")");
    }
    all_cached = all_cached && cached;
    return std::make_shared<MeshBody>(piece, grid);
  };
  const std::vector<TriangleMesh> pieces = collisionPieces(mesh);
  std::shared_ptr<const Body> result;
  if (pieces.size() == 1) {
    result = bodyOf(mesh);
  } else {
    auto joined = std::make_shared<UnionBody>();
    for (const TriangleMesh& piece : pieces) joined->add(bodyOf(piece));
    result = joined;
  }
  rep.sdf_from_cache = all_cached;
  rep.seconds_sdf += since(t0);
  return result;
}

// A head or torso from its mesh: loaded, checked, its body baked.
std::shared_ptr<const Body> meshBody(const MeshSpec& spec, const std::string& field, const std::string& source,
                                     const MeshLimits& limits, BuildReport& rep, TriangleMesh& mesh) {
  mesh = loadBodyMesh(spec, field, source, limits, rep);
  const glm::vec3 extent = checkBodyMesh(mesh, spec, field, source, limits, rep);
  return bakeBody(mesh, spec, field, source, std::max({extent.x, extent.y, extent.z}), rep);
}

// A sphere head of no size is refused, one far from human size warned of.
void checkSphereHead(const HeadDesc& desc, const std::string& source, BuildReport& rep) {
  if (desc.head_radius < 5e-4)
    throw SceneError(source + ": head.radius: " + num(desc.head_radius) +
                     " m has no surface to hang hair on; a human head is about 0.1 m");
  if (desc.head_radius < 0.04 || desc.head_radius > 0.3)
    rep.warnings.push_back("head.radius: " + num(desc.head_radius) + " m is far from a human head (about 0.1 m)");
}

}  // namespace

HeadModel::HeadModel() = default;
HeadModel::HeadModel(HeadModel&&) noexcept = default;
HeadModel& HeadModel::operator=(HeadModel&&) noexcept = default;
HeadModel::~HeadModel() = default;

// The head from its mesh: the body, the scalp (the scene's four curves or
// the automatic ones) mapped to the square.
void HeadModel::buildMeshHead(const HeadDesc& desc, const std::string& source, const MeshLimits& limits,
                              BuildReport& rep) {
  TriangleMesh mesh;
  auto body = meshBody(desc.head_mesh, "head", source, limits, rep, mesh);
  rep.head_vertices = mesh.vertices.size();
  rep.head_triangles = mesh.triangles.size();
  const auto t0 = Clock::now();
  ScalpCurves curves;
  if (desc.scalp_kind == ScalpKind::Curves) {
    for (std::size_t k = 0; k < 4; ++k) curves.control[k] = desc.scalp_curves[k];
  } else {
    curves = automaticScalpCurves(mesh, *body);
  }
  try {
    auto ms = std::make_unique<MeshScalp>(mesh, *body, curves, desc.head_mesh.path);
    rep.scalp_triangles = ms->report().triangles;
    rep.scalp_area = ms->report().area;
    rep.scalp_mean_value = ms->report().mean_value_weights;
    scalp_ = std::move(ms);
  } catch (const MeshError& e) {
    // what the mesh looked like may explain it
    std::string notes;
    for (const std::string& w : rep.warnings) notes += "\n  (" + w + ")";
    if (const std::size_t h = handles(mesh); h > 0)
      notes += "\n  (head.mesh: the mesh has " + std::to_string(h) + (h == 1 ? " handle" : " handles") +
               ", a hole right through it as in a ring: the scalp is mapped to a square, which needs a "
               "head shaped like a ball)";
    throw SceneError(source + ": scalp: " + e.what() + notes);
  }
  rep.seconds_scalp = since(t0);
  head_ = body;
  head_mesh_ = std::move(mesh);
}

// The scalp as triangles (picking, regions, nearest points), their (u, v)
// buckets, and the head's mirror plane.
void HeadModel::buildScalpTables() {
  ScalpTriangles& t = tris_;
  if (const auto* ms = dynamic_cast<const MeshScalp*>(scalp_.get())) {
    t.positions = ms->positions();
    t.uvs = ms->uvs();
    t.triangles = ms->triangles();
  } else {
    const int g = 48;
    for (int i = 0; i <= g; ++i)
      for (int j = 0; j <= g; ++j) {
        const glm::vec2 uv(static_cast<float>(j) / g, static_cast<float>(i) / g);
        t.uvs.push_back(uv);
        t.positions.push_back(scalp_->point(uv));
      }
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j) {
        const auto a = static_cast<std::uint32_t>(i * (g + 1) + j);
        // counter-clockwise in (u, v); outward on the cap as on the mesh scalp
        t.triangles.emplace_back(a, a + 1, a + g + 2);
        t.triangles.emplace_back(a, a + g + 2, a + g + 1);
      }
  }
  for (const auto& tr : t.triangles)
    t.areas.push_back(0.5 * glm::length(glm::cross(glm::dvec3(t.positions[tr.y] - t.positions[tr.x]),
                                                   glm::dvec3(t.positions[tr.z] - t.positions[tr.x]))));
  nearest_ = std::make_unique<NearestTriangle>(t.positions, t.triangles);
  // uv buckets for scalpTriangleAt
  buckets_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(t.triangles.size()) / 2.0)));
  const int nb = buckets_;
  std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(nb * nb));
  for (std::uint32_t k = 0; k < t.triangles.size(); ++k) {
    const auto tr = t.triangles[k];
    const glm::vec2 lo = glm::min(t.uvs[tr.x], glm::min(t.uvs[tr.y], t.uvs[tr.z]));
    const glm::vec2 hi = glm::max(t.uvs[tr.x], glm::max(t.uvs[tr.y], t.uvs[tr.z]));
    const int x0 = std::clamp(static_cast<int>(lo.x * static_cast<float>(nb)), 0, nb - 1),
              x1 = std::clamp(static_cast<int>(hi.x * static_cast<float>(nb)), 0, nb - 1);
    const int y0 = std::clamp(static_cast<int>(lo.y * static_cast<float>(nb)), 0, nb - 1),
              y1 = std::clamp(static_cast<int>(hi.y * static_cast<float>(nb)), 0, nb - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) lists[static_cast<std::size_t>(y * nb + x)].push_back(k);
  }
  bucket_start_.assign(1, 0);
  for (const auto& l : lists) {
    bucket_items_.insert(bucket_items_.end(), l.begin(), l.end());
    bucket_start_.push_back(static_cast<std::uint32_t>(bucket_items_.size()));
  }
  float lo = INFINITY, hi = -INFINITY;
  for (const glm::vec3& v : head_mesh_.vertices) {
    lo = std::min(lo, v.x);
    hi = std::max(hi, v.x);
  }
  mirror_x_ = 0.5f * (lo + hi);
}

HeadModel HeadModel::build(const HeadDesc& desc, const std::string& source, const MeshLimits& limits,
                           BuildReport* report) {
  BuildReport local;
  BuildReport& rep = report ? *report : local;
  HeadModel m;
  m.desc_ = desc;
  if (desc.head_kind == HeadKind::Sphere) {
    checkSphereHead(desc, source, rep);
    m.scalp_ = std::make_unique<SphereCapScalp>(desc.head_center, desc.head_radius, glm::radians(desc.cap_angle_deg));
    m.head_ = std::make_shared<SphereBody>(desc.head_center, desc.head_radius);
    m.head_mesh_ = sphereMesh(desc.head_center, desc.head_radius);
  } else {
    m.buildMeshHead(desc, source, limits, rep);
  }
  if (desc.has_torso) {
    TriangleMesh mesh;
    m.torso_ = meshBody(desc.torso_mesh, "torso", source, limits, rep, mesh);
    rep.torso_triangles = mesh.triangles.size();
  }
  m.buildScalpTables();
  return m;
}

glm::vec3 HeadModel::scalpPoint(glm::vec2 uv) const { return scalp_->point(uv); }
glm::vec3 HeadModel::scalpNormal(glm::vec2 uv) const { return scalp_->normal(uv); }
double HeadModel::scalpArea() const { return scalp_->area(); }

glm::vec3 HeadModel::scalpTangentU(glm::vec2 uv) const {
  const glm::vec3 n = scalpNormal(uv);
  const float du = 2e-3f;
  const float a = std::max(0.0f, uv.x - du), b = std::min(1.0f, uv.x + du);
  glm::vec3 d = scalpPoint({b, uv.y}) - scalpPoint({a, uv.y});
  d -= glm::dot(d, n) * n;
  if (glm::length(d) < 1e-9f) {  // u does not move the point here (a pole of the map)
    const float c = std::max(0.0f, uv.y - du), e = std::min(1.0f, uv.y + du);
    const glm::vec3 dv = scalpPoint({uv.x, e}) - scalpPoint({uv.x, c});
    d = glm::cross(dv, n);
    d -= glm::dot(d, n) * n;
  }
  if (glm::length(d) < 1e-12f) {
    d = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    d -= glm::dot(d, n) * n;
  }
  return glm::normalize(d);
}

glm::vec2 HeadModel::nearestScalpUv(glm::vec3 p, float* distance) const {
  glm::vec2 uv(0.5f);
  if (nearest_) {
    const NearestTriangle::Hit h = nearest_->nearest(p);
    if (std::isfinite(h.distance)) {
      const auto tr = tris_.triangles[h.triangle];
      const glm::vec3 l = h.barycentric;
      uv = l.x * tris_.uvs[tr.x] + l.y * tris_.uvs[tr.y] + l.z * tris_.uvs[tr.z];
    }
  }
  uv = glm::clamp(uv, glm::vec2(0.0f), glm::vec2(1.0f));
  if (distance) *distance = glm::length(scalpPoint(uv) - p);
  return uv;
}

std::uint32_t HeadModel::scalpTriangleAt(glm::vec2 uv) const {
  uv = glm::clamp(uv, glm::vec2(0.0f), glm::vec2(1.0f));
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(buckets_)), 0, buckets_ - 1);
  const int y = std::clamp(static_cast<int>(uv.y * static_cast<float>(buckets_)), 0, buckets_ - 1);
  const std::size_t b = static_cast<std::size_t>(y * buckets_ + x);
  float best = -INFINITY;
  std::uint32_t best_t = 0;
  auto test = [&](std::uint32_t k) {
    const auto tr = tris_.triangles[k];
    const glm::vec2 a = tris_.uvs[tr.x], e1 = tris_.uvs[tr.y] - a, e2 = tris_.uvs[tr.z] - a, q = uv - a;
    const float det = e1.x * e2.y - e1.y * e2.x;
    if (!(det > 0.0f)) return false;
    const float l1 = (q.x * e2.y - q.y * e2.x) / det, l2 = (e1.x * q.y - e1.y * q.x) / det;
    const float worst = std::min({1.0f - l1 - l2, l1, l2});
    if (worst > best) {
      best = worst;
      best_t = k;
    }
    return worst >= 0.0f;
  };
  for (std::uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k)
    if (test(bucket_items_[k])) return best_t;
  if (best == -INFINITY)
    for (std::uint32_t k = 0; k < tris_.triangles.size(); ++k) test(k);
  return best_t;
}

std::vector<std::uint32_t> HeadModel::scalpTrianglesNear(glm::vec2 lo, glm::vec2 hi) const {
  std::vector<std::uint32_t> out;
  if (!(lo.x <= hi.x && lo.y <= hi.y)) return out;
  const float nb = static_cast<float>(buckets_);
  auto bucket = [&](float c) { return std::clamp(static_cast<int>(std::floor(c * nb)), 0, buckets_ - 1); };
  // a triangle is listed in every bucket its box overlaps, and the boxes
  // overlap in a point whose bucket is in this range
  for (int y = bucket(lo.y); y <= bucket(hi.y); ++y)
    for (int x = bucket(lo.x); x <= bucket(hi.x); ++x) {
      const std::size_t b = static_cast<std::size_t>(y * buckets_ + x);
      out.insert(out.end(), bucket_items_.begin() + bucket_start_[b], bucket_items_.begin() + bucket_start_[b + 1]);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

float HeadModel::headDistance(glm::vec3 p) const {
  float phi = 0;
  glm::vec3 n;
  head_->signedDistance(&p, 1, &phi, &n);
  return phi;
}

}  // namespace loosehair
