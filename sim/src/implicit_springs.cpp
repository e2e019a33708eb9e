// Backward-Euler velocity solve of the loose springs (implicit_springs.hpp).
#include "implicit_springs.hpp"

#include "parallel.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

namespace {

constexpr std::size_t L = ConnectionSlices::kLanes;
constexpr std::size_t kWindowSlices = kSliceWindow / L;

inline glm::vec3 applySym(const float* a, const glm::vec3& v) {
  return {a[0] * v.x + a[1] * v.y + a[2] * v.z, a[1] * v.x + a[3] * v.y + a[4] * v.z,
          a[2] * v.x + a[4] * v.y + a[5] * v.z};
}

// (A p)_i = m_i p_i + sum_j c n (n . (p_i - p_j)) for the 16 lanes of one
// slice, row by row (each lane in its list's order).
void sliceProduct(std::size_t rows, std::size_t q0, const float* __restrict ux, const float* __restrict uy,
                  const float* __restrict uz, const float* __restrict c, const std::uint32_t* __restrict partner,
                  const glm::vec3* __restrict p, const float* pix, const float* piy, const float* piz,
                  float* __restrict ax, float* __restrict ay, float* __restrict az) {
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t q = q0 + r * L;
    for (std::size_t l = 0; l < L; ++l) {
      const glm::vec3 pj = p[partner[q + l]];
      const float dx = pix[l] - pj.x, dy = piy[l] - pj.y, dz = piz[l] - pj.z;
      const float nx = ux[q + l], ny = uy[q + l], nz = uz[q + l];
      const float s = c[q + l] * (nx * dx + ny * dy + nz * dz);
      ax[l] += s * nx;
      ay[l] += s * ny;
      az[l] += s * nz;
    }
  }
}

}  // namespace

