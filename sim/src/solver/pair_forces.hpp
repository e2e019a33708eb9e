// The physics of one pair, written once: the hair-hair force of method.md
// §4 (eqs. 16-18). Plain floats in, plain floats out, so that the blocked
// pair loop of hair_hair.cpp inlines it into a loop over columns that the
// compiler vectorises (every lane the same IEEE operations as this scalar
// code, so the bits do not depend on the vector width); a test calls it on
// one hand-made pair (tests/test_solver_stages.cpp).
#pragma once

#include "solver/kernel.hpp"

#include <cmath>

namespace loosehair {

struct HairHairPairTerms {
  float inv_h, norm_w, norm_g;  // kernel W(r, h2): 1/h, 1/(4 pi h^3), 1/(4 pi h^4)
  float dc, dfr;                // collision and friction coefficients
};

struct PairForce {
  float x, y, z;
};

/// The force on i from j. x_ij = x_j - x_i = (dx, dy, dz), v_ij = v_j - v_i,
/// t_i, t_j the hair directions, mm = m_i m_j, pp = P_i/rho_i^2 + P_j/rho_j^2.
/// The force on j is exactly its negative (every term is odd in x_ij, v_ij
/// and symmetric in i, j).
inline PairForce hairHairPairForce(const HairHairPairTerms& p, float dx, float dy, float dz, float vx, float vy,
                                   float vz, float tix, float tiy, float tiz, float tjx, float tjy, float tjz, float mm,
                                   float pp) {
  const float r2 = dx * dx + dy * dy + dz * dz;
  const float r = std::sqrt(r2);
  const float inv_r = r > 0.0f ? 1.0f / r : 0.0f;
  const float w = cubicW(r, p.inv_h, p.norm_w);      // W(r, h2)
  const float dw = cubicDWdr(r, p.inv_h, p.norm_g);  // dW/dr
  // eq. 16: -m_i m_j (P_i/rho_i^2 + P_j/rho_j^2) grad_i W, grad_i W = -dW/dr x_ij / r
  const float pc = mm * pp * dw * inv_r;
  // eq. 17: collision direction t_i x t_j; for near-parallel hairs the
  // part of x_ij normal to their mean direction (our symmetric choice,
  // so that the pair force is exactly opposite on j).
  const float cx = tiy * tjz - tiz * tjy;
  const float cy = tiz * tjx - tix * tjz;
  const float cz = tix * tjy - tiy * tjx;
  const float c2 = cx * cx + cy * cy + cz * cz;
  const float sgn = tix * tjx + tiy * tjy + tiz * tjz >= 0.0f ? 1.0f : -1.0f;
  const float mx = tix + sgn * tjx, my = tiy + sgn * tjy, mz = tiz + sgn * tjz;
  const float m2 = mx * mx + my * my + mz * mz;
  const float along = (dx * mx + dy * my + dz * mz) / (m2 > 0.0f ? m2 : 1.0f);
  const float ax = dx - along * mx, ay = dy - along * my, az = dz - along * mz;
  const float a2 = ax * ax + ay * ay + az * az;
  const bool parallel = c2 < 1e-6f;
  // the fallback direction is usable if the hairs are not on one line
  // (float masks, not bools: the loop then vectorises)
  const float usable = m2 > 0.0f ? (a2 < 1e-6f * r2 ? 0.0f : 1.0f) : 0.0f;
  const float valid = parallel ? usable : 1.0f;
  const float d2 = parallel ? a2 : c2;
  const float inv_d = valid / std::sqrt(valid > 0.0f ? d2 : 1.0f);
  const float nx = (parallel ? ax : cx) * inv_d, ny = (parallel ? ay : cy) * inv_d, nz = (parallel ? az : cz) * inv_d;
  const float vn = vx * nx + vy * ny + vz * nz;
  // approaching pairs only (eqs. 17-18)
  const float wc = (dx * nx + dy * ny + dz * nz) * vn < 0.0f ? w : 0.0f;
  const float cn = p.dc * wc * vn, ft = p.dfr * wc;
  return {pc * dx + cn * nx + ft * (vx - vn * nx), pc * dy + cn * ny + ft * (vy - vn * ny),
          pc * dz + cn * nz + ft * (vz - vn * nz)};
}

/// The density term of eq. 1 from j: m_j W(r, h2), r^2 = |x_ij|^2.
inline float densityPairTerm(float r2, float mj, float inv_h, float norm_w) {
  return mj * cubicW(std::sqrt(r2), inv_h, norm_w);
}

}  // namespace loosehair
