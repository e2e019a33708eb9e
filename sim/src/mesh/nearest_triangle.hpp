// The nearest point of a triangle soup (an open surface such as the scalp)
// to a point: a bounding-volume tree of the triangles, searched nearest box
// first until no box left can hold anything nearer. Gives exactly what
// trying every triangle gives (ties go to the lower triangle id), for points
// near the surface and far from it alike.
#pragma once

#include <glm/gtc/type_precision.hpp>
#include <glm/vec3.hpp>

#include <cmath>

#include <cstdint>
#include <vector>

namespace loosehair {

/// Closest point to p on triangle abc, as barycentric weights.
glm::vec3 closestBarycentric(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c);

class NearestTriangle {
 public:
  NearestTriangle() = default;
  NearestTriangle(std::vector<glm::vec3> positions, std::vector<glm::u32vec3> triangles);

  struct Hit {
    std::uint32_t triangle = 0;
    glm::vec3 barycentric{1, 0, 0};
    float distance = INFINITY;  // m
  };
  /// The nearest triangle to p and the nearest point on it. With no
  /// triangles, distance is infinite.
  Hit nearest(glm::vec3 p) const;

 private:
  std::vector<glm::vec3> positions_;
  std::vector<glm::u32vec3> triangles_;
  struct Node {
    glm::vec3 lo, hi;            // box of the triangles below
    std::uint32_t first, count;  // leaf: order_[first, first + count); inner: count 0, children first, first + 1
  };
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;  // triangle ids, grouped by leaf
};

}  // namespace loosehair
