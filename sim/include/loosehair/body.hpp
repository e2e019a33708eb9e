// Collision bodies as signed-distance functions (method.md §5). Distances are
// negative inside. Queries are batched so that a body costs one virtual call
// per block of particles, not one per particle.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/ext/vector_int3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace loosehair {

/// Signed distances (negative inside) and outward normals of some placed
/// bodies at `points`, exact where phi < limit (`rough`: the bodies' fast
/// approximation there, Body::roughDistanceBelow); elsewhere phi is a lower
/// bound >= limit.
using BodyContacts = std::function<void(std::span<const glm::vec3> points, float limit, bool rough,
                                        std::span<float> phi, std::span<glm::vec3> normal)>;

class Body;

/// A body seen from another frame: a point p there is q = m p + d in the
/// body's own frame (m a rotation).
struct BodyPlacement {
  std::shared_ptr<const Body> body;
  glm::mat3 m{1.0f};
  glm::vec3 d{0.0f};
};

/// BodyContacts of the nearest of `placed` for points in the frame the
/// placements map from (normals in that frame); it keeps the bodies.
BodyContacts placedBodyContacts(std::vector<BodyPlacement> placed);

class Body {
 public:
  virtual ~Body() = default;
  /// For each of the n points p[k] (in the body's frame): phi[k] = signed
  /// distance (m, negative inside), normal[k] = unit outward normal of the
  /// nearest surface point (gradient of phi).
  virtual void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const = 0;
  /// The same where phi[k] < limit; elsewhere phi[k] is some value >= limit
  /// (a lower bound of the distance) and normal[k] is unspecified. For the
  /// solver's contact tests, which only look closer than a limit: a body may
  /// skip the exact query far from its surface. By default it does not.
  virtual void signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                                   glm::vec3* normal) const {
    (void)limit;
    signedDistance(p, n, phi, normal);
  }
  /// signedDistanceBelow with a hint a point: hint[k] (in and out) is what
  /// an earlier query of the same, moving point left there, or -1 (MeshBody:
  /// the nearest triangle). Hints only make a query faster: the answer has
  /// the same bits whatever they hold. By default they are left alone.
  virtual void signedDistanceBelowHinted(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal,
                                         std::int32_t* hint) const {
    (void)hint;
    signedDistanceBelow(p, n, limit, phi, normal);
  }
  /// The same answered by a body's fast approximation where it has one
  /// (MeshBody: its grid, within a voxel), for the velocity-level contact
  /// response and the air, which do not decide whether a particle is left
  /// inside. By default: signedDistanceBelow.
  virtual void roughDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal) const {
    signedDistanceBelow(p, n, limit, phi, normal);
  }
  /// How far (m) roughDistanceBelow's answers may lie above the exact
  /// signed distance, where the exact distance is 1-Lipschitz and decides
  /// the sign signedDistanceBelow gives below 0: rough - roughError() is
  /// then a lower bound of it everywhere (the solver's proof that a
  /// particle is clear of the body without asking again). Negative: no
  /// such bound (the default; the solver then asks about every particle).
  virtual float roughError() const { return -1.0f; }
  /// A box (body frame) outside which the signed distance is positive:
  /// the body lies in [lower, upper]. False where the body has none (the
  /// default); then no distance volume can be sampled around it
  /// (loosehair/distance_volume.hpp).
  virtual bool bounds(glm::vec3& lower, glm::vec3& upper) const {
    (void)lower;
    (void)upper;
    return false;
  }
};

/// An analytic sphere.
class SphereBody final : public Body {
 public:
  SphereBody(glm::vec3 center, float radius);
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override;
  float roughError() const override { return 0.0f; }  // exact
  bool bounds(glm::vec3& lower, glm::vec3& upper) const override;
  glm::vec3 center() const { return center_; }
  float radius() const { return radius_; }

 private:
  glm::vec3 center_;
  float radius_;
};

/// An analytic capsule: the points within `radius` of the segment a-b.
class CapsuleBody final : public Body {
 public:
  CapsuleBody(glm::vec3 a, glm::vec3 b, float radius);
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override;
  float roughError() const override { return 0.0f; }  // exact
  bool bounds(glm::vec3& lower, glm::vec3& upper) const override;

 private:
  glm::vec3 a_, b_;
  float radius_;
};

