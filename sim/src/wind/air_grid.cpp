// Wind on a grid: see air_grid.hpp and docs/design.md "Air on a grid".
#include "wind/air_grid.hpp"

#include "util/parallel.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {
namespace {

// Directions of a cell's six faces: -x, +x, -y, +y, -z, +z (grid axes).
constexpr int kStep[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

}  // namespace

AirGrid::AirGrid(const WindParams& params) : p_(params) {
  requireValid(p_);
  axes_ = windAxes(p_);
  h_ = p_.spacing;
  for (int a = 0; a < 3; ++a) n_[a] = std::max(2, static_cast<int>(std::lround(p_.box_size[a] / h_)));
  origin_ = p_.box_center - 0.5f * h_ *
                                (static_cast<float>(n_[0]) * axes_.wind + static_cast<float>(n_[1]) * axes_.up +
                                 static_cast<float>(n_[2]) * axes_.side);
  cell_count_ = static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1]) * static_cast<std::size_t>(n_[2]);
  solve_pad_ = static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1]);
  for (int c = 0; c < 3; ++c) {
    auto& d = fdim_[static_cast<std::size_t>(c)];
    for (int a = 0; a < 3; ++a) d[static_cast<std::size_t>(a)] = n_[a] + (a == c ? 1 : 0);
    const std::size_t faces =
        static_cast<std::size_t>(d[0]) * static_cast<std::size_t>(d[1]) * static_cast<std::size_t>(d[2]);
    for (auto* field : {&u_, &next_}) (*field)[static_cast<std::size_t>(c)].assign(faces, 0.0f);
  }
  pressure_.assign(cell_count_, 0.0f);
  solid_.assign(cell_count_, 0);
  solid_v_.assign(cell_count_, glm::vec3(0.0f));
  links_.assign(cell_count_, 0);
}

double AirGrid::stepLength() const {
  return kCellsAStep * static_cast<double>(h_) / std::max(0.1, static_cast<double>(windMaxSpeed(p_)));
}

bool AirGrid::due(float dt) {
  pending_ += static_cast<double>(dt);
  // the nearest whole number of hair steps to the air's step
  return pending_ + 0.5 * static_cast<double>(dt) >= stepLength();
}

glm::vec3 AirGrid::toGrid(const glm::vec3& world) const {
  const glm::vec3 d = world - origin_;
  return {glm::dot(d, axes_.wind), glm::dot(d, axes_.up), glm::dot(d, axes_.side)};
}

glm::vec3 AirGrid::toWorld(const glm::vec3& g) const {
  return origin_ + g.x * axes_.wind + g.y * axes_.up + g.z * axes_.side;
}

void AirGrid::stencils(const glm::vec3& q, std::uint32_t* index, float* weight) const {
  // per axis: the lower node and fraction on the faces' own axis (offset 0)
  // and on the others (offset half a cell)
  int lo[2][3];
  float fr[2][3];
  for (int a = 0; a < 3; ++a)
    for (int half = 0; half < 2; ++half) {
      const float x = q[a] / h_ - (half ? 0.5f : 0.0f);
      // faces along a: n_a + 1 on their own axis, n_a on the others
      const int last_lower = half ? n_[a] - 2 : n_[a] - 1;
      const int i = std::clamp(static_cast<int>(std::floor(x)), 0, last_lower);
      lo[half][a] = i;
      fr[half][a] = std::clamp(x - static_cast<float>(i), 0.0f, 1.0f);
    }
  for (int c = 0; c < 3; ++c) {
    int i0[3];
    float f[3];
    for (int a = 0; a < 3; ++a) {
      const int half = a == c ? 0 : 1;
      i0[a] = lo[half][a];
      f[a] = fr[half][a];
    }
    int t = 8 * c;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx, ++t) {
          index[t] = static_cast<std::uint32_t>(face(c, i0[0] + dx, i0[1] + dy, i0[2] + dz));
          weight[t] = (dx ? f[0] : 1.0f - f[0]) * (dy ? f[1] : 1.0f - f[1]) * (dz ? f[2] : 1.0f - f[2]);
        }
  }
}

