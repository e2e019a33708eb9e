// Density (method.md §2 eq. 1) and the pressure terms of eq. 16.
#include "solver/density.hpp"

#include "solver/solver_internal.hpp"
#include "solver/pair_forces.hpp"

namespace loosehair {

// ---- stage 2: density, eq. 1 -----------------------------------------------
// A blocked loop (pair_columns.hpp).
namespace {

LOOSEHAIR_PAIR_KERNEL
void densityPairTerms(std::size_t pairs, float inv_h, float norm_w, const float* __restrict r2,
                      const float* __restrict mj, float* __restrict rho) {
  for (std::size_t q = 0; q < pairs; ++q) {
    rho[q] = densityPairTerm(r2[q], mj[q], inv_h, norm_w);
  }
}

}  // namespace

void computeDensity(const DensitySettings& settings, const NeighborGrid& grid, std::span<const glm::vec3> position,
                    std::span<const float> mass, PairRecords& records, std::span<float> density,
                    std::span<float> pressure, std::span<float> pressure_term, int threads) {
  const CubicKernel k2(settings.h2);
  const std::size_t n = position.size();
  const glm::vec3* x = position.data();
  const float* m = mass.data();
  const float w0 = k2.W(0.0f), inv_h = 1.0f / k2.h(), norm_w = w0 / 4.0f;
  const float ka = settings.pressure_stiffness, rest_density = settings.rest_density;
  // Blocks of points in the search's order, whose lists lie one after the
  // other in memory (each point's sum is the same in any visiting order).
  const std::uint32_t* ord = grid.searchOrder().data();
  records.xm.resize(n);
  const glm::vec4* xm = records.xm.data();
  enum { R2, MJ, RHO, kColumns };
  parallel::run(threads, [&] {
    const auto [k0, k1] = pairLoopPart(grid);
    fillRecords(records.xm, x, m, ord, k0, k1);
    parallel::barrier();
    PairColumns& col = threadColumns();
    for (std::size_t b = k0; b < k1; b += kPairBlock) {
      const std::size_t e = std::min(k1, b + kPairBlock);
      std::size_t pairs = 0;
      for (std::size_t p = b; p < e; ++p) pairs += grid.list(p).size();
      col.reserve(pairs + 4, kColumns);  // a group of 4 may write 3 past the last pair
      float* __restrict r2 = col[R2], * __restrict mj = col[MJ], * __restrict rho = col[RHO];
      std::size_t k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const auto list = grid.list(p);
#if defined(__SSE2__)
        const std::size_t count = list.size();
        __m128 ri[4], a[4];
        broadcastRecord(xm[p], ri);
        for (std::size_t g = 0; g < count; g += 4) {
          transposedRecords(xm, PartnerGroup(list, g), a);
          const __m128 dx = _mm_sub_ps(a[0], ri[0]), dy = _mm_sub_ps(a[1], ri[1]), dz = _mm_sub_ps(a[2], ri[2]);
          // (dx dx + dy dy) + dz dz, the order of glm::dot
          _mm_storeu_ps(r2 + k + g, _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz)));
          _mm_storeu_ps(mj + k + g, a[3]);
        }
        k += count;
#else
        const glm::vec3 xi(xm[p]);
        for (std::uint32_t j : list) {
          const glm::vec3 d = glm::vec3(xm[j]) - xi;
          r2[k] = glm::dot(d, d);
          mj[k] = xm[j].w;
          ++k;
        }
#endif
      }
      densityPairTerms(pairs, inv_h, norm_w, r2, mj, rho);
      k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const std::uint32_t i = ord[p];
        float sum = m[i] * w0;
        for (std::size_t end = k + grid.list(p).size(); k < end; ++k) sum += rho[k];
        density[i] = sum;
        pressure[i] = ka * (sum - rest_density);
        pressure_term[i] = pressure[i] / (sum * sum);  // P_i / rho_i^2 of eq. 16
      }
    }
  });
}

}  // namespace loosehair