/// The union of bodies given in one frame: the least signed distance wins
/// (exact outside the union; inside, the deepest part's, whose surface may
/// lie inside another part: the solver's later rounds push again). A mesh of
/// separate closed parts that overlap (a neck pushed into a bust, eyes in
/// a head) is such a union: as one mesh, the faces of one part inside
/// another are surfaces too, and a point inside near one of them is pushed
/// onto it, still inside (head_model.cpp).
class UnionBody final : public Body {
 public:
  void add(std::shared_ptr<const Body> body) { parts_.push_back(std::move(body)); }
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override;
  void signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                           glm::vec3* normal) const override;
  /// The hint a point keeps is the nearest part's own, with the part
  /// (hint = part's hint * parts + part); the other parts are asked
  /// without one.
  void signedDistanceBelowHinted(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal,
                                 std::int32_t* hint) const override;
  void roughDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal) const override;
  /// The parts' largest (their signedDistance is within it of the exact
  /// distance: exact, or a MeshBody's grid beyond its band); negative if
  /// any part has none.
  float roughError() const override;
  /// The parts' boxes together; false if any part has none (or there are none).
  bool bounds(glm::vec3& lower, glm::vec3& upper) const override;

 private:
  // the least over the parts of query(part, points, count, phi, normal)
  template <class Query>
  void least(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal, const Query& query) const;
  std::vector<std::shared_ptr<const Body>> parts_;
};

}  // namespace loosehair

#include "loosehair/mesh.hpp"

#include <memory>
#include <string>
#include <vector>

namespace loosehair {

struct SdfBakeOptions {
  /// Grid spacing (m); 0 chooses 1/128 of the mesh's largest extent.
  float voxel_size = 0.0f;
  /// The grid reaches this far beyond the mesh's bounding box (m); farther
  /// out the distance is extrapolated from the box.
  float margin = 0.04f;
  /// Directory for baked grids, reused when the same mesh and options come
  /// again; empty: no cache.
  std::string cache_dir;
};

/// A closed triangle mesh as a signed-distance grid (method.md §5): baked once
/// with OpenVDB's mesh-to-level-set conversion, sampled trilinearly, with
/// the normal from the gradient of the interpolant.
class GridSdfBody final : public Body {
 public:
  /// Bakes `mesh` (or reads the cached grid). `source` names it in
  /// messages. `from_cache` (optional) tells whether the cache was used.
  static std::shared_ptr<GridSdfBody> bake(const TriangleMesh& mesh, const SdfBakeOptions& options,
                                           bool* from_cache = nullptr);
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override;
  /// Skips the exact query where the lowest grid value around the point's
  /// cell (kept per brick of kBrick^3 cells) already proves phi >= limit.
  void signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                           glm::vec3* normal) const override;
  /// What the corners of p's cell (p clamped to the grid) say about p.
  struct Cell {
    /// a lower bound of the signed distance at p (m), from the corners the
    /// bake computed exactly (-infinity if none of them was)
    float lower;
    static constexpr int kMaxTriangles = 8;
    int triangles = 0;  // the corners' distinct nearest triangles
    std::int32_t triangle[kMaxTriangles];
  };
  Cell cell(const glm::vec3& p) const;
  /// The grid's box (the mesh lies inside it, a margin in).
  bool bounds(glm::vec3& lower, glm::vec3& upper) const override;
  float voxelSize() const { return voxel_; }
  glm::vec3 lower() const { return lower_; }
  glm::ivec3 dims() const { return dims_; }
  /// The baked value (m) of voxel (i, j, k), at lower() + voxelSize() (i, j, k).
  float voxelValue(int i, int j, int k) const { return at(i, j, k); }
  /// How far (voxels) a baked value may exceed the exact signed distance at
  /// its voxel: the bake gives any voxel over it its exact value. MeshBody's
  /// error of sqrt(3) voxels is sqrt(3/4) voxel for the interpolation and at
  /// least this for the values (below sqrt(3/4), with room for rounding).
  static constexpr float kFarAllowance = 0.8f;
  /// Default cache directory: $LOOSEHAIR_CACHE_DIR, else $XDG_CACHE_HOME/loosehair,
  /// else $HOME/.cache/loosehair (empty if none of them is set).
  static std::string defaultCacheDir();