void AirGrid::placeBodies(const BodySampler& bodies) {
  auto& centre = centre_;
  auto& velocity = body_v_;
  auto& phi = body_phi_;
  centre.resize(cell_count_);
  velocity.assign(cell_count_, glm::vec3(0.0f));
  phi.assign(cell_count_, 1.0f);
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i)
        centre[cell(i, j, k)] = toWorld(
            h_ * glm::vec3(static_cast<float>(i) + 0.5f, static_cast<float>(j) + 0.5f, static_cast<float>(k) + 0.5f));
  if (bodies) bodies(centre.data(), cell_count_, phi.data(), velocity.data());
  for (std::size_t q = 0; q < cell_count_; ++q) {
    solid_[q] = phi[q] < 0.0f ? 1 : 0;
    const glm::vec3 w = velocity[q];
    solid_v_[q] = std::isfinite(w.x + w.y + w.z)
                      ? glm::vec3(glm::dot(w, axes_.wind), glm::dot(w, axes_.up), glm::dot(w, axes_.side))
                      : glm::vec3(0.0f);
  }
  // Air that the outflow face does not reach (a pocket closed by the
  // bodies) has no pressure to be solved for: it moves with the bodies.
  // Flood from the open cells at the downwind face, in cell order.
  auto& reached = reached_;
  auto& queue = queue_;
  reached.assign(cell_count_, 0);
  queue.clear();
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        const bool open_face = i == n_[0] - 1;
        const std::size_t q = cell(i, j, k);
        if (open_face && !solid_[q]) {
          reached[q] = 1;
          queue.push_back(q);
        }
      }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t q = queue[head];
    const int i = static_cast<int>(q % static_cast<std::size_t>(n_[0]));
    const int j = static_cast<int>((q / static_cast<std::size_t>(n_[0])) % static_cast<std::size_t>(n_[1]));
    const int k = static_cast<int>(q / (static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1])));
    for (const auto& s : kStep) {
      const int a = i + s[0], b = j + s[1], c = k + s[2];
      if (a < 0 || b < 0 || c < 0 || a >= n_[0] || b >= n_[1] || c >= n_[2]) continue;
      const std::size_t r = cell(a, b, c);
      if (solid_[r] || reached[r]) continue;
      reached[r] = 1;
      queue.push_back(r);
    }
  }
  for (std::size_t q = 0; q < cell_count_; ++q)
    if (!reached[q]) solid_[q] = 1;
  mic_stale_ = true;
  // Which faces of each open cell carry the pressure gradient: those to an
  // open neighbour or out through the downwind face (the upwind face has
  // the wind's velocity, the sides the flow just inside them).
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        const std::size_t q = cell(i, j, k);
        std::uint8_t bits = 0;
        if (!solid_[q])
          for (int d = 0; d < 6; ++d) {
            const int a = i + kStep[d][0], b = j + kStep[d][1], c = k + kStep[d][2];
            const bool outside = a < 0 || b < 0 || c < 0 || a >= n_[0] || b >= n_[1] || c >= n_[2];
            if (outside ? d == 1 : !solid_[cell(a, b, c)]) bits = static_cast<std::uint8_t>(bits | (1u << d));
          }
        links_[q] = bits;
      }
}

void AirGrid::imposeBoundaries(double t) {
  const float speed = windSpeedAt(p_, t);
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j) u_[0][face(0, 0, j, k)] = speed;
  // the four sides let through what reaches them (the flow across a side
  // is its neighbour's inside: no pressure pushes air out or in)
  for (int k = 0; k < n_[2]; ++k)
    for (int i = 0; i < n_[0]; ++i) {
      u_[1][face(1, i, 0, k)] = u_[1][face(1, i, 1, k)];
      u_[1][face(1, i, n_[1], k)] = u_[1][face(1, i, n_[1] - 1, k)];
    }
  for (int j = 0; j < n_[1]; ++j)
    for (int i = 0; i < n_[0]; ++i) {
      u_[2][face(2, i, j, 0)] = u_[2][face(2, i, j, 1)];
      u_[2][face(2, i, j, n_[2])] = u_[2][face(2, i, j, n_[2] - 1)];
    }
  // A face touching a body takes the body's velocity (the mean of the
  // bodies' cells it touches).
  for (int c = 0; c < 3; ++c) {
    const auto& d = fdim_[static_cast<std::size_t>(c)];
    auto& u = u_[static_cast<std::size_t>(c)];
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          int idx[3] = {i, j, k};
          float sum = 0.0f;
          int count = 0;
          for (int side = 0; side < 2; ++side) {
            int cidx[3] = {idx[0], idx[1], idx[2]};
            cidx[c] -= 1 - side;  // the cell below the face, then above
            if (cidx[c] < 0 || cidx[c] >= n_[c]) continue;
            const std::size_t q = cell(cidx[0], cidx[1], cidx[2]);
            if (!solid_[q]) continue;
            sum += solid_v_[q][c];
            ++count;
          }
          if (count > 0) u[face(c, i, j, k)] = sum / static_cast<float>(count);
        }
  }
}

double AirGrid::outflow(int i, int j, int k) const {
  return static_cast<double>(u_[0][face(0, i + 1, j, k)]) - u_[0][face(0, i, j, k)] + u_[1][face(1, i, j + 1, k)] -
         u_[1][face(1, i, j, k)] + u_[2][face(2, i, j, k + 1)] - u_[2][face(2, i, j, k)];
}

