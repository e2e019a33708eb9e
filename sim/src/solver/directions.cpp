// The hair directions, eq. 15, with the spring lengths of the next step
// (directions.hpp).
// The weights alpha_ij k_ij are this step's; x_ij are the new positions. The
// same pass measures |x_ij|, k_ij and the side sums at the new positions,
// which the next step's factor pass would otherwise gather again, and checks
// that every particle's state is finite.
#include "solver/directions.hpp"

#include "solver/connection_builder.hpp"
#include "solver/connection_passes.hpp"

#include <glm/geometric.hpp>

#include <atomic>
#include <cassert>
#include <cmath>

namespace loosehair {

namespace {

// For the connections of a run of slices: the direction t_ij that i's hair
// direction would have if the pair kept its rest angle (x_ij turned by
// theta_ij towards t_i), weighted by this step's alpha_ij k_ij and summed
// per lane; and per lane the sums of l_ij k_ij of each side and the count
// of k_ij > 0 at the new positions.
LOOSEHAIR_PAIR_KERNEL
void directionSlices(std::size_t slices, const std::uint32_t* __restrict rows, const SpringKernel& p,
                     const float* __restrict degree, const float* __restrict root_degree, const float* __restrict xi,
                     const float* __restrict yi, const float* __restrict zi, const float* __restrict tix,
                     const float* __restrict tiy, const float* __restrict tiz, const float* __restrict xj,
                     const float* __restrict yj, const float* __restrict zj, const float* __restrict weight,
                     const float* __restrict strength, const float* __restrict rest, const float* __restrict cos_rest,
                     float* __restrict sum_root, float* __restrict sum_tip, float* __restrict active,
                     float* __restrict ox_out, float* __restrict oy_out, float* __restrict oz_out) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const float inv_h = p.inv_h, norm_w = p.norm_w;
  std::size_t q0 = 0;
  for (std::size_t sl = 0; sl < slices; ++sl) {
    float sr[L], st[L], act[L], ox[L], oy[L], oz[L];
    for (std::size_t l = 0; l < L; ++l) sr[l] = st[l] = act[l] = ox[l] = oy[l] = oz[l] = 0.0f;
    const std::size_t o = sl * L;
    for (std::uint32_t r = 0; r < rows[sl]; ++r, q0 += L) {
      const float row = static_cast<float>(r);
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t q = q0 + l;
        const float dx = xj[q] - xi[o + l], dy = yj[q] - yi[o + l], dz = zj[q] - zi[o + l];
        const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float k_next = springCoefficient(strength[q], len, inv_h, norm_w);
        const float lk = rest[q] * k_next;
        const float on = weight[q] > 0.0f ? (len > 0.0f ? 1.0f : 0.0f) : 0.0f;
        const float inv_r = 1.0f / (on > 0.0f ? len : 1.0f);
        const float hx = dx * inv_r, hy = dy * inv_r, hz = dz * inv_r;
        // cos(theta) xhat + sin(theta) t_perp, t_perp the part of t_i normal to xhat
        const float ti_x = tix[o + l], ti_y = tiy[o + l], ti_z = tiz[o + l];
        const float along = ti_x * hx + ti_y * hy + ti_z * hz;
        const float px = ti_x - along * hx, py = ti_y - along * hy, pz = ti_z - along * hz;
        const float perp_len = std::sqrt(px * px + py * py + pz * pz);
        const float bent = perp_len > 1e-6f ? 1.0f : 0.0f;
        const float sp = restSine(cos_rest[q]) / (bent > 0.0f ? perp_len : 1.0f);
        const float sign = cos_rest[q] >= 0.0f ? 1.0f : -1.0f;
        const float tx = bent > 0.0f ? cos_rest[q] * hx + sp * px : sign * hx;
        const float ty = bent > 0.0f ? cos_rest[q] * hy + sp * py : sign * hy;
        const float tz = bent > 0.0f ? cos_rest[q] * hz + sp * pz : sign * hz;
        const float w = on > 0.0f ? weight[q] : 0.0f;
        const bool valid = row < degree[o + l];
        const bool root_side = row < root_degree[o + l];
        sr[l] = valid && root_side ? sr[l] + lk : sr[l];
        st[l] = valid && !root_side ? st[l] + lk : st[l];
        act[l] = valid && k_next > 0.0f ? act[l] + 1.0f : act[l];
        ox[l] = valid ? ox[l] + w * tx : ox[l];
        oy[l] = valid ? oy[l] + w * ty : oy[l];
        oz[l] = valid ? oz[l] + w * tz : oz[l];
      }
    }
    for (std::size_t l = 0; l < L; ++l) {
      sum_root[o + l] = sr[l];
      sum_tip[o + l] = st[l];
      active[o + l] = act[l];
      ox_out[o + l] = ox[l];
      oy_out[o + l] = oy[l];
      oz_out[o + l] = oz[l];
    }
  }
}

}  // namespace

