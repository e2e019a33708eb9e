// Hair-hair forces (method.md §4, eqs. 16-18): pressure, collision and
// friction between current neighbours.
#include "solver/hair_hair.hpp"

#include "solver/solver_internal.hpp"
#include "solver/pair_forces.hpp"

namespace loosehair {

namespace {

// Each gathered pair's force on i (hairHairPairForce, pair_forces.hpp), for
// accumulateHairHair. A function of its own with plain arguments so that
// the loop vectorises (inside the parallel region's lambda it may not).
LOOSEHAIR_PAIR_KERNEL
void hairHairPairTerms(std::size_t pairs, const HairHairPairTerms& p, const float* __restrict dx,
                       const float* __restrict dy, const float* __restrict dz, const float* __restrict vx,
                       const float* __restrict vy, const float* __restrict vz, const float* __restrict tix,
                       const float* __restrict tiy, const float* __restrict tiz, const float* __restrict tjx,
                       const float* __restrict tjy, const float* __restrict tjz, const float* __restrict mm,
                       const float* __restrict pp, float* __restrict fx, float* __restrict fy, float* __restrict fz) {
  const HairHairPairTerms terms = p;  // a local copy: no aliasing with the outputs
  for (std::size_t q = 0; q < pairs; ++q) {
    const PairForce f = hairHairPairForce(terms, dx[q], dy[q], dz[q], vx[q], vy[q], vz[q], tix[q], tiy[q], tiz[q],
                                          tjx[q], tjy[q], tjz[q], mm[q], pp[q]);
    fx[q] = f.x;
    fy[q] = f.y;
    fz[q] = f.z;
  }
}

}  // namespace

// ---- stage 3c: hair-hair pressure, collision, friction (method.md §4) -----------
// A blocked pair loop (pair_columns.hpp): every neighbour is within the
// kernel's support; the terms are selected, not branched on.
void accumulateHairHair(const HairHairSettings& settings, const NeighborGrid& grid, const HairHairInput& in,
                        PairRecords& rec, PositionRecords xm_records, std::span<glm::vec3> force, int threads) {
  const CubicKernel k2(settings.h2);
  const std::size_t n = in.position.size();
  const glm::vec3* x = in.position.data();
  const glm::vec3* v = in.velocity.data();
  const glm::vec3* t = in.direction.data();
  const float* m = in.mass.data();
  const float* pterm = in.pressure_term.data();
  const HairHairPairTerms terms{1.0f / k2.h(), k2.W(0.0f) / 4.0f, -k2.dWdr(k2.h()) / 3.0f, settings.collision,
                                settings.friction};
  const std::uint32_t* ord = grid.searchOrder().data();  // as in computeDensity
  enum { DX, DY, DZ, VX, VY, VZ, TIX, TIY, TIZ, TJX, TJY, TJZ, MM, PP, FX, FY, FZ, kColumns };
  const bool make_xm = xm_records == PositionRecords::Make;
  rec.xm.resize(n);
  rec.vp.resize(n);
  rec.tt.resize(n);
  const glm::vec4 *xm = rec.xm.data(), *vp = rec.vp.data(), *tt = rec.tt.data();
  parallel::run(threads, [&] {
    const auto [k0, k1] = pairLoopPart(grid);
    if (make_xm) fillRecords(rec.xm, x, m, ord, k0, k1);
    fillRecords(rec.vp, v, pterm, ord, k0, k1);
    fillRecords(rec.tt, t, nullptr, ord, k0, k1);
    parallel::barrier();
    PairColumns& col = threadColumns();
    for (std::size_t b = k0; b < k1; b += kPairBlock) {
      const std::size_t e = std::min(k1, b + kPairBlock);
      std::size_t pairs = 0;
      for (std::size_t p = b; p < e; ++p) {
        pairs += grid.list(p).size();
        __builtin_prefetch(&force[ord[p]], 1);  // added to in step 3, in search order
      }
      col.reserve(pairs + 4, kColumns);  // a group of 4 may write 3 past the last pair
      float* __restrict dx = col[DX], * __restrict dy = col[DY], * __restrict dz = col[DZ];
      float* __restrict vx = col[VX], * __restrict vy = col[VY], * __restrict vz = col[VZ];
      float* __restrict tix = col[TIX], * __restrict tiy = col[TIY], * __restrict tiz = col[TIZ];
      float* __restrict tjx = col[TJX], * __restrict tjy = col[TJY], * __restrict tjz = col[TJZ];
      float* __restrict mm = col[MM], * __restrict pp = col[PP];
      float* __restrict fx = col[FX], * __restrict fy = col[FY], * __restrict fz = col[FZ];
      // 1. gather: x_ij, v_ij, t_i, t_j, m_i m_j, P_i/rho_i^2 + P_j/rho_j^2
      std::size_t k = 0;
      for (std::size_t p = b; p < e; ++p) {
        const auto list = grid.list(p);
#if defined(__SSE2__)
        const std::size_t count = list.size();
        __m128 ri[4], qi[4], ui[4], a[4], bv[4], c[4];  // i's and the partners' records
        broadcastRecord(xm[p], ri);
        broadcastRecord(vp[p], qi);
        broadcastRecord(tt[p], ui);
        for (std::size_t g = 0; g < count; g += 4) {
          const PartnerGroup group(list, g);
          transposedRecords(xm, group, a);
          transposedRecords(vp, group, bv);
          transposedRecords(tt, group, c);
          const std::size_t q = k + g;
          _mm_storeu_ps(dx + q, _mm_sub_ps(a[0], ri[0]));
          _mm_storeu_ps(dy + q, _mm_sub_ps(a[1], ri[1]));
          _mm_storeu_ps(dz + q, _mm_sub_ps(a[2], ri[2]));
          _mm_storeu_ps(mm + q, _mm_mul_ps(ri[3], a[3]));
          _mm_storeu_ps(vx + q, _mm_sub_ps(bv[0], qi[0]));
          _mm_storeu_ps(vy + q, _mm_sub_ps(bv[1], qi[1]));
          _mm_storeu_ps(vz + q, _mm_sub_ps(bv[2], qi[2]));
          _mm_storeu_ps(pp + q, _mm_add_ps(qi[3], bv[3]));
          _mm_storeu_ps(tjx + q, c[0]);
          _mm_storeu_ps(tjy + q, c[1]);
          _mm_storeu_ps(tjz + q, c[2]);
          _mm_storeu_ps(tix + q, ui[0]);
          _mm_storeu_ps(tiy + q, ui[1]);
          _mm_storeu_ps(tiz + q, ui[2]);
        }
        k += count;
#else
        const glm::vec3 xi(xm[p]), vi(vp[p]), ti(tt[p]);
        const float mi = xm[p].w, pi = vp[p].w;
        for (std::uint32_t j : list) {
          const glm::vec3 xij = glm::vec3(xm[j]) - xi, vij = glm::vec3(vp[j]) - vi;
          const glm::vec3 tj(tt[j]);
          dx[k] = xij.x, dy[k] = xij.y, dz[k] = xij.z;
          vx[k] = vij.x, vy[k] = vij.y, vz[k] = vij.z;
          tix[k] = ti.x, tiy[k] = ti.y, tiz[k] = ti.z;
          tjx[k] = tj.x, tjy[k] = tj.y, tjz[k] = tj.z;
          mm[k] = mi * xm[j].w;
          pp[k] = pi + vp[j].w;
          ++k;
        }
#endif
      }
      // 2. compute each pair's force on i
      hairHairPairTerms(pairs, terms, dx, dy, dz, vx, vy, vz, tix, tiy, tiz, tjx, tjy, tjz, mm, pp, fx, fy, fz);
      // 3. reduce in list order
      k = 0;
      for (std::size_t p = b; p < e; ++p) {
        glm::vec3 f(0.0f);
        for (std::size_t end = k + grid.list(p).size(); k < end; ++k) f += glm::vec3(fx[k], fy[k], fz[k]);
        force[ord[p]] += f;
      }
    }
  });
}

}  // namespace loosehair
