// Backward-Euler velocity solve of the loose springs (implicit_springs.hpp).
#include "solver/implicit_springs.hpp"

#include "solver/pair_columns.hpp"
#include "util/parallel.hpp"

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
// slice, row by row (each lane in its list's order); multiversioned like
// the pair kernels (the same bits in every version).
LOOSEHAIR_PAIR_KERNEL
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

// The set-up of one slice (16 lanes, row by row, each lane's sums in its
// list's order): per entry c = scale w (0 where `live` is 0 or past the
// lane's degree), and per lane the sums of c n n^T (6 numbers).
struct SetupLanes {
  float degree[L], live[L];
  float a[6][L];
};
LOOSEHAIR_PAIR_KERNEL
void sliceSetup(std::size_t rows, std::size_t q0, float scale, const float* __restrict weight,
                const float* __restrict ux, const float* __restrict uy, const float* __restrict uz, float* __restrict c,
                SetupLanes& __restrict s) {
  for (int k = 0; k < 6; ++k)
    for (std::size_t l = 0; l < L; ++l) s.a[k][l] = 0.0f;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t q = q0 + r * L;
    const float row = static_cast<float>(r);
    for (std::size_t l = 0; l < L; ++l) {
      const bool on = s.live[l] != 0.0f && row < s.degree[l];
      const float nx = ux[q + l], ny = uy[q + l], nz = uz[q + l];
      const float cq = on ? scale * weight[q + l] : 0.0f;
      c[q + l] = cq;
      s.a[0][l] += cq * nx * nx;
      s.a[1][l] += cq * nx * ny;
      s.a[2][l] += cq * nx * nz;
      s.a[3][l] += cq * ny * ny;
      s.a[4][l] += cq * ny * nz;
      s.a[5][l] += cq * nz * nz;
    }
  }
}

}  // namespace

// The blocks of a thread's slices [sb, se): each owner's entries, its 3x3
// block's inverse (the preconditioner) and its right-hand side
// dt f_i + dt^2 sum_j w n (n . (v_j - v_i)), in list order.
void ImplicitSprings::setUp(const Input& in, const Part& part, float scale) {
  const ConnectionSlices& cs = *in.layout;
  const std::size_t n = in.particles;
  const float dt = in.dt;
  const glm::vec3* f = in.force;
  const float* m = in.mass;
  const std::uint8_t* root = in.is_root;
  const std::size_t sb = part.sb, se = part.se;
  SetupLanes lanes;
  for (std::size_t s = sb; s < se; ++s) {
    const std::size_t row0 = cs.row_begin[s], rows = cs.row_begin[s + 1] - row0;
    for (std::size_t l = 0; l < L; ++l) {
      const std::size_t lane = s * L + l;
      lanes.degree[l] = cs.degree[lane];
      lanes.live[l] = lane < n && root[cs.owner[lane]] == 0 ? 1.0f : 0.0f;
    }
    sliceSetup(rows, row0 * L, scale, in.weight, in.unit_x, in.unit_y, in.unit_z, c_.data(), lanes);
    for (std::size_t l = 0; l < L; ++l) {
      const std::size_t lane = s * L + l;
      if (lane >= n) continue;
      const std::uint32_t i = cs.owner[lane];
      float* pc = &precond_[6 * std::size_t{i}];
      if (root[i]) {
        std::fill(pc, pc + 6, 0.0f);
        r_[i] = glm::vec3(0.0f);
        continue;
      }
      const float a0 = lanes.a[0][l], a1 = lanes.a[1][l], a2 = lanes.a[2][l], a3 = lanes.a[3][l], a4 = lanes.a[4][l],
                  a5 = lanes.a[5][l];
      const glm::mat3 block(m[i] + a0, a1, a2, a1, m[i] + a3, a4, a2, a4, m[i] + a5);
      const glm::mat3 inv = glm::inverse(block);
      pc[0] = inv[0][0];
      pc[1] = inv[0][1];
      pc[2] = inv[0][2];
      pc[3] = inv[1][1];
      pc[4] = inv[1][2];
      pc[5] = inv[2][2];
      r_[i] = dt * f[i] + (dt * dt) * in.pull[i];
    }
  }
}

// ap = A src over a thread's windows, and src . ap per window.
void ImplicitSprings::multiply(const Input& in, const Part& part, const std::vector<glm::vec3>& src) {
  const ConnectionSlices& cs = *in.layout;
  const std::size_t n = in.particles, slices = cs.sliceCount();
  const float* m = in.mass;
  const std::uint8_t* root = in.is_root;
  const std::size_t wb = part.wb, we = part.we;
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
      sliceProduct(cs.row_begin[s + 1] - row0, row0 * L, in.unit_x, in.unit_y, in.unit_z, c_.data(), cs.partner.data(),
                   src.data(), pix, piy, piz, ax, ay, az);
      for (std::size_t l = 0; l < L && s * L + l < n; ++l) {
        const std::uint32_t i = cs.owner[s * L + l];
        const glm::vec3 api = root[i] ? glm::vec3(0.0f) : glm::vec3(ax[l], ay[l], az[l]);
        ap_[i] = api;
        sum += static_cast<double>(pix[l] * api.x + piy[l] * api.y + piz[l] * api.z);
      }
    }
    pap_partial_[w] = sum;
  }
}

ImplicitSpringReport ImplicitSprings::solve(const Input& in, int threads, std::vector<glm::vec3>& dv) {
  const ConnectionSlices& cs = *in.layout;
  const std::size_t n = in.particles, slices = cs.sliceCount();
  const std::size_t windows = (slices + kWindowSlices - 1) / kWindowSlices;
  const std::size_t entries = cs.entryCount();
  c_.resize(entries);
  precond_.resize(6 * n);
  r_.resize(n);
  z_.resize(n);
  p_.resize(n);
  ap_.resize(n);
  // the guess may be dv itself (the last step's answer)
  const bool warm = in.guess != nullptr;
  if (!warm)
    dv.assign(n, glm::vec3(0.0f));
  else if (in.guess != dv.data())
    dv.assign(in.guess, in.guess + n);
  else
    dv.resize(n);
  pap_partial_.assign(windows, 0.0);
  rz_partial_.assign(windows, 0.0);
  const float dt = in.dt, scale = dt * dt + in.gamma * dt;
  const double tol2 = static_cast<double>(in.tolerance) * in.tolerance;
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
    const Part part{wb, we, sb, se};
    setUp(in, part, scale);
    // ap = A src and src . ap, per window
    auto multiply = [&](const std::vector<glm::vec3>& src) { this->multiply(in, part, src); };
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
