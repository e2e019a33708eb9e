// method.md §2 eq. 1: the SPH density on a regular lattice matches the lattice sum
// and the continuum value m / a^3 away from the border.
#include "solver/kernel.hpp"
#include "loosehair/loosehair.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace loosehair;

TEST(Density, RegularLatticeMatchesAnalyticValue) {
  // A block of hair particles on a cubic lattice, hanging from a root layer.
  const float a = 0.01f, m = 2e-5f;
  const int nx = 12, ny = 14, nz = 12;
  Particles p;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (int k = 0; k < nz; ++k) {
        const std::size_t q = p.size();
        p.resize(q + 1);
        const float s = (ny - 1 - j) * a - a;  // top layer: roots (s < 0)
        p.position[q] = glm::vec3(i * a, j * a, k * a);
        p.direction[q] = glm::vec3(0, -1, 0);
        p.mass[q] = m;
        p.arc_length[q] = s;
        p.is_root[q] = s < 0 ? 1 : 0;
        p.root_point[q] = glm::vec3(i * a, (ny - 2) * a, k * a);
      }
  SimParams params;
  params.h1 = 1.2f * a;
  params.h2 = 1.0f * a;
  auto body = std::make_shared<SphereBody>(glm::vec3(0, 10, 0), 0.1f);
  Solver solver(params, p, body);

  const CubicKernel k(params.h2);
  double lattice_sum = 0;  // m * sum over the infinite lattice within support
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int l = -3; l <= 3; ++l) lattice_sum += m * k.W(a * std::sqrt(float(i * i + j * j + l * l)));

  const auto rho = solver.density();
  int checked = 0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    const glm::vec3 x = p.position[q] / a;
    const bool interior =
        x.x >= 2.5f && x.x <= nx - 3.5f && x.y >= 2.5f && x.y <= ny - 3.5f && x.z >= 2.5f && x.z <= nz - 3.5f;
    if (!interior) continue;
    ++checked;
    EXPECT_NEAR(rho[q], lattice_sum, 1e-4 * lattice_sum);
    EXPECT_NEAR(rho[q], m / (a * a * a), 0.03 * m / (a * a * a));  // continuum value
  }
  EXPECT_GT(checked, 100);
  // at the border the density is lower
  EXPECT_LT(rho[0], 0.8 * lattice_sum);
}