 private:
  GridSdfBody() = default;
  static constexpr int kBrick = 8;
  /// Voxels nearer the surface than this many voxels hold the exact signed
  /// distance; farther ones the conversion's value, which can exceed it.
  static constexpr float kExactBand = 2.5f;
  /// The cell of p (clamped to the grid), the point clamped to the grid's
  /// box (whose upper corner is `top`), and the cell's offset in voxels
  /// (`inv`: 1 / voxel size).
  void locate(const glm::vec3& p, const glm::vec3& top, float inv, glm::ivec3& cell, glm::vec3& clamped,
              glm::vec3& f) const;
  /// The exact query of p, given locate's results.
  void sample(const glm::vec3& p, const glm::ivec3& c, const glm::vec3& pc, const glm::vec3& f, float& phi,
              glm::vec3& normal) const;
  void computeBricks();  // brick_min_ from values_
  // the steps of bake (sdf_body.cpp)
  bool readCache(const std::filesystem::path& cache_file, std::uint64_t key, std::size_t triangles);
  void convert(const TriangleMesh& mesh, glm::vec3 grid_lower, float margin);  // grid_lower: in voxels
  void exactNearSurface(const TriangleMesh& mesh);
  void writeCache(const std::filesystem::path& cache_file, std::uint64_t key) const;
  std::size_t brickIndex(const glm::ivec3& brick) const;
  float at(int i, int j, int k) const {
    return values_[(static_cast<std::size_t>(k) * static_cast<std::size_t>(dims_.y) + static_cast<std::size_t>(j)) *
                       static_cast<std::size_t>(dims_.x) +
                   static_cast<std::size_t>(i)];
  }
  glm::vec3 lower_{0.0f};
  float voxel_ = 0.0f;
  glm::ivec3 dims_{0};
  std::vector<float> values_;
  std::vector<std::int32_t> nearest_;  // per voxel: the nearest triangle, -1 if unknown
  // per brick of kBrick^3 cells: the lowest value at any of its cells' corners
  glm::ivec3 bricks_{0};
  std::vector<float> brick_min_;
};

/// A closed triangle mesh with exact distances at its surface (method.md §5):
/// where the baked grid says a point may lie within `exact_band` of the
/// surface (or inside it), the nearest triangle is found in a bounding-volume
/// hierarchy and the distance signed by the angle-weighted pseudo-normal of
/// the nearest feature (face, edge or vertex); farther out the grid answers.
/// So contacts keep particles outside the real triangles, not only outside
/// the grid's interpolant, which cuts corners by up to a voxel.
class ExactDistance;

class MeshBody final : public Body {
 public:
  /// `mesh` as checkMesh left it (closed, consistently oriented) and the
  /// grid baked from it.
  MeshBody(const TriangleMesh& mesh, std::shared_ptr<const GridSdfBody> grid);
  ~MeshBody() override;
  MeshBody(const MeshBody&) = delete;
  MeshBody& operator=(const MeshBody&) = delete;
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override;
  void signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                           glm::vec3* normal) const override;
  void signedDistanceBelowHinted(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal,
                                 std::int32_t* hint) const override;
  void roughDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal) const override;
  /// Its grid's error: the rough answers (and signedDistance's beyond its
  /// band) are within it of the exact distance, which decides the sign.
  float roughError() const override { return grid_error_; }
  /// The mesh's bounding box.
  bool bounds(glm::vec3& lower, glm::vec3& upper) const override;
  const GridSdfBody& grid() const { return *grid_; }
  /// The grid's worst error (m): a Lipschitz bound, sqrt(3) voxels.
  float gridError() const { return grid_error_; }

 private:
  /// The exact query of the points whose grid values are in phi (with the
  /// grid's normals in normal): replaced where -deep < phi < limit + grid
  /// error; where phi >= limit + error it becomes a lower bound >= limit.
  /// `hint` (optional): a seed triangle a point, set to the nearest found.
  void refine(const glm::vec3* p, std::size_t n, float limit, float deep, float* phi, glm::vec3* normal,
              std::int32_t* hint = nullptr) const;
  std::shared_ptr<const GridSdfBody> grid_;
  std::unique_ptr<ExactDistance> exact_;
  float grid_error_ = 0.0f;
  glm::vec3 lower_{0.0f}, upper_{0.0f};
};

}  // namespace loosehair