void AirGrid::buildPreconditioner() {
  // The matrix (each open cell's linked faces on the diagonal, -1 to each
  // linked neighbour inside the box), then modified incomplete Cholesky,
  // MIC(0) (Bridson, Fluid Simulation for Computer Graphics, ch. 4): the
  // factor's inverse diagonal in cell order and its +x, +y, +z couplings.
  // All in the padded cell order (solve_pad_ zero cells before and after),
  // so the solve's loops read their neighbours without a test: a coupling
  // to a neighbour outside the box, or of a closed cell, is 0.
  const std::size_t nc = cell_count_, pad = solve_pad_, total = nc + 2 * pad;
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n_[0]),
                                 static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1])};
  diag_.assign(total, 0.0);
  mic_.assign(total, 0.0);
  for (int a = 0; a < 3; ++a) {
    coupling_[static_cast<std::size_t>(a)].assign(total, 0.0);
    mic_up_[static_cast<std::size_t>(a)].assign(total, 0.0);
  }
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        const std::size_t q = cell(i, j, k), p = q + pad;
        const int at[3] = {i, j, k};
        diag_[p] = static_cast<double>(std::popcount(links_[q]));
        for (int a = 0; a < 3; ++a)
          if ((links_[q] >> (2 * a + 1)) & 1u && at[a] + 1 < n_[a]) coupling_[static_cast<std::size_t>(a)][p] = -1.0;
      }
  constexpr double kTau = 0.97, kSigma = 0.25;
  for (std::size_t p = pad; p < pad + nc; ++p) {
    if (diag_[p] == 0.0) continue;
    double e = diag_[p];
    for (std::size_t a = 0; a < 3; ++a) {
      // the cell before along a (at the box's low face: the last cell of
      // the row or slab before, or the pad, whose coupling along a is 0)
      const std::size_t m = p - stride[a];
      const double c = coupling_[a][m] * mic_[m];
      if (c == 0.0) continue;
      e -= c * c;
      double others = 0.0;
      for (std::size_t b = 0; b < 3; ++b)
        if (b != a) others += coupling_[b][m];
      e -= kTau * coupling_[a][m] * others * mic_[m] * mic_[m];
    }
    if (e < kSigma * diag_[p]) e = diag_[p];
    mic_[p] = 1.0 / std::sqrt(e);
    for (std::size_t a = 0; a < 3; ++a) mic_up_[a][p] = coupling_[a][p] * mic_[p];
  }
  // the sweeps' chain along x: a cell's coupling to the one before it
  // (forwards) or after it (backwards), times its own inverse diagonal
  for (auto& chain : mic_chain_) chain.assign(total, 0.0);
  for (std::size_t p = pad; p < pad + nc; ++p) {
    mic_chain_[0][p] = mic_up_[0][p - 1] * mic_[p];
    mic_chain_[1][p] = mic_up_[0][p] * mic_[p];
  }
  mic_stale_ = false;
}

