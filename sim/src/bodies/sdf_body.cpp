// Signed-distance grid of a mesh (method.md §5 body collisions). The bake uses
// OpenVDB (tools::meshToSignedDistanceField); the solver samples a dense copy.
#include "loosehair/file_io.hpp"
#include "loosehair/body.hpp"

#include "mesh/exact_distance.hpp"
#include "mesh/grid_value_bounds.hpp"
#include "util/parallel.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>

namespace loosehair {
namespace {

constexpr std::uint32_t kCacheMagic = 0x4c485344;  // "LHSD"
// 4: exact voxels near the surface, nearest triangles; 6: far values bounded
// by the triangles (5 was taken by unlanded experiments, whose grids may
// still sit in developers' caches)
constexpr std::uint32_t kCacheVersion = 6;

std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < bytes; ++k) {
    h ^= p[k];
    h *= 0x100000001b3ULL;
  }
  return h;
}

struct CacheHeader {
  std::uint32_t magic = kCacheMagic, version = kCacheVersion;
  std::uint64_t key = 0;
  float lower[3] = {0, 0, 0};
  float voxel = 0;
  std::int32_t dims[3] = {0, 0, 0};
};

}  // namespace

std::string GridSdfBody::defaultCacheDir() {
  if (const char* d = std::getenv("LOOSEHAIR_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::string(d) + "/loosehair";
  if (const char* d = std::getenv("HOME"); d && *d) return std::string(d) + "/.cache/loosehair";
  return {};
}

// Reads the grid from the cache file when it holds this key and placement
// (and its nearest triangles are triangles of the mesh).
bool GridSdfBody::readCache(const std::filesystem::path& cache_file, std::uint64_t key, std::size_t triangles) {
  const float voxel = voxel_;
  const glm::ivec3 dims = dims_;
  const double cells = static_cast<double>(dims.x) * dims.y * dims.z;
  GridSdfBody* body = this;
  std::ifstream in(cache_file, std::ios::binary);
  CacheHeader h;
  if (in && in.read(reinterpret_cast<char*>(&h), sizeof h) && h.magic == kCacheMagic && h.version == kCacheVersion &&
      h.key == key && h.voxel == voxel && h.dims[0] == dims.x && h.dims[1] == dims.y && h.dims[2] == dims.z) {
    body->values_.resize(static_cast<std::size_t>(cells));
    body->nearest_.resize(static_cast<std::size_t>(cells));
    bool ok = in.read(reinterpret_cast<char*>(body->values_.data()),
                      static_cast<std::streamsize>(body->values_.size() * sizeof(float))) &&
              in.read(reinterpret_cast<char*>(body->nearest_.data()),
                      static_cast<std::streamsize>(body->nearest_.size() * sizeof(std::int32_t)));
    for (std::size_t k = 0; ok && k < body->nearest_.size(); ++k)
      ok = body->nearest_[k] >= -1 && body->nearest_[k] < static_cast<std::int64_t>(triangles);
    if (ok) return true;
  }
  return false;
}

// The distances from OpenVDB's mesh-to-volume conversion (index space: the
// coordinates in voxels), with the nearest triangle of every voxel in the
// band, which the exact queries of MeshBody start from.
void GridSdfBody::convert(const TriangleMesh& mesh, glm::vec3 glo, float margin) {
  const float voxel = voxel_;
  const glm::ivec3 dims = dims_;
  const double cells = static_cast<double>(dims.x) * dims.y * dims.z;
  GridSdfBody* body = this;
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  std::vector<openvdb::Vec3s> points(mesh.vertices.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    points[v] = openvdb::Vec3s(mesh.vertices[v].x, mesh.vertices[v].y, mesh.vertices[v].z);
  // The conversion signs the distance by flooding the outside, so it needs a
  // closed mesh (checkMesh) but not any particular winding.
  std::vector<openvdb::Vec3I> tris(mesh.triangles.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    tris[t] = openvdb::Vec3I(mesh.triangles[t].x, mesh.triangles[t].y, mesh.triangles[t].z);
  auto xform = openvdb::math::Transform::createLinearTransform(static_cast<double>(voxel));
  const float band = margin / voxel + 2.0f;
  // The conversion works in index space (coordinates in voxels); it also
  // gives the nearest triangle of every voxel in the band, which the exact
  // queries of MeshBody start from.
  for (auto& p : points) p /= voxel;
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points.data(), points.size(),
                                                                                     tris.data(), tris.size());
  openvdb::Int32Grid index_grid(static_cast<openvdb::Int32>(openvdb::util::INVALID_IDX));
  // Without renormalisation the voxels keep their exact distances to the
  // nearest triangle, which the Lipschitz bounds of cell() rely on.
  auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *xform, band, std::numeric_limits<float>::max(),
                                                               openvdb::tools::DISABLE_RENORMALIZATION, &index_grid);
  auto acc = grid->getConstAccessor();
  auto index_acc = index_grid.getConstAccessor();
  body->values_.resize(static_cast<std::size_t>(cells));
  body->nearest_.resize(static_cast<std::size_t>(cells));
  const glm::ivec3 base(glo);
  const auto triangles = static_cast<std::int64_t>(mesh.triangles.size());
  std::size_t idx = 0;
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const openvdb::Coord ijk(base.x + i, base.y + j, base.z + k);
        body->values_[idx] = acc.getValue(ijk);
        const std::int64_t t = index_acc.getValue(ijk);
        body->nearest_[idx++] = t >= 0 && t < triangles ? static_cast<std::int32_t>(t) : -1;
      }
}

// The conversion's sign is unreliable a fraction of a voxel from the
// surface (on the bundled head about 1 voxel in 700 of the band has it
// flipped); MeshBody's bounds need exact voxels there, so the voxels within
// kExactBand voxels of the surface get the exact signed distance. (The
// conversion's distance is to some triangle, never below the exact one, so
// every voxel it put nearer than that is recomputed, and only those are: a
// value beyond the band may exceed the distance.)
void GridSdfBody::exactNearSurface(const TriangleMesh& mesh) {
  const float voxel = voxel_;
  const glm::ivec3 dims = dims_;
  GridSdfBody* body = this;
  const ExactDistance exact(mesh);
  const float near = kExactBand * voxel;
  const auto sx = static_cast<std::size_t>(dims.x), sy = static_cast<std::size_t>(dims.y);
  parallel::forEach(parallel::availableThreads(), static_cast<std::size_t>(dims.z), [&](std::size_t k) {
    for (std::size_t j = 0; j < sy; ++j)
      for (std::size_t i = 0; i < sx; ++i) {
        const std::size_t at = (k * sy + j) * sx + i;
        if (!(std::fabs(body->values_[at]) < near)) continue;
        const glm::vec3 c = body->lower_ + voxel * glm::vec3(glm::uvec3(i, j, k));
        const std::int32_t seed = body->nearest_[at];
        std::uint32_t tri = 0;
        const float d = exact.signedDistance(c, &seed, seed >= 0 ? 1 : 0, nullptr, &tri);
        if (!std::isfinite(d)) continue;
        body->values_[at] = d;
        body->nearest_[at] = static_cast<std::int32_t>(tri);
      }
  });
  // Beyond that band a value may exceed the distance; MeshBody's proofs of
  // clearance allow kFarAllowance voxel of that (grid_value_bounds.hpp),
  // and a voxel over it gets its exact value too.
  const GridValues view{body->lower_, voxel, dims, body->values_, body->nearest_};
  boundFarValues(exact, view, near, kFarAllowance * voxel, parallel::availableThreads());
}

// The grid into the cache (optional: a failed write leaves the next run to
// bake again).
void GridSdfBody::writeCache(const std::filesystem::path& cache_file, std::uint64_t key) const {
  const GridSdfBody* body = this;
  const float voxel = voxel_;
  const glm::ivec3 dims = dims_;
  std::error_code ec;
  std::filesystem::create_directories(cache_file.parent_path(), ec);
  CacheHeader h;
  h.key = key;
  for (int a = 0; a < 3; ++a) {
    h.lower[a] = body->lower_[a];
    h.dims[a] = dims[a];
  }
  h.voxel = voxel;
  try {
    AtomicFile out(cache_file.string());
    out.write({reinterpret_cast<const char*>(&h), sizeof h});
    out.write({reinterpret_cast<const char*>(body->values_.data()), body->values_.size() * sizeof(float)});
    out.write({reinterpret_cast<const char*>(body->nearest_.data()), body->nearest_.size() * sizeof(std::int32_t)});
    out.commit();
  } catch (const FileError&) {
    // a cache is optional: without it the next run bakes again
  }
}

std::shared_ptr<GridSdfBody> GridSdfBody::bake(const TriangleMesh& mesh, const SdfBakeOptions& opt, bool* from_cache) {
  if (from_cache) *from_cache = false;
  if (mesh.triangles.empty()) throw MeshError("signed-distance bake: the mesh has no triangles");
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : mesh.vertices) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(extent > 0.0f) || !std::isfinite(extent)) throw MeshError("signed-distance bake: the mesh has no extent");
  const float voxel = opt.voxel_size > 0.0f ? opt.voxel_size : extent / 128.0f;
  if (!(voxel > 0.0f) || !std::isfinite(voxel) || !(opt.margin >= 0.0f))
    throw MeshError("signed-distance bake: voxel size and margin must be positive");
  const float margin = std::max(opt.margin, 2.0f * voxel);
  const glm::vec3 glo = glm::floor((lo - margin) / voxel);
  const glm::vec3 ghi = glm::ceil((hi + margin) / voxel);
  const glm::ivec3 dims = glm::ivec3(ghi - glo) + 1;
  const double cells = static_cast<double>(dims.x) * dims.y * dims.z;
  if (cells > 4.0e8)
    throw MeshError("signed-distance bake: a grid of " + std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" +
                    std::to_string(dims.z) + " is too large; use a larger voxel size");

  auto body = std::shared_ptr<GridSdfBody>(new GridSdfBody());
  body->lower_ = glo * voxel;
  body->voxel_ = voxel;
  body->dims_ = dims;

  // Cache key: the mesh's bits and the grid's placement.
  std::uint64_t key = 0xcbf29ce484222325ULL;
  key = fnv(key, mesh.vertices.data(), mesh.vertices.size() * sizeof(glm::vec3));
  key = fnv(key, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::u32vec3));
  key = fnv(key, &voxel, sizeof voxel);
  key = fnv(key, &margin, sizeof margin);
  key = fnv(key, &kCacheVersion, sizeof kCacheVersion);
  std::filesystem::path cache_file;
  if (!opt.cache_dir.empty()) {
    char name[40];
    std::snprintf(name, sizeof name, "sdf-%016llx.bin", static_cast<unsigned long long>(key));
    cache_file = std::filesystem::path(opt.cache_dir) / name;
    if (body->readCache(cache_file, key, mesh.triangles.size())) {
      if (from_cache) *from_cache = true;
      body->computeBricks();
      return body;
    }
  }

  body->convert(mesh, glo, margin);
  body->exactNearSurface(mesh);
  body->computeBricks();

  if (!cache_file.empty()) {
    body->writeCache(cache_file, key);
  }
  return body;
}