ImplicitSpringReport ImplicitSprings::solve(const Input& in, int threads, std::vector<glm::vec3>& dv) {
  const ConnectionSlices& cs = *in.layout;
  const std::size_t n = in.particles, slices = cs.sliceCount();
  const std::size_t windows = (slices + kWindowSlices - 1) / kWindowSlices;
  const std::size_t entries = cs.entryCount();
  ux_.resize(entries);
  uy_.resize(entries);
  uz_.resize(entries);
  c_.resize(entries);
  precond_.resize(6 * n);
  r_.resize(n);
  z_.resize(n);
  p_.resize(n);
  ap_.resize(n);
  // the guess may be dv itself (the last step's answer)
  const bool warm = in.guess != nullptr;
  if (!warm) dv.assign(n, glm::vec3(0.0f));
  else if (in.guess != dv.data()) dv.assign(in.guess, in.guess + n);
  else dv.resize(n);
  pap_partial_.assign(windows, 0.0);
  rz_partial_.assign(windows, 0.0);
  const float dt = in.dt, scale = dt * dt + in.gamma * dt;
  const double tol2 = static_cast<double>(in.tolerance) * in.tolerance;
  const glm::vec3 *x = in.position, *v = in.velocity, *f = in.force;
  const float* m = in.mass;
  const std::uint8_t* root = in.is_root;
  ImplicitSpringReport report;

  parallel::run(threads, [&] {
    // a thread's windows, their slices and their particles (a window's
    // lanes are the particles [window * kSliceWindow, ...) reordered)
    const auto [wb, we] = parallel::share(windows);
    const std::size_t sb = std::min(slices, wb * kWindowSlices), se = std::min(slices, we * kWindowSlices);
    const std::size_t ib = std::min(n, wb * kSliceWindow), ie = std::min(n, we * kSliceWindow);
    auto total = [&](const std::vector<double>& partial) {
      double s = 0.0;
      for (std::size_t k = 0; k < windows; ++k) s += partial[k];
      return s;
    };
    // Each owner's entries, its 3x3 block and its right-hand side
    // dt f_i + dt^2 sum_j w n (n . (v_j - v_i)), in list order.
    for (std::size_t s = sb; s < se; ++s) {
      const std::size_t row0 = cs.row_begin[s], rows = cs.row_begin[s + 1] - row0;
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t lane = s * L + l;
        const std::uint32_t i = cs.owner[lane];
        const bool real = lane < n, fixed = root[i] != 0;
        const auto degree = static_cast<std::size_t>(cs.degree[lane]);
        const glm::vec3 xi = x[i], vi = v[i];
        float a[6] = {0, 0, 0, 0, 0, 0};
        glm::vec3 pull(0.0f);
        for (std::size_t r = 0; r < rows; ++r) {
          const std::size_t q = (row0 + r) * L + l;
          if (!real || fixed || r >= degree) {
            ux_[q] = uy_[q] = uz_[q] = c_[q] = 0.0f;
            continue;
          }
          const std::uint32_t j = cs.partner[q];
          const glm::vec3 d = x[j] - xi;
          const float len = glm::length(d);
          const glm::vec3 u = len > 0.0f ? d / len : glm::vec3(0.0f);
          const float w = in.weight[q], c = scale * w;
          ux_[q] = u.x;
          uy_[q] = u.y;
          uz_[q] = u.z;
          c_[q] = c;
          a[0] += c * u.x * u.x;
          a[1] += c * u.x * u.y;
          a[2] += c * u.x * u.z;
          a[3] += c * u.y * u.y;
          a[4] += c * u.y * u.z;
          a[5] += c * u.z * u.z;
          pull += (w * glm::dot(u, v[j] - vi)) * u;
        }
        if (!real) continue;
        float* pc = &precond_[6 * std::size_t{i}];
        if (fixed) {
          std::fill(pc, pc + 6, 0.0f);
          r_[i] = glm::vec3(0.0f);
          continue;
        }
        const glm::mat3 block(m[i] + a[0], a[1], a[2], a[1], m[i] + a[3], a[4], a[2], a[4], m[i] + a[5]);
        const glm::mat3 inv = glm::inverse(block);
        pc[0] = inv[0][0];
        pc[1] = inv[0][1];
        pc[2] = inv[0][2];
        pc[3] = inv[1][1];
        pc[4] = inv[1][2];
        pc[5] = inv[2][2];
        r_[i] = dt * f[i] + (dt * dt) * pull;
      }
    }
    // ap = A src and src . ap, per window
    auto multiply = [&](const std::vector<glm::vec3>& src) {
      for (std::size_t w = wb; w < we; ++w) {
        double sum = 0.0;
        for (std::size_t s = w * kWindowSlices, s1 = std::min(slices, s + kWindowSlices); s < s1; ++s) {
          float pix[L], piy[L], piz[L], ax[L], ay[L], az[L];
          for (std::size_t l = 0; l < L; ++l) {
            const std::uint32_t i = cs.owner[s * L + l];
            const glm::vec3 pi = src[i];
            pix[l] = pi.x;
            piy[l] = pi.y;
            piz[l] = pi.z;
            ax[l] = m[i] * pi.x;
            ay[l] = m[i] * pi.y;
            az[l] = m[i] * pi.z;
          }
          const std::size_t row0 = cs.row_begin[s];
          sliceProduct(cs.row_begin[s + 1] - row0, row0 * L, ux_.data(), uy_.data(), uz_.data(), c_.data(),
                       cs.partner.data(), src.data(), pix, piy, piz, ax, ay, az);
          for (std::size_t l = 0; l < L && s * L + l < n; ++l) {
            const std::uint32_t i = cs.owner[s * L + l];
            const glm::vec3 api = root[i] ? glm::vec3(0.0f) : glm::vec3(ax[l], ay[l], az[l]);
            ap_[i] = api;
            sum += static_cast<double>(pix[l] * api.x + piy[l] * api.y + piz[l] * api.z);
          }
        }
        pap_partial_[w] = sum;
      }
    };
    // The residual of the guess (zero, or dv on entry: dv is 0 at roots),
    // its preconditioned form, and the stopping threshold: relative to the
    // preconditioned norm of the right-hand side, as from a zero guess.
    for (std::size_t w = wb; w < we; ++w) {
      double sum = 0.0;
      for (std::size_t i = w * kSliceWindow, e = std::min(n, i + kSliceWindow); i < e; ++i) {
        if (warm && root[i]) dv[i] = glm::vec3(0.0f);
        sum += static_cast<double>(glm::dot(r_[i], applySym(&precond_[6 * i], r_[i])));
      }
      rz_partial_[w] = sum;
    }
    parallel::barrier();
    const double rz0 = total(rz_partial_);
    parallel::barrier();  // every thread has read rz_partial_
    if (warm) {
      multiply(dv);
      for (std::size_t i = ib; i < ie; ++i) r_[i] -= ap_[i];
    }
    // z = P r, p = z
    for (std::size_t w = wb; w < we; ++w) {
      double sum = 0.0;
      for (std::size_t i = w * kSliceWindow, e = std::min(n, i + kSliceWindow); i < e; ++i) {
        z_[i] = applySym(&precond_[6 * i], r_[i]);
        p_[i] = z_[i];
        sum += static_cast<double>(glm::dot(r_[i], z_[i]));
      }
      rz_partial_[w] = sum;
    }
    parallel::barrier();
    double rz = total(rz_partial_);
    int it = 0;
    for (; it < in.max_iterations && rz > tol2 * rz0; ++it) {
      multiply(p_);
      parallel::barrier();
      const double pap = total(pap_partial_);
      if (!(pap > 0.0)) break;
      const float alpha = static_cast<float>(rz / pap);
      for (std::size_t w = wb; w < we; ++w) {
        double sum = 0.0;
        for (std::size_t i = w * kSliceWindow, e = std::min(n, i + kSliceWindow); i < e; ++i) {
          dv[i] += alpha * p_[i];
          r_[i] -= alpha * ap_[i];
          z_[i] = applySym(&precond_[6 * i], r_[i]);
          sum += static_cast<double>(glm::dot(r_[i], z_[i]));
        }
        rz_partial_[w] = sum;
      }
      parallel::barrier();
      const double rz_new = total(rz_partial_);
      const float beta = static_cast<float>(rz_new / rz);
      rz = rz_new;
      for (std::size_t i = ib; i < ie; ++i) p_[i] = z_[i] + beta * p_[i];
      parallel::barrier();
    }
    if (parallel::threadIndex() == 0) {
      report.iterations = it;
      report.residual = rz0 > 0.0 ? static_cast<float>(std::sqrt(rz / rz0)) : 0.0f;
    }
  });
  return report;
}

}  // namespace loosehair