void AirGrid::project(int threads) {
  const std::size_t nc = cell_count_, pad = solve_pad_, total = nc + 2 * pad;
  const std::size_t sy = static_cast<std::size_t>(n_[0]),
                    sz = static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1]);
  if (mic_stale_) buildPreconditioner();
  for (auto* v : {&x_, &r_, &z_, &d_, &ad_}) v->assign(total, 0.0);
  const double* cx = coupling_[0].data();
  const double* cy = coupling_[1].data();
  const double* cz = coupling_[2].data();
  // out = A v over the cells (padded order; the pads of v are 0), in slabs
  // of constant k
  auto apply = [&](const std::vector<double>& v, std::vector<double>& out) {
    parallel::forEach(threads, static_cast<std::size_t>(n_[2]), [&](std::size_t k) {
      const double* x = v.data();
      for (std::size_t p = pad + k * sz, e = p + sz; p < e; ++p)
        out[p] = diag_[p] * x[p] + cx[p] * x[p + 1] + cx[p - 1] * x[p - 1] + cy[p] * x[p + sy] +
                 cy[p - sy] * x[p - sy] + cz[p] * x[p + sz] + cz[p - sz] * x[p - sz];
    });
  };
  auto& x = x_;
  for (std::size_t q = 0; q < nc; ++q) x[q + pad] = links_[q] ? static_cast<double>(pressure_[q]) : 0.0;
  // r = b - A x from the last pressure, b = -h div u (minus the flux out of
  // each open cell)
  apply(x, ad_);
  double bnorm = 0.0;
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        const std::size_t q = cell(i, j, k);
        if (!links_[q]) continue;
        r_[q + pad] = -outflow(i, j, k) - ad_[q + pad];
        bnorm = std::max(bnorm, std::abs(r_[q + pad]));
      }
  // Preconditioned conjugate gradients; the sums and sweeps in cell order
  // on this thread. The flux imbalance left is at most a thousandth of the
  // fastest wind through a face.
  const double tolerance = 1e-3 * std::max(0.1, static_cast<double>(windMaxSpeed(p_)));
  const std::size_t begin = pad, end = pad + nc;
  // the preconditioner: two triangular sweeps of MIC(0)
  // (buildPreconditioner); a closed cell's inverse diagonal is 0, so its z
  // stays 0. Along x each cell waits for the one before it: that chain is
  // one multiply-add a cell (mic_chain_: the x coupling times the inverse
  // diagonal), the rows below and behind are done already.
  const double* my = mic_up_[1].data();
  const double* mz = mic_up_[2].data();
  const double* chain_fwd = mic_chain_[0].data();
  const double* chain_bwd = mic_chain_[1].data();
  auto precondition = [&] {
    double* z = z_.data();
    double prev = 0.0;                         // z of the cell before (0: the pad's)
    for (std::size_t p = begin; p < end; ++p)  // L q = r, forwards
      z[p] = prev = (r_[p] - my[p - sy] * z[p - sy] - mz[p - sz] * z[p - sz]) * mic_[p] - chain_fwd[p] * prev;
    prev = 0.0;
    for (std::size_t p = end; p-- > begin;)  // L^T z = q, backwards
      z[p] = prev = (z[p] - my[p] * z[p + sy] - mz[p] * z[p + sz]) * mic_[p] - chain_bwd[p] * prev;
    double rz = 0.0;
    for (std::size_t p = begin; p < end; ++p) rz += r_[p] * z[p];
    return rz;
  };
  double rz = precondition();
  d_ = z_;
  int it = 0;
  constexpr int kMaxIterations = 600;
  double worst = bnorm;
  while (worst > tolerance && it < kMaxIterations) {
    apply(d_, ad_);
    double dad = 0.0;
    for (std::size_t p = begin; p < end; ++p) dad += d_[p] * ad_[p];
    if (!(dad > 0.0)) break;
    const double alpha = rz / dad;
    worst = 0.0;
    for (std::size_t p = begin; p < end; ++p) {
      x[p] += alpha * d_[p];
      r_[p] -= alpha * ad_[p];
      worst = std::max(worst, std::abs(r_[p]));
    }
    const double rz_next = precondition();
    const double beta = rz_next / rz;
    rz = rz_next;
    for (std::size_t p = begin; p < end; ++p) d_[p] = z_[p] + beta * d_[p];
    ++it;
  }
  last_iterations_ = it;
  for (std::size_t q = 0; q < nc; ++q) pressure_[q] = static_cast<float>(x[q + pad]);
  // u -= grad p on the linked faces (a face is linked from both of its
  // open cells, or from its one open cell at the box's open faces).
  for (int c = 0; c < 3; ++c) {
    const auto& dm = fdim_[static_cast<std::size_t>(c)];
    auto& u = u_[static_cast<std::size_t>(c)];
    const int lower_bit = 2 * c, upper_bit = 2 * c + 1;
    parallel::forEach(threads, static_cast<std::size_t>(dm[2]), [&](std::size_t kk) {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < dm[1]; ++j)
        for (int i = 0; i < dm[0]; ++i) {
          int below[3] = {i, j, k};
          below[c] -= 1;
          const int above_at = c == 0 ? i : (c == 1 ? j : k);
          const bool has_below = below[c] >= 0, has_above = above_at < n_[c];
          const std::size_t qb = has_below ? cell(below[0], below[1], below[2]) : 0;
          const std::size_t qa = has_above ? cell(i, j, k) : 0;
          // linked from the open side(s)
          const bool linked = has_above ? (links_[qa] >> lower_bit) & 1u : (links_[qb] >> upper_bit) & 1u;
          if (!linked) continue;
          const double pa = has_above ? x[qa + pad] : 0.0, pb = has_below ? x[qb + pad] : 0.0;
          u[face(c, i, j, k)] -= static_cast<float>(pa - pb);
        }
    });
  }
}

void AirGrid::fill(double t, const BodySampler& bodies) {
  placeBodies(bodies);
  const float speed = windSpeedAt(p_, t);
  std::fill(u_[0].begin(), u_[0].end(), speed);
  std::fill(u_[1].begin(), u_[1].end(), 0.0f);
  std::fill(u_[2].begin(), u_[2].end(), 0.0f);
  pending_ = 0.0;
  std::fill(pressure_.begin(), pressure_.end(), 0.0f);
  imposeBoundaries(t);
  project(1);
}