// (inline: called per point in the queries below, the only callers)
inline std::size_t GridSdfBody::brickIndex(const glm::ivec3& b) const {
  return (static_cast<std::size_t>(b.z) * static_cast<std::size_t>(bricks_.y) + static_cast<std::size_t>(b.y)) *
             static_cast<std::size_t>(bricks_.x) +
         static_cast<std::size_t>(b.x);
}

inline void GridSdfBody::locate(const glm::vec3& p, const glm::vec3& top, float inv, glm::ivec3& c, glm::vec3& pc,
                                glm::vec3& f) const {
  pc = glm::clamp(p, lower_, top);
  const glm::vec3 q = (pc - lower_) * inv;
  c = glm::min(glm::ivec3(q), dims_ - 2);
  c = glm::max(c, glm::ivec3(0));
  f = q - glm::vec3(c);
}

void GridSdfBody::computeBricks() {
  // Cells 0 .. dims - 2 along each axis; brick b holds the cells [b kBrick,
  // (b + 1) kBrick), whose corners are the voxels [b kBrick, (b + 1) kBrick].
  bricks_ = (dims_ - 1 + (kBrick - 1)) / kBrick;
  brick_min_.resize(static_cast<std::size_t>(bricks_.x) * static_cast<std::size_t>(bricks_.y) *
                    static_cast<std::size_t>(bricks_.z));
  for (int bz = 0; bz < bricks_.z; ++bz)
    for (int by = 0; by < bricks_.y; ++by)
      for (int bx = 0; bx < bricks_.x; ++bx) {
        const glm::ivec3 first = glm::ivec3(bx, by, bz) * kBrick;
        const glm::ivec3 last = glm::min(first + kBrick, dims_ - 1);  // corners, inclusive
        float lowest = INFINITY;
        for (int k = first.z; k <= last.z; ++k)
          for (int j = first.y; j <= last.y; ++j)
            for (int i = first.x; i <= last.x; ++i) lowest = std::min(lowest, at(i, j, k));
        brick_min_[brickIndex(glm::ivec3(bx, by, bz))] = lowest;
      }
}

