// A body's signed distance sampled on a grid for the GPU strand carry
// (issue 45): exact at the grid points near the surface, close to the exact
// distance between them, the same for any thread count, and refused for a
// body without a bounding box.
#include "loosehair/distance_volume.hpp"
#include "loosehair/head_model.hpp"
#include "loosehair/scene.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

using namespace loosehair;

namespace {

// a body that does not say where it is
class Unbounded final : public Body {
 public:
  void signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const override {
    for (std::size_t k = 0; k < n; ++k) {
      phi[k] = p[k].y;
      normal[k] = glm::vec3(0, 1, 0);
    }
  }
};

}  // namespace

TEST(DistanceVolume, ASphereIsSampledExactlyAtItsPointsAndCloselyBetween) {
  const SphereBody sphere(glm::vec3(0.01f, 0.02f, -0.03f), 0.08f);
  DistanceVolumeOptions o;
  o.voxel = 0.004f;
  const DistanceVolume v = sampleDistanceVolume(sphere, o, 2);
  // the sphere and the band around it lie inside the grid
  glm::vec3 lo, hi;
  ASSERT_TRUE(sphere.bounds(lo, hi));
  EXPECT_TRUE(glm::all(glm::lessThanEqual(v.lower, lo - glm::vec3(v.exact_band))));
  EXPECT_TRUE(glm::all(glm::greaterThanEqual(v.upper(), hi + glm::vec3(v.exact_band))));
  EXPECT_FLOAT_EQ(v.voxel, 0.004f);
  // a grid point's value is the distance
  for (int k = 0; k < v.dims.z; k += 7)
    for (int j = 0; j < v.dims.y; j += 5)
      for (int i = 0; i < v.dims.x; i += 3) {
        const glm::vec3 p = v.lower + v.voxel * glm::vec3(i, j, k);
        EXPECT_NEAR(v.at(i, j, k), glm::length(p - sphere.center()) - sphere.radius(), 1e-6f);
      }
  // between them, near the surface, within a few hundredths of a voxel
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  float worst = 0.0f;
  for (int t = 0; t < 2000; ++t) {
    glm::vec3 d(u(rng), u(rng), u(rng));
    if (glm::length(d) < 1e-3f) continue;
    const glm::vec3 p = sphere.center() + (sphere.radius() + 0.01f * u(rng)) * glm::normalize(d);
    worst = std::max(worst, std::abs(v.sample(p) - (glm::length(p - sphere.center()) - sphere.radius())));
  }
  EXPECT_LT(worst, 0.05f * v.voxel) << "voxel " << v.voxel;
}

TEST(DistanceVolume, TheBundledHeadIsCloseToItsExactDistanceNearTheSkinAndTheSameForAnyThreads) {
  const SceneDesc scene = loadScene(lhtest::sourceDir() + "/data/scenes/hang.json");
  const HeadModel model = HeadModel::build(scene, scene.source);
  const Body& head = *model.head();
  DistanceVolumeOptions o;
  const DistanceVolume one = sampleDistanceVolume(head, o, 1), three = sampleDistanceVolume(head, o, 3);
  ASSERT_EQ(one.values.size(), three.values.size());
  EXPECT_EQ(0, std::memcmp(one.values.data(), three.values.data(), one.values.size() * sizeof(float)));
  // points within a voxel of the skin: the interpolant against the exact
  // distance (the push on the GPU relies on it)
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<glm::vec3> pts;
  const glm::vec3 lo = one.lower, hi = one.upper();
  while (pts.size() < 3000) {
    const glm::vec3 p = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
    float phi;
    glm::vec3 n;
    head.signedDistance(&p, 1, &phi, &n);
    if (std::abs(phi) < one.voxel) pts.push_back(p);
  }
  std::vector<float> err;
  for (const glm::vec3& p : pts) {
    float phi;
    glm::vec3 n;
    head.signedDistance(&p, 1, &phi, &n);
    err.push_back(std::abs(one.sample(p) - phi));
  }
  std::sort(err.begin(), err.end());
  const float p99 = err[err.size() * 99 / 100], worst = err.back();
  EXPECT_LT(p99, 0.25f * one.voxel) << "voxel " << one.voxel << " m";
  EXPECT_LT(worst, one.voxel) << "voxel " << one.voxel << " m";
}

TEST(DistanceVolume, ABodyWithoutABoxAndBadOptionsAreRefused) {
  const Unbounded plane;
  EXPECT_THROW(sampleDistanceVolume(plane), std::invalid_argument);
  const SphereBody sphere(glm::vec3(0.0f), 0.1f);
  DistanceVolumeOptions o;
  o.voxel = std::nanf("");
  EXPECT_THROW(sampleDistanceVolume(sphere, o), std::invalid_argument);
  o = {};
  o.max_points = 4;
  EXPECT_THROW(sampleDistanceVolume(sphere, o), std::invalid_argument);
  o = {};
  o.exact_voxels = 1.0f;
  EXPECT_THROW(sampleDistanceVolume(sphere, o), std::invalid_argument);
  // a large body gets a coarser grid, not more points
  o = {};
  o.max_points = 32;
  const DistanceVolume v = sampleDistanceVolume(SphereBody(glm::vec3(0.0f), 1.0f), o);
  EXPECT_LE(std::max({v.dims.x, v.dims.y, v.dims.z}), 32);
  EXPECT_GT(v.voxel, 0.002f);
}