// Each hair particle's stencil (the lower of its eight cells and
// their trilinear weights, between cell centres) and its world
// velocity in the grid's axes; the cells' velocities, the mean of
// each component's two faces.
void AirGrid::dragStencils(const DragPass& pass, std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                           std::span<const std::uint8_t> hair_root) {
  const std::size_t nh = hair_x.size();
  const glm::mat3& rot = pass.rot;
  const glm::vec3 centre = pass.centre, omega = pass.omega, frame_v = pass.frame_v, extent = pass.extent;
  constexpr std::uint32_t kNone = UINT32_MAX;
  const auto [b, e] = parallel::share(nh);
  for (std::size_t i = b; i < e; ++i) {
    const glm::vec3 q = toGrid(rot * hair_x[i] + centre);
    const bool inside =
        q.x >= 0.0f && q.y >= 0.0f && q.z >= 0.0f && q.x <= extent.x && q.y <= extent.y && q.z <= extent.z;
    if (hair_root[i] || !inside) {
      hair_cell_[i] = kNone;
      continue;
    }
    int lo[3];
    glm::vec3 f;
    for (int a = 0; a < 3; ++a) {
      // x >= -0.5 inside the box: truncation is the floor where it
      // matters (below 0 both clamp to the first cell, fraction 0)
      const float x = q[a] / h_ - 0.5f;
      lo[a] = std::clamp(static_cast<int>(x), 0, n_[a] - 2);
      f[a] = std::clamp(x - static_cast<float>(lo[a]), 0.0f, 1.0f);
    }
    hair_cell_[i] = static_cast<std::uint32_t>(cell(lo[0], lo[1], lo[2]));
    const float yz[4] = {(1.0f - f.y) * (1.0f - f.z), f.y * (1.0f - f.z), (1.0f - f.y) * f.z, f.y * f.z};
    for (int t = 0; t < 4; ++t) {
      hair_w_[i][2 * t] = (1.0f - f.x) * yz[t];
      hair_w_[i][2 * t + 1] = f.x * yz[t];
    }
    const glm::vec3 vw = rot * (hair_v[i] + glm::cross(omega, hair_x[i])) + frame_v;
    hair_vb_[i] = {glm::dot(vw, axes_.wind), glm::dot(vw, axes_.up), glm::dot(vw, axes_.side)};
  }
  const auto [kb, ke] = parallel::share(static_cast<std::size_t>(n_[2]));
  for (int k = static_cast<int>(kb); k < static_cast<int>(ke); ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i)
        cell_air_[cell(i, j, k)] = glm::vec4(0.5f * glm::vec3(u_[0][face(0, i, j, k)] + u_[0][face(0, i + 1, j, k)],
                                                              u_[1][face(1, i, j, k)] + u_[1][face(1, i, j + 1, k)],
                                                              u_[2][face(2, i, j, k)] + u_[2][face(2, i, j, k + 1)]),
                                             0.0f);
}

// The hair mass each cell holds, which makes its limiter (as the
// particle air's: a side whose velocity would relax by more than
// half in a step has its pair forces scaled down; a pair takes the
// smaller of its two). Each thread owns a range of cells and adds
// their taps in hair order: the same sums for any thread count.
void AirGrid::dragLimiters(const DragPass& pass, std::span<const float> hair_m, float dt, std::size_t cb,
                           std::size_t ce) {
  const std::size_t nh = hair_m.size();
  const float rate = pass.rate, cell_mass = pass.cell_mass, hair_limit = pass.hair_limit;
  const std::uint32_t* offset = pass.offset;
  constexpr std::uint32_t kNone = UINT32_MAX;
  for (std::size_t i = 0; i < nh; ++i) {
    const std::uint32_t base = hair_cell_[i];
    if (base == kNone || base + offset[7] < cb || base >= ce) continue;
    const auto& w = hair_w_[i];
    for (int t = 0; t < 8; ++t) {
      const std::uint32_t q = base + offset[t];
      if (q >= cb && q < ce) cell_air_[q].w += w[t] * hair_m[i];
    }
  }
  for (std::size_t q = cb; q < ce; ++q) {
    const float r = rate * cell_air_[q].w / cell_mass;
    cell_air_[q].w = std::min(hair_limit, r * dt > 0.5f ? 0.5f / (r * dt) : 1.0f);
  }
}

// The force on each hair particle.
void AirGrid::dragOnHair(const DragPass& pass, std::span<const float> hair_m, std::span<glm::vec3> hair_force) {
  const std::size_t nh = hair_m.size();
  const glm::mat3& rot_t = pass.rot_t;
  const float rate = pass.rate;
  const std::uint32_t* offset = pass.offset;
  constexpr std::uint32_t kNone = UINT32_MAX;
  const auto [b, e] = parallel::share(nh);
  for (std::size_t i = b; i < e; ++i) {
    const std::uint32_t base = hair_cell_[i];
    if (base == kNone) continue;
    const auto& w = hair_w_[i];
    glm::vec3 sum_u(0.0f);  // sum_t w_t L_t U_t
    float sum_w = 0.0f;     // sum_t w_t L_t
    for (int t = 0; t < 8; ++t) {
      const glm::vec4 air = cell_air_[base + offset[t]];
      const float a = w[t] * air.w;
      sum_u += a * glm::vec3(air);
      sum_w += a;
    }
    const glm::vec3 force = rate * hair_m[i] * (sum_u - sum_w * hair_vb_[i]);
    const glm::vec3 world = force.x * axes_.wind + force.y * axes_.up + force.z * axes_.side;
    hair_force[i] += rot_t * world;
  }
}