inline void GridSdfBody::sample(const glm::vec3& p, const glm::ivec3& c, const glm::vec3& pc, const glm::vec3& f,
                                float& phi, glm::vec3& normal) const {
  const float c000 = at(c.x, c.y, c.z), c100 = at(c.x + 1, c.y, c.z);
  const float c010 = at(c.x, c.y + 1, c.z), c110 = at(c.x + 1, c.y + 1, c.z);
  const float c001 = at(c.x, c.y, c.z + 1), c101 = at(c.x + 1, c.y, c.z + 1);
  const float c011 = at(c.x, c.y + 1, c.z + 1), c111 = at(c.x + 1, c.y + 1, c.z + 1);
  const float gx = f.x, hx = 1.0f - f.x, gy = f.y, hy = 1.0f - f.y, gz = f.z, hz = 1.0f - f.z;
  const float value = hz * (hy * (hx * c000 + gx * c100) + gy * (hx * c010 + gx * c110)) +
                      gz * (hy * (hx * c001 + gx * c101) + gy * (hx * c011 + gx * c111));
  glm::vec3 grad;
  grad.x = hz * (hy * (c100 - c000) + gy * (c110 - c010)) + gz * (hy * (c101 - c001) + gy * (c111 - c011));
  grad.y = hz * (hx * (c010 - c000) + gx * (c110 - c100)) + gz * (hx * (c011 - c001) + gx * (c111 - c101));
  grad.z = hy * (hx * (c001 - c000) + gx * (c101 - c100)) + gy * (hx * (c011 - c010) + gx * (c111 - c110));
  const glm::vec3 out = p - pc;
  const float out_len = glm::length(out);
  if (out_len > 0.0f) {
    phi = value + out_len;
    normal = out / out_len;
    return;
  }
  phi = value;
  const float gl = glm::length(grad);
  normal = gl > 0.0f ? grad / gl : glm::vec3(0.0f, 1.0f, 0.0f);
}

