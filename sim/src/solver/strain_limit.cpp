// The strain limit (method.md §5, §9): strain_limit.hpp.
#include "solver/strain_limit.hpp"

#include "solver/connection_passes.hpp"

#include <glm/geometric.hpp>

#include <atomic>
#include <cassert>
#include <cmath>

namespace loosehair {

namespace {

// The strain-limit corrections of the connections of a run of slices (for
// Solver::limitStrain): a connection longer than (1 + max_strain) l_ij and
// still within the kernel's support pulls i towards j by its share
// w_i / (w_i + w_j) of the excess, scaled by the spring's looseness
// W(r)/W(l_ij) (so a connection that is letting go, hair splitting, is not
// pulled back hard). Each lane sums, in its list's order, the shift and
// the number of acting connections. 1/W(l_ij) and the shares are computed
// here, as the constructor would (the same bits), rather than streamed
// from memory: the pass runs twice a step over every connection entry.
struct StrainTerms {
  float inv_h, norm_w;  // kernel W(r, h1)
  float support2, max_len_scale;
};
LOOSEHAIR_PAIR_KERNEL
void strainSlices(std::size_t slices, const std::uint32_t* __restrict rows, const StrainTerms& p,
                  const float* __restrict degree, const float* __restrict xi, const float* __restrict yi,
                  const float* __restrict zi, const float* __restrict wi, const float* __restrict xj,
                  const float* __restrict yj, const float* __restrict zj, const float* __restrict wj,
                  const float* __restrict rest, float* __restrict shift_x, float* __restrict shift_y,
                  float* __restrict shift_z, float* __restrict acting) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const float inv_h = p.inv_h, norm_w = p.norm_w, support2 = p.support2, scale = p.max_len_scale;
  std::size_t q0 = 0;  // first entry of the slice's rows
  for (std::size_t sl = 0; sl < slices; ++sl) {
    float sx[L], sy[L], sz[L], act[L];
    for (std::size_t l = 0; l < L; ++l) sx[l] = sy[l] = sz[l] = act[l] = 0.0f;
    const std::size_t o = sl * L;
    for (std::uint32_t r = 0; r < rows[sl]; ++r, q0 += L) {
      const float row = static_cast<float>(r);
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t q = q0 + l;
        const float dx = xj[q] - xi[o + l], dy = yj[q] - yi[o + l], dz = zj[q] - zi[o + l];
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float limit = scale * rest[q];
        // slack connections and connections beyond the support stay free
        const float on = r2 > limit * limit ? (r2 < support2 ? 1.0f : 0.0f) : 0.0f;
        const float len = std::sqrt(r2);
        const float inv_rest_w = 1.0f / cubicW(rest[q], inv_h, norm_w);
        const float looseness = std::min(1.0f, cubicW(len, inv_h, norm_w) * inv_rest_w);
        const float w_i = wi[o + l], share = w_i / (w_i + wj[q]);  // w: inverse mass
        const float coef = on > 0.0f ? looseness * (len - limit) * share / len : 0.0f;
        const bool valid = row < degree[o + l];  // not a padding entry
        sx[l] = valid ? sx[l] + coef * dx : sx[l];
        sy[l] = valid ? sy[l] + coef * dy : sy[l];
        sz[l] = valid ? sz[l] + coef * dz : sz[l];
        act[l] = valid ? act[l] + on : act[l];
      }
    }
    for (std::size_t l = 0; l < L; ++l) {
      shift_x[o + l] = sx[l];
      shift_y[o + l] = sy[l];
      shift_z[o + l] = sz[l];
      acting[o + l] = act[l];
    }
  }
}

}  // namespace

std::size_t limitStrain(const StrainLimitSettings& settings, const SlicedConnections& sl,
                        std::span<const std::uint8_t> root, std::vector<glm::vec3>& position,
                        std::vector<glm::vec4> (&records)[2], std::vector<glm::vec3>& scratch, int threads) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  std::size_t limited = 0;
  if (settings.rounds <= 0) return 0;
  const CubicKernel k1(settings.h1);
  const StrainTerms terms{1.0f / k1.h(), k1.W(0.0f) / 4.0f, k1.support2(), 1.0f + settings.max_strain};
  const ConnectionSlices& cs = sl.layout;
  enum { XJ, YJ, ZJ, WJ, kEntryColumns };
  enum { XI, YI, ZI, WI, SX, SY, SZ, ACT, kLaneColumns };
  const std::size_t n = position.size();
  assert(records[0].size() == n && root.size() == n);
  records[1].resize(n);
  scratch.resize(n);
  for (int it = 0; it < settings.rounds; ++it) {
    const glm::vec3* x = position.data();
    glm::vec3* out = scratch.data();
    const glm::vec4* rec_in4 = records[it & 1].data();
    const float* rec_in = &rec_in4[0].x;
    glm::vec4* rec_out = records[(it + 1) & 1].data();
    std::size_t count = 0;
    std::atomic<std::size_t> count_sum{0};
    parallel::run(threads, [&] {
      std::size_t count_part = 0;
      SliceColumns& col = threadSliceColumns();
      forOwnWorkItems(cs, [&](const SliceRun& run) {
        const std::size_t q0 = run.q0, s0 = run.s0;
        col.reserve(run.entries, kEntryColumns, run.lanes, kLaneColumns);
        const std::uint32_t* owner = cs.owner.data() + s0 * L;
        run.prefetchNext(cs.partner.data(), sl.rest.data());
        gatherRecords(rec_in, cs.partner.data() + q0, run.entries, run.gatherAhead(n * sizeof(glm::vec4)),
                      col.entry(XJ), col.entry(YJ), col.entry(ZJ), col.entry(WJ));
        gatherRecords(rec_in, owner, run.lanes, 0, col.lane(XI), col.lane(YI), col.lane(ZI), col.lane(WI));
        strainSlices(run.s1 - s0, run.rows, terms, cs.degree.data() + s0 * L, col.lane(XI), col.lane(YI), col.lane(ZI),
                     col.lane(WI), col.entry(XJ), col.entry(YJ), col.entry(ZJ), col.entry(WJ), sl.rest.data() + q0,
                     col.lane(SX), col.lane(SY), col.lane(SZ), col.lane(ACT));
        for (std::size_t l = 0; l < run.used; ++l) {
          const std::uint32_t i = owner[l];
          out[i] = x[i];
          const float active = col.lane(ACT)[l];
          if (!root[i] && active > 0.0f) {
            out[i] = x[i] + glm::vec3(col.lane(SX)[l], col.lane(SY)[l], col.lane(SZ)[l]) / active;
            ++count_part;
          }
          rec_out[i] = glm::vec4(out[i], rec_in4[i].w);
        }
      });
      count_sum += count_part;
    });
    count = count_sum.load();
    position.swap(scratch);
    if (it == 0) limited = count;
    if (count == 0) break;
  }
  return limited;
}

}  // namespace loosehair
