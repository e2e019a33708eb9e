// Hair-hair forces (method.md §4, eqs. 16-18): pressure, collision and
// friction between current neighbours.
#include "solver/solver_internal.hpp"
#include "solver/neighbor_records.hpp"

namespace loosehair {

namespace {

// The hair-hair force on i of each gathered pair (method.md §4, eqs. 16-18), for
// accumulateHairHairForces. A function of its own with plain arguments so
// that the loop vectorises (inside the parallel region's lambda it may not).
struct HairHairTerms {
  float inv_h, norm_w, norm_g;  // kernel W(r, h2): 1/h, 1/(4 pi h^3), 1/(4 pi h^4)
  float dc, dfr;                // collision and friction coefficients
};
LOOSEHAIR_PAIR_KERNEL
void hairHairPairTerms(std::size_t pairs, const HairHairTerms& p, const float* __restrict dx,
                       const float* __restrict dy, const float* __restrict dz,
                       const float* __restrict vx, const float* __restrict vy,
                       const float* __restrict vz, const float* __restrict tix,
                       const float* __restrict tiy, const float* __restrict tiz,
                       const float* __restrict tjx, const float* __restrict tjy,
                       const float* __restrict tjz, const float* __restrict mm,
                       const float* __restrict pp, float* __restrict fx, float* __restrict fy,
                       float* __restrict fz) {
  const float inv_h = p.inv_h, norm_w = p.norm_w, norm_g = p.norm_g, dc = p.dc, dfr = p.dfr;
  for (std::size_t q = 0; q < pairs; ++q) {
    const float r2 = dx[q] * dx[q] + dy[q] * dy[q] + dz[q] * dz[q];
    const float r = std::sqrt(r2);
    const float inv_r = r > 0.0f ? 1.0f / r : 0.0f;
    const float w = cubicW(r, inv_h, norm_w);      // W(r, h2)
    const float dw = cubicDWdr(r, inv_h, norm_g);  // dW/dr
    // eq. 16: -m_i m_j (P_i/rho_i^2 + P_j/rho_j^2) grad_i W, grad_i W = -dW/dr x_ij / r
    const float pc = mm[q] * pp[q] * dw * inv_r;
    // eq. 17: collision direction t_i x t_j; for near-parallel hairs the
    // part of x_ij normal to their mean direction (our symmetric choice,
    // so that the pair force is exactly opposite on j).
    const float cx = tiy[q] * tjz[q] - tiz[q] * tjy[q];
    const float cy = tiz[q] * tjx[q] - tix[q] * tjz[q];
    const float cz = tix[q] * tjy[q] - tiy[q] * tjx[q];
    const float c2 = cx * cx + cy * cy + cz * cz;
    const float sgn = tix[q] * tjx[q] + tiy[q] * tjy[q] + tiz[q] * tjz[q] >= 0.0f ? 1.0f : -1.0f;
    const float mx = tix[q] + sgn * tjx[q], my = tiy[q] + sgn * tjy[q], mz = tiz[q] + sgn * tjz[q];
    const float m2 = mx * mx + my * my + mz * mz;
    const float along = (dx[q] * mx + dy[q] * my + dz[q] * mz) / (m2 > 0.0f ? m2 : 1.0f);
    const float ax = dx[q] - along * mx, ay = dy[q] - along * my, az = dz[q] - along * mz;
    const float a2 = ax * ax + ay * ay + az * az;
    const bool parallel = c2 < 1e-6f;
    // the fallback direction is usable if the hairs are not on one line
    // (float masks, not bools: the loop then vectorises)
    const float usable = m2 > 0.0f ? (a2 < 1e-6f * r2 ? 0.0f : 1.0f) : 0.0f;
    const float valid = parallel ? usable : 1.0f;
    const float d2 = parallel ? a2 : c2;
    const float inv_d = valid / std::sqrt(valid > 0.0f ? d2 : 1.0f);
    const float nx = (parallel ? ax : cx) * inv_d, ny = (parallel ? ay : cy) * inv_d,
                nz = (parallel ? az : cz) * inv_d;
    const float vn = vx[q] * nx + vy[q] * ny + vz[q] * nz;
    // approaching pairs only (eqs. 17-18)
    const float wc = (dx[q] * nx + dy[q] * ny + dz[q] * nz) * vn < 0.0f ? w : 0.0f;
    const float cn = dc * wc * vn, ft = dfr * wc;
    fx[q] = pc * dx[q] + cn * nx + ft * (vx[q] - vn * nx);
    fy[q] = pc * dy[q] + cn * ny + ft * (vy[q] - vn * ny);
    fz[q] = pc * dz[q] + cn * nz + ft * (vz[q] - vn * nz);
  }
}

}  // namespace

// ---- stage 3c: hair-hair pressure, collision, friction (method.md §4) -----------
// A blocked pair loop (pair_columns.hpp): every neighbour is within the
// kernel's support; the terms are selected, not branched on.
void Solver::accumulateHairHairForces(std::vector<glm::vec3>& force, bool xm_ready) const {
  const CubicKernel k2(params_.h2);
  const std::size_t n = particles_.size();
  const glm::vec3* x = particles_.position.data();
  const glm::vec3* v = particles_.velocity.data();
  const glm::vec3* t = particles_.direction.data();
  const float* m = particles_.mass.data();
  const float* pterm = pressure_term_.data();
  const HairHairTerms terms{1.0f / k2.h(), k2.W(0.0f) / 4.0f, -k2.dWdr(k2.h()) / 3.0f, dc_, dfr_};
  const std::uint32_t* ord = grid_->searchOrder().data();  // as in computeDensity
  const NeighborGrid& grid = *grid_;
  enum { DX, DY, DZ, VX, VY, VZ, TIX, TIY, TIZ, TJX, TJY, TJZ, MM, PP, FX, FY, FZ, kColumns };
  // The partners' records (hairRecords()); (x, m) comes from computeDensity
  // in a step, and is made here for a query between steps.
  HairRecords& rec = hairRecords();
  rec.xm.resize(n);
  rec.vp.resize(n);
  rec.tt.resize(n);
  const glm::vec4 *xm = rec.xm.data(), *vp = rec.vp.data(), *tt = rec.tt.data();
  parallel::run(threads_, [&] {
    const auto [k0, k1] = pairLoopPart(grid);
    if (!xm_ready) fillRecords(rec.xm, x, m, ord, k0, k1);
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
      hairHairPairTerms(pairs, terms, dx, dy, dz, vx, vy, vz, tix, tiy, tiz, tjx, tjy, tjz, mm, pp,
                        fx, fy, fz);
      // 3. reduce in list order
      k = 0;
      for (std::size_t p = b; p < e; ++p) {
        glm::vec3 f(0.0f);
        for (std::size_t end = k + grid.list(p).size(); k < end; ++k)
          f += glm::vec3(fx[k], fy[k], fz[k]);
        force[ord[p]] += f;
      }
    }
  });
}

}  // namespace loosehair