DirectionPassResult updateDirections(float h1, const SlicedConnections& sl, std::span<const float> weight,
                                     std::span<const std::uint8_t> root, std::span<const glm::vec3> position,
                                     std::span<const glm::vec3> velocity, std::span<glm::vec3> direction,
                                     std::span<float> next_sum_root, std::span<float> next_sum_tip, int threads) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const glm::vec3* x = position.data();
  const glm::vec3* v = velocity.data();
  glm::vec3* dir = direction.data();
  const std::size_t n = position.size();
  assert(root.size() == n && velocity.size() == n && direction.size() == n);
  assert(next_sum_root.size() == n && next_sum_tip.size() == n);
  const ConnectionSlices& cs = sl.layout;
  assert(weight.size() == cs.entryCount());
  const SpringKernel terms{CubicKernel(h1)};
  enum { XJ, YJ, ZJ, kEntryColumns };
  enum { XI, YI, ZI, TX, TY, TZ, SR, ST, ACT, OX, OY, OZ, kLaneColumns };
  std::atomic<std::size_t> broken_sum{0};
  std::atomic<std::size_t> active_sum{0};
  parallel::run(threads, [&] {
    std::size_t broken_part = 0;
    std::size_t active_part = 0;
    SliceColumns& col = threadSliceColumns();
    forOwnWorkItems(cs, [&](const SliceRun& run) {
      const std::size_t q0 = run.q0, s0 = run.s0;
      col.reserve(run.entries, kEntryColumns, run.lanes, kLaneColumns);
      run.prefetchNext(cs.partner.data(), weight.data(), sl.strength.data(), sl.rest.data(), sl.cos_rest.data());
      gatherRows3(&x[0].x, cs.partner.data() + q0, run.entries, run.gatherAhead(n * sizeof(glm::vec3)), col.entry(XJ),
                  col.entry(YJ), col.entry(ZJ));
      const std::uint32_t* owner = cs.owner.data() + s0 * L;
      gatherRows3(&x[0].x, owner, run.lanes, 0, col.lane(XI), col.lane(YI), col.lane(ZI));
      gatherRows3(&dir[0].x, owner, run.lanes, 0, col.lane(TX), col.lane(TY), col.lane(TZ));
      directionSlices(run.s1 - s0, run.rows, terms, cs.degree.data() + s0 * L, cs.root_degree.data() + s0 * L,
                      col.lane(XI), col.lane(YI), col.lane(ZI), col.lane(TX), col.lane(TY), col.lane(TZ), col.entry(XJ),
                      col.entry(YJ), col.entry(ZJ), weight.data() + q0, sl.strength.data() + q0, sl.rest.data() + q0,
                      sl.cos_rest.data() + q0, col.lane(SR), col.lane(ST), col.lane(ACT), col.lane(OX), col.lane(OY),
                      col.lane(OZ));
      for (std::size_t l = 0; l < run.used; ++l) {
        const std::uint32_t i = owner[l];
        next_sum_root[i] = col.lane(SR)[l];
        next_sum_tip[i] = col.lane(ST)[l];
        active_part += static_cast<std::size_t>(col.lane(ACT)[l]);
        const glm::vec3 sum(col.lane(OX)[l], col.lane(OY)[l], col.lane(OZ)[l]);
        const float len = std::sqrt(glm::dot(sum, sum));
        if (!root[i] && len > 0.0f) dir[i] = sum * (1.0f / len);
        // Never go on silently with a broken state.
        const glm::vec3 pa = x[i], pb = v[i], pd = dir[i];
        const float probe = pa.x + pa.y + pa.z + pb.x + pb.y + pb.z + pd.x + pd.y + pd.z;
        broken_part += std::isfinite(probe) ? 0 : 1;
      }
    });
    broken_sum += broken_part;
    active_sum += active_part;
  });
  return {broken_sum.load(), active_sum.load()};
}

}  // namespace loosehair