// The opposite impulses onto the cells (velocity changes), each
// thread its cells in hair order, as the masses.
void AirGrid::dragOnCells(const DragPass& pass, std::span<const float> hair_m, float dt, std::size_t cb,
                          std::size_t ce) {
  const std::size_t nh = hair_m.size();
  const float rate = pass.rate, cell_mass = pass.cell_mass;
  const std::uint32_t* offset = pass.offset;
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::fill(cell_push_.begin() + static_cast<std::ptrdiff_t>(cb), cell_push_.begin() + static_cast<std::ptrdiff_t>(ce),
            glm::vec3(0.0f));
  const float to_velocity = -rate * dt / cell_mass;
  for (std::size_t i = 0; i < nh; ++i) {
    const std::uint32_t base = hair_cell_[i];
    if (base == kNone || base + offset[7] < cb || base >= ce) continue;
    const auto& w = hair_w_[i];
    const float scale = to_velocity * hair_m[i];
    const glm::vec3 v = hair_vb_[i];
    for (int t = 0; t < 8; ++t) {
      const std::uint32_t q = base + offset[t];
      if (q < cb || q >= ce) continue;
      const glm::vec4 air = cell_air_[q];
      cell_push_[q] += (scale * w[t] * air.w) * (glm::vec3(air) - v);
    }
  }
}

// Each cell's impulse goes half to each of its two faces of every
// component (so the faces' momentum changes by the cells'), the faces
// shared by the threads in slabs along z.
void AirGrid::cellsToFaces() {
  const auto [kb, ke] = parallel::share(static_cast<std::size_t>(n_[2]) + 1);
  for (int c = 0; c < 3; ++c) {
    const auto& d = fdim_[static_cast<std::size_t>(c)];
    auto& u = u_[static_cast<std::size_t>(c)];
    for (int k = static_cast<int>(kb); k < std::min(static_cast<int>(ke), d[2]); ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          int at[3] = {i, j, k};
          float sum = 0.0f;
          if (at[c] < n_[c]) sum += cell_push_[cell(at[0], at[1], at[2])][c];
          at[c] -= 1;
          if (at[c] >= 0) sum += cell_push_[cell(at[0], at[1], at[2])][c];
          u[face(c, i, j, k)] += 0.5f * sum;
        }
  }
}

