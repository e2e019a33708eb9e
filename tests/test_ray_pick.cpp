// Picking by rays (the viewer's styling brush): rays meet the head mesh
// where geometry says, and the brush gathers the scalp triangles around
// the hit.
#include "loosehair/ray_pick.hpp"
#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

using namespace loosehair;

TEST(RayPick, ARayMeetsTheSphereHeadAtItsNearSide) {
  const SceneDesc scene = lhtest::sphereScene(100);
  const HeadModel head = HeadModel::build(scene, "test");
  const float r = scene.head_radius;
  // from the front, aimed at the centre: the front pole, a radius in
  const auto hit = intersectRay(head.headMesh(), glm::vec3(0, 0, 1), glm::vec3(0, 0, -2));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->point.z, r, 0.01f * r) << "the tessellated sphere is within 1% of the radius";
  EXPECT_NEAR(hit->distance, 1.0f - r, 0.01f * r) << "distance along the unit direction";
  // a ray that passes beside the head misses; one pointing away misses
  EXPECT_FALSE(intersectRay(head.headMesh(), glm::vec3(0, 2 * r, 1), glm::vec3(0, 0, -1)));
  EXPECT_FALSE(intersectRay(head.headMesh(), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)));
  EXPECT_FALSE(intersectRay(head.headMesh(), glm::vec3(0, 0, 1), glm::vec3(0.0f)));
}

TEST(RayPick, TheBrushGathersTheScalpTrianglesAroundThePoint) {
  const SceneDesc scene = lhtest::sphereScene(100);
  const HeadModel head = HeadModel::build(scene, "test");
  const glm::vec3 crown(0, scene.head_radius, 0);
  const auto small = scalpTrianglesWithin(head, crown, 0.01f), large = scalpTrianglesWithin(head, crown, 0.03f);
  ASSERT_FALSE(small.empty());
  EXPECT_GT(large.size(), 3 * small.size()) << "area grows with the radius squared";
  const ScalpTriangles& st = head.scalpTriangles();
  for (std::uint32_t t : small) {  // every one has a corner or its centre in reach
    float nearest = 1e9f;
    glm::vec3 c(0.0f);
    for (int k = 0; k < 3; ++k) {
      nearest = std::min(nearest, glm::length(st.positions[st.triangles[t][k]] - crown));
      c += st.positions[st.triangles[t][k]] / 3.0f;
    }
    EXPECT_LE(std::min(nearest, glm::length(c - crown)), 0.01f + 1e-6f);
  }
  EXPECT_TRUE(std::is_sorted(small.begin(), small.end()));
  EXPECT_TRUE(scalpTrianglesWithin(head, glm::vec3(0, -scene.head_radius, 0), 0.01f).empty())
      << "no scalp under the chin";
  EXPECT_NEAR(distanceToRay(glm::vec3(1, 1, 0), glm::vec3(0.0f), glm::vec3(2, 0, 0)), 1.0f, 1e-6f);
  EXPECT_NEAR(distanceToRay(glm::vec3(-1, 0, 0), glm::vec3(0.0f), glm::vec3(1, 0, 0)), 1.0f, 1e-6f)
      << "behind the origin";
}
