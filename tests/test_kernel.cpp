// method.md §2: the cubic spline kernel integrates to 1, its gradient to 0, and
// the analytic derivative matches finite differences.
#include "solver/kernel.hpp"

#include <gtest/gtest.h>

#include <cmath>

using loosehair::CubicKernel;

TEST(Kernel, IntegratesToOneInThreeDimensions) {
  for (float h : {0.01f, 0.3f, 2.0f}) {
    const CubicKernel k(h);
    // Radial quadrature: int_0^{2h} 4 pi r^2 W(r) dr (midpoint rule, fine).
    const int steps = 20000;
    const double dr = 2.0 * h / steps;
    double radial = 0;
    for (int s = 0; s < steps; ++s) {
      const double r = (s + 0.5) * dr;
      radial += 4.0 * M_PI * r * r * k.W(static_cast<float>(r)) * dr;
    }
    EXPECT_NEAR(radial, 1.0, 1e-4) << "h = " << h;

    // Cartesian lattice quadrature, off-centre to avoid symmetric luck.
    const int m = 60;
    const double a = 4.0 * h / m;
    double lattice = 0, gx = 0, gy = 0, gz = 0, abs_g = 0;
    for (int ix = 0; ix < m; ++ix)
      for (int iy = 0; iy < m; ++iy)
        for (int iz = 0; iz < m; ++iz) {
          const glm::vec3 d(static_cast<float>((ix + 0.37) * a - 2 * h), static_cast<float>((iy + 0.61) * a - 2 * h),
                            static_cast<float>((iz + 0.13) * a - 2 * h));
          const float r = glm::length(d);
          lattice += k.W(r) * a * a * a;
          const glm::vec3 g = k.gradW(d, r);
          gx += g.x * a * a * a;
          gy += g.y * a * a * a;
          gz += g.z * a * a * a;
          abs_g += glm::length(g) * a * a * a;
        }
    EXPECT_NEAR(lattice, 1.0, 5e-3) << "h = " << h;
    EXPECT_LT(std::abs(gx) + std::abs(gy) + std::abs(gz), 2e-2 * abs_g) << "h = " << h;
  }
}

TEST(Kernel, ShapeAndSupport) {
  const CubicKernel k(0.5f);
  EXPECT_FLOAT_EQ(k.W(0.0f), 4.0f / (4.0f * static_cast<float>(M_PI) * 0.125f));
  EXPECT_EQ(k.W(1.0f), 0.0f);  // r = 2h
  EXPECT_EQ(k.W(5.0f), 0.0f);
  EXPECT_EQ(k.dWdr(1.2f), 0.0f);
  // continuous at q = 1
  EXPECT_NEAR(k.W(0.5f - 1e-6f), k.W(0.5f + 1e-6f), 1e-4f);
  EXPECT_NEAR(k.dWdr(0.5f - 1e-6f), k.dWdr(0.5f + 1e-6f), 1e-3f);
  // decreasing
  float last = k.W(0.0f);
  for (int s = 1; s <= 100; ++s) {
    const float w = k.W(s * 0.01f);
    EXPECT_LE(w, last);
    last = w;
  }
}

TEST(Kernel, GradientMatchesFiniteDifferences) {
  const CubicKernel k(0.2f);
  const glm::vec3 dirs[] = {{1, 0, 0}, {0.3f, -0.5f, 0.8f}, {-0.2f, 0.1f, -0.4f}};
  for (glm::vec3 dir : dirs) {
    dir = glm::normalize(dir);
    for (float r : {0.02f, 0.1f, 0.19f, 0.21f, 0.3f, 0.39f}) {
      const glm::vec3 x = r * dir;
      const glm::vec3 g = k.gradW(x, r);
      const double eps = 1e-4;
      for (int a = 0; a < 3; ++a) {
        glm::dvec3 xp(x), xm(x);
        xp[a] += eps;
        xm[a] -= eps;
        const double fd =
            (k.W(static_cast<float>(glm::length(xp))) - k.W(static_cast<float>(glm::length(xm)))) / (2 * eps);
        EXPECT_NEAR(g[a], fd, 2e-3 * std::abs(k.dWdr(0.1f))) << "r = " << r << " axis " << a;
      }
    }
  }
}