void AirGrid::exchangeDrag(const HeadKinematics& head, std::span<const glm::vec3> hair_x,
                           std::span<const glm::vec3> hair_v, std::span<const float> hair_m,
                           std::span<const std::uint8_t> hair_root, std::span<glm::vec3> hair_force, float dt,
                           int threads) {
  const std::size_t nh = hair_x.size(), nc = cell_count_;
  hair_cell_.resize(nh);
  hair_w_.resize(nh);
  hair_vb_.resize(nh);
  cell_air_.resize(nc);
  cell_push_.resize(nc);
  DragPass pass;
  pass.rot = glm::mat3(head.pose.rotation);
  pass.rot_t = glm::transpose(glm::mat3(head.pose.rotation));
  pass.centre = glm::vec3(head.pose.center);
  pass.omega = glm::vec3(head.angular_velocity);
  pass.frame_v = glm::vec3(head.velocity);
  pass.extent = h_ * glm::vec3(static_cast<float>(n_[0]), static_cast<float>(n_[1]), static_cast<float>(n_[2]));
  const std::uint32_t sy = static_cast<std::uint32_t>(n_[0]), sz = sy * static_cast<std::uint32_t>(n_[1]);
  // a stencil's eight cells: the base and +x, +y, +z combinations
  const std::uint32_t offset[8] = {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
  std::copy(std::begin(offset), std::end(offset), pass.offset);
  const float rate = p_.drag_rate, cell_mass = p_.density * h_ * h_ * h_;
  pass.rate = rate;
  pass.cell_mass = cell_mass;
  pass.hair_limit = rate * dt > 0.5f ? 0.5f / (rate * dt) : 1.0f;
  // The pair forces of a hair particle and its cells, on the hair (the
  // cells take minus them): rate m_i w_t L_t (U_t - v_i), with the pair's
  // limiter L_t = min(the hair's, the cell's). cell_air_ holds (U, L).
  constexpr std::uint32_t kNone = UINT32_MAX;
  parallel::run(threads, [&] {
    dragStencils(pass, hair_x, hair_v, hair_root);
    parallel::barrier();
    const auto [cb, ce] = parallel::share(nc);
    dragLimiters(pass, hair_m, dt, cb, ce);
    parallel::barrier();
    dragOnHair(pass, hair_m, hair_force);
    dragOnCells(pass, hair_m, dt, cb, ce);
    parallel::barrier();
    cellsToFaces();
  });
  coupled_ = static_cast<std::size_t>(
      std::count_if(hair_cell_.begin(), hair_cell_.end(), [](std::uint32_t q) { return q != kNone; }));
  // the air's side of the exchange, summed in cell order
  glm::dvec3 on_air(0.0);
  for (const glm::vec3& push : cell_push_) on_air += glm::dvec3(push);
  on_air *= dt > 0.0f ? static_cast<double>(cell_mass) / static_cast<double>(dt) : 0.0;
  drag_on_air_ =
      on_air.x * glm::dvec3(axes_.wind) + on_air.y * glm::dvec3(axes_.up) + on_air.z * glm::dvec3(axes_.side);
}

void AirGrid::advance(double t, const BodySampler& bodies, int threads) {
  const auto dt = static_cast<float>(pending_);
  pending_ = 0.0;
  if (bodies) placeBodies(bodies);
  // Viscosity: each face relaxes towards the mean of its neighbours of the
  // same component at the viscosity rate.
  const float relax = std::min(1.0f, p_.viscosity_rate * dt);
  for (int c = 0; c < 3; ++c) {
    auto& u = u_[static_cast<std::size_t>(c)];
    const auto& d = fdim_[static_cast<std::size_t>(c)];
    auto& out = next_[static_cast<std::size_t>(c)];
    parallel::forEach(threads, static_cast<std::size_t>(d[2]), [&](std::size_t kk) {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const std::size_t q = face(c, i, j, k);
          float sum = 0.0f;
          int count = 0;
          if (i > 0) sum += u[face(c, i - 1, j, k)], ++count;
          if (i + 1 < d[0]) sum += u[face(c, i + 1, j, k)], ++count;
          if (j > 0) sum += u[face(c, i, j - 1, k)], ++count;
          if (j + 1 < d[1]) sum += u[face(c, i, j + 1, k)], ++count;
          if (k > 0) sum += u[face(c, i, j, k - 1)], ++count;
          if (k + 1 < d[2]) sum += u[face(c, i, j, k + 1)], ++count;
          out[q] = u[q] + relax * (sum / static_cast<float>(count) - u[q]);
        }
    });
  }
  std::swap(u_, next_);
  // Advection: each face takes the velocity found a step back along the
  // flow (Stam's backtrace, from the face's own velocity: its component and
  // the mean of the four nearest faces of each other component; the air
  // moves at most two cells a step, see stableTimeStep); from upwind of the
  // box, the wind's.
  const float inflow = windSpeedAt(p_, t);
  const float step_cells = dt / h_;
  for (int c = 0; c < 3; ++c) {
    const auto& d = fdim_[static_cast<std::size_t>(c)];
    const int dx = d[0], dy = d[1], dz = d[2];
    const std::size_t sy = static_cast<std::size_t>(dx), sz = sy * static_cast<std::size_t>(dy);
    const float* own = u_[static_cast<std::size_t>(c)].data();
    float* out = next_[static_cast<std::size_t>(c)].data();
    const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
    parallel::forEach(threads, static_cast<std::size_t>(dz), [&](std::size_t kk) {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < dy; ++j)
        for (int i = 0; i < dx; ++i) {
          const int at[3] = {i, j, k};
          glm::vec3 vel(0.0f);
          vel[c] =
              own[static_cast<std::size_t>(i) + sy * static_cast<std::size_t>(j) + sz * static_cast<std::size_t>(k)];
          // component o's faces around this one: cells at[c]-1 and at[c]
          // along c (clamped), at[o] and at[o]+1 along o
          for (const int o : {c1, c2}) {
            int idx[3] = {at[0], at[1], at[2]};
            const int lo = std::max(at[c] - 1, 0), hi = std::min(at[c], n_[c] - 1);
            idx[c] = lo;
            const std::size_t a = face(o, idx[0], idx[1], idx[2]);
            idx[c] = hi;
            const std::size_t b = face(o, idx[0], idx[1], idx[2]);
            const std::size_t up = o == 0
                                       ? 1
                                       : (o == 1 ? static_cast<std::size_t>(fdim_[static_cast<std::size_t>(o)][0])
                                                 : static_cast<std::size_t>(fdim_[static_cast<std::size_t>(o)][0]) *
                                                       static_cast<std::size_t>(fdim_[static_cast<std::size_t>(o)][1]));
            const float* uo = u_[static_cast<std::size_t>(o)].data();
            vel[o] = 0.25f * (uo[a] + uo[b] + uo[a + up] + uo[b + up]);
          }
          // the backtraced point in this component's index space
          const float g[3] = {static_cast<float>(i) - step_cells * vel.x, static_cast<float>(j) - step_cells * vel.y,
                              static_cast<float>(k) - step_cells * vel.z};
          const std::size_t q =
              static_cast<std::size_t>(i) + sy * static_cast<std::size_t>(j) + sz * static_cast<std::size_t>(k);
          // upwind of the box (its upwind face is x = 0 in grid metres)
          const float along = c == 0 ? g[0] : g[0] + 0.5f;
          if (along < 0.0f) {
            out[q] = c == 0 ? inflow : 0.0f;
            continue;
          }
          int i0[3];
          float f[3];
          for (int a = 0; a < 3; ++a) {
            const int last_lower = d[static_cast<std::size_t>(a)] - 2;
            const int lo = std::clamp(static_cast<int>(std::floor(g[a])), 0, last_lower);
            i0[a] = lo;
            f[a] = std::clamp(g[a] - static_cast<float>(lo), 0.0f, 1.0f);
          }
          const float* base = own + static_cast<std::size_t>(i0[0]) + sy * static_cast<std::size_t>(i0[1]) +
                              sz * static_cast<std::size_t>(i0[2]);
          const float x00 = base[0] + f[0] * (base[1] - base[0]);
          const float x10 = base[sy] + f[0] * (base[sy + 1] - base[sy]);
          const float x01 = base[sz] + f[0] * (base[sz + 1] - base[sz]);
          const float x11 = base[sz + sy] + f[0] * (base[sz + sy + 1] - base[sz + sy]);
          const float y0 = x00 + f[1] * (x10 - x00), y1 = x01 + f[1] * (x11 - x01);
          out[q] = y0 + f[2] * (y1 - y0);
        }
    });
  }
  std::swap(u_, next_);
  imposeBoundaries(t);
  project(threads);
}