bool GridSdfBody::bounds(glm::vec3& lower, glm::vec3& upper) const {
  if (values_.empty()) return false;
  lower = lower_;
  upper = lower_ + voxel_ * glm::vec3(dims_ - 1);
  return true;
}

GridSdfBody::Cell GridSdfBody::cell(const glm::vec3& p) const {
  const glm::vec3 top = lower_ + voxel_ * glm::vec3(dims_ - 1);
  glm::ivec3 c;
  glm::vec3 pc, f;
  locate(p, top, 1.0f / voxel_, c, pc, f);
  Cell out;
  out.lower = -INFINITY;
  const float exact_band = kExactBand * voxel_;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const std::size_t idx = (static_cast<std::size_t>(c.z + dz) * static_cast<std::size_t>(dims_.y) +
                                 static_cast<std::size_t>(c.y + dy)) *
                                    static_cast<std::size_t>(dims_.x) +
                                static_cast<std::size_t>(c.x + dx);
        const glm::vec3 corner = lower_ + voxel_ * glm::vec3(c + glm::ivec3(dx, dy, dz));
        // phi is 1-Lipschitz: phi(p) >= phi(corner) - |p - corner|, where
        // the corner's value is the distance (tests/test_mesh_body.cpp,
        // ClearanceProofsAreLowerBounds: a value beyond the band overstated
        // the distance by up to 1 mm on a bumpy sphere's 4 mm voxels)
        if (std::fabs(values_[idx]) < exact_band)
          out.lower = std::max(out.lower, values_[idx] - glm::length(p - corner));
        const std::int32_t t = nearest_[idx];
        if (t < 0) continue;
        bool seen = false;
        for (int k = 0; k < out.triangles; ++k) seen = seen || out.triangle[k] == t;
        if (!seen) out.triangle[out.triangles++] = t;
      }
  // Exact values bound the distance at any point, also outside the grid's
  // box (p is not clamped here).
  return out;
}

void GridSdfBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const {
  const glm::vec3 top = lower_ + voxel_ * glm::vec3(dims_ - 1);
  const float inv = 1.0f / voxel_;
  for (std::size_t k = 0; k < n; ++k) {
    glm::ivec3 c;
    glm::vec3 pc, f;
    locate(p[k], top, inv, c, pc, f);
    sample(p[k], c, pc, f, phi[k], normal[k]);
  }
}

void GridSdfBody::signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                                      glm::vec3* normal) const {
  // The interpolant in a cell is a convex combination of its corners, so it
  // is at least the lowest corner of the brick less rounding (about ten
  // roundings of 2^-24 each, 6e-7 relative; the factor's 1e-5 leaves more
  // than tenfold room), and outside the box phi only adds the distance to it. For non-finite points
  // the exact query decides.
  constexpr float kRounding = 1.0f - 1e-5f;
  const glm::vec3 top = lower_ + voxel_ * glm::vec3(dims_ - 1);
  const float inv = 1.0f / voxel_;
  for (std::size_t k = 0; k < n; ++k) {
    glm::ivec3 c;
    glm::vec3 pc, f;
    locate(p[k], top, inv, c, pc, f);
    if (std::isfinite(p[k].x + p[k].y + p[k].z)) {
      const float lowest = brick_min_[brickIndex(c / kBrick)];
      const float bound = lowest * kRounding;
      if (lowest > 0.0f && bound >= limit) {
        phi[k] = bound;
        normal[k] = glm::vec3(0.0f, 1.0f, 0.0f);
        continue;
      }
    }
    sample(p[k], c, pc, f, phi[k], normal[k]);
  }
}

}  // namespace loosehair