std::size_t AirGrid::openCellCount() const {
  return static_cast<std::size_t>(std::count(solid_.begin(), solid_.end(), std::uint8_t{0}));
}

void AirGrid::openCells(std::vector<glm::vec3>& centre, std::vector<glm::vec3>& velocity) const {
  centre.clear();
  velocity.clear();
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        if (solid_[cell(i, j, k)]) continue;
        centre.push_back(toWorld(
            h_ * glm::vec3(static_cast<float>(i) + 0.5f, static_cast<float>(j) + 0.5f, static_cast<float>(k) + 0.5f)));
        const glm::vec3 v(0.5f * (u_[0][face(0, i, j, k)] + u_[0][face(0, i + 1, j, k)]),
                          0.5f * (u_[1][face(1, i, j, k)] + u_[1][face(1, i, j + 1, k)]),
                          0.5f * (u_[2][face(2, i, j, k)] + u_[2][face(2, i, j, k + 1)]));
        velocity.push_back(v.x * axes_.wind + v.y * axes_.up + v.z * axes_.side);
      }
}

glm::vec3 AirGrid::velocityAt(const glm::vec3& world) const {
  std::uint32_t index[kTaps];
  float weight[kTaps];
  stencils(toGrid(world), index, weight);
  glm::vec3 v(0.0f);
  for (int t = 0; t < kTaps; ++t) v[t / 8] += weight[t] * u_[static_cast<std::size_t>(t / 8)][index[t]];
  return v.x * axes_.wind + v.y * axes_.up + v.z * axes_.side;
}

float AirGrid::maxDivergence() const {
  float worst = 0.0f;
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        if (!links_[cell(i, j, k)]) continue;
        worst = std::max(worst, static_cast<float>(std::abs(outflow(i, j, k))) / h_);
      }
  return worst;
}

void AirGrid::restore(State s) {
  for (std::size_t c = 0; c < 3; ++c)
    if (s.u[c].size() != u_[c].size())
      throw std::invalid_argument("air grid state: " + std::to_string(s.u[c].size()) + " faces of component " +
                                  std::to_string(c) + ", the grid has " + std::to_string(u_[c].size()));
  if (s.pressure.size() != cell_count_)
    throw std::invalid_argument("air grid state: " + std::to_string(s.pressure.size()) + " cells, the grid has " +
                                std::to_string(cell_count_));
  if (!std::isfinite(s.pending) || s.pending < 0.0 || s.pending > 10.0 * stepLength())
    throw std::invalid_argument("air grid state: the time since its last step is " + std::to_string(s.pending) + " s");
  u_ = std::move(s.u);
  pressure_ = std::move(s.pressure);
  pending_ = s.pending;
}

// ---- WindAir ------------------------------------------------------------------
void AirGrid::move(double, double t_end, float, const Bodies& bodies, int threads) {
  if (!bodies.moved) {
    advance(t_end, {}, threads);
    return;
  }
  advance(
      t_end,
      [&bodies](const glm::vec3* w, std::size_t n, float* phi, glm::vec3* v) { bodies.worldSample(w, n, phi, v); },
      threads);
}

void AirGrid::worldState(const HeadKinematics&, std::vector<glm::vec3>* x, std::vector<glm::vec3>* v) const {
  std::vector<glm::vec3> unused;
  openCells(x ? *x : unused, v ? *v : unused);
}

std::span<const float> AirGrid::density() const {
  density_.assign(openCellCount(), p_.density);
  return density_;
}

void AirGrid::report(StepStats& stats) const {
  stats.air_particles = cellCount();
  stats.hair_air_pairs = 0;
  stats.coupled_hair = coupled_;
  stats.air_iterations = last_iterations_;
}

std::size_t AirGrid::nonFinite() const {
  std::size_t n = 0;
  for (const auto& u : u_)
    for (float f : u) n += !std::isfinite(f);
  for (float f : pressure_) n += !std::isfinite(f);
  return n;
}

void AirGrid::hashState(const std::function<void(const void* data, std::size_t bytes)>& mix) const {
  for (const auto& u : u_) mix(u.data(), u.size() * sizeof(float));
}

}  // namespace loosehair
