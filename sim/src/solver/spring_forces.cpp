// The loose springs (method.md §3.2): the side factors of eqs. 10-14 and the
// damped spring forces.
#include "solver/spring_forces.hpp"

#include "solver/solver_internal.hpp"

namespace loosehair {

// ---- stage 3a: loose spring coefficients, eqs. 7, 10-14 ---------------------
void resizeSpringScratch(SpringScratch& s, std::size_t n, const ConnectionSet& connections,
                         const SlicedConnections& sliced, bool keep_k) {
  const std::size_t m = connections.entryCount();
  s.sum_root.assign(n, 0.0f);
  s.sum_tip.assign(n, 0.0f);
  s.factor_root.assign(n, 0.0f);
  s.factor_tip.assign(n, 0.0f);
  s.weight.assign(sliced.layout.entryCount(), 0.0f);  // in the slice layout
  s.unit_x.assign(sliced.layout.entryCount(), 0.0f);
  s.unit_y.assign(sliced.layout.entryCount(), 0.0f);
  s.unit_z.assign(sliced.layout.entryCount(), 0.0f);
  s.pull.assign(n, glm::vec3(0.0f));
  s.k.assign(keep_k ? m : 0, 0.0f);
  s.sums_current = false;
}

void computeSpringFactors(const SpringSettings& settings, const ConnectionSet& connections, const SpringParticles& p,
                          SpringScratch& s, int threads) {
  const CubicKernel k1(settings.h1);
  const auto& x = p.position;
  const auto& c = connections;
  const double young = settings.youngs_modulus;
  const float clamp = settings.stiffness_clamp;
  const Index n = static_cast<Index>(x.size());
  std::size_t clamped = 0, active = 0;
  const bool measure = !s.sums_current;  // else the direction pass measured (and counted)
  const bool keep_k = !s.k.empty();
  const SpringKernel sk(k1);
  const auto& v = p.velocity;
  const auto& root = p.is_root;
  const auto& cross_section = p.cross_section;
  const auto& rest_factor_root = p.rest_factor_root;
  const auto& rest_factor_tip = p.rest_factor_tip;
  s.spring_records.resize(2 * x.size());
  glm::vec4* rec = s.spring_records.data();
  std::atomic<std::size_t> clamped_sum{0};
  std::atomic<std::size_t> active_sum{0};
  parallel::run(threads, [&] {
    std::size_t clamped_part = 0;
    std::size_t active_part = 0;
    const auto [first, last] = parallel::share(static_cast<std::size_t>(n));
    for (std::size_t i = first; i < last; ++i) {
      if (measure) {
        // k_ij and |x_ij| of every entry, and the two sides' sums of l_ij k_ij
        const glm::vec3 xi = x[i];
        float sums[2] = {0.0f, 0.0f};
        const std::uint32_t bounds[3] = {c.begin(i), c.tipBegin(i), c.end(i)};
        for (int side = 0; side < 2; ++side) {
          float sum = 0.0f;
          for (std::uint32_t e = bounds[side]; e < bounds[side + 1]; ++e) {
            const glm::vec3 d = x[c.partner[e]] - xi;
            const float r = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            const float k = springCoefficient(c.strength[e], r, sk.inv_h, sk.norm_w);
            if (keep_k) s.k[e] = k;
            active_part += k > 0.0f ? 1 : 0;
            sum += c.rest_length[e] * k;
          }
          sums[side] = sum;
        }
        s.sum_root[i] = sums[0];
        s.sum_tip[i] = sums[1];
      }
      const double ea = young * cross_section[i];
      auto factor = [&](float sum, float rest) {
        if (!(sum > 0.0f)) return 0.0f;
        const float a = static_cast<float>(ea / sum), limit = clamp * rest;
        if (a > limit) {
          ++clamped_part;
          return limit;
        }
        return a;
      };
      s.factor_root[i] = factor(s.sum_root[i], rest_factor_root[i]);
      s.factor_tip[i] = factor(s.sum_tip[i], rest_factor_tip[i]);
      // the spring pass's records of i (accumulateSpringForces), a root's
      // factors replaced by the marker
      const bool r = root[i] != 0;
      rec[2 * i] = glm::vec4(x[i], r ? kRootFactor : s.factor_root[i]);
      rec[2 * i + 1] = glm::vec4(v[i], r ? kRootFactor : s.factor_tip[i]);
    }
    clamped_sum += clamped_part;
    active_sum += active_part;
  });
  clamped = clamped_sum.load();
  active = active_sum.load();

  s.clamped = clamped;
  if (measure) s.active_entries = active;
  s.sums_current = false;  // the step moves the particles
}

// ---- stage 3b: damped spring forces (method.md §3.2) ----------------------------
namespace {

// The damped spring forces of the connections of a run of slices:
// alpha_ij k_ij (|x_ij| - l_ij + gamma (v_ij . n)) n, n = x_ij / |x_ij|,
// summed per lane in list order; and alpha_ij k_ij per entry, kept for the
// direction pass; for the implicit solve (implicit_springs.hpp), n per
// entry and alpha_ij k_ij (v_ij . n) n summed per lane as well. alpha_ij
// (eq. 14) from the owner's factor on the entry's side and the partner's on
// the other side (gathered); roots are known by their factors' kRootFactor.
struct SpringTerms {
  float inv_h, norm_w;  // kernel W(r, h1)
  float gamma;          // spring damping (s)
};
LOOSEHAIR_PAIR_KERNEL
void springSlices(std::size_t slices, const std::uint32_t* __restrict rows, const SpringTerms& p,
                  const float* __restrict degree, const float* __restrict root_degree, const float* __restrict xi,
                  const float* __restrict yi, const float* __restrict zi, const float* __restrict vxi,
                  const float* __restrict vyi, const float* __restrict vzi, const float* __restrict own_root,
                  const float* __restrict own_tip, const float* __restrict xj, const float* __restrict yj,
                  const float* __restrict zj, const float* __restrict vxj, const float* __restrict vyj,
                  const float* __restrict vzj, const float* __restrict frj, const float* __restrict ftj,
                  const float* __restrict strength, const float* __restrict rest, float* __restrict weight,
                  float* __restrict nx_out, float* __restrict ny_out, float* __restrict nz_out,
                  float* __restrict fx_out, float* __restrict fy_out, float* __restrict fz_out,
                  float* __restrict px_out, float* __restrict py_out, float* __restrict pz_out) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const float inv_h = p.inv_h, norm_w = p.norm_w, gamma = p.gamma;
  std::size_t q0 = 0;
  for (std::size_t sl = 0; sl < slices; ++sl) {
    float fx[L], fy[L], fz[L], px[L], py[L], pz[L];
    for (std::size_t l = 0; l < L; ++l) fx[l] = fy[l] = fz[l] = px[l] = py[l] = pz[l] = 0.0f;
    const std::size_t o = sl * L;
    for (std::uint32_t r = 0; r < rows[sl]; ++r, q0 += L) {
      const float row = static_cast<float>(r);
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t q = q0 + l;
        const float dx = xj[q] - xi[o + l], dy = yj[q] - yi[o + l], dz = zj[q] - zi[o + l];
        const float ux = vxj[q] - vxi[o + l], uy = vyj[q] - vyi[o + l], uz = vzj[q] - vzi[o + l];
        // root side: own factor a_r,i and the partner's a_t,j; tip side the
        // reverse (all four loaded, then selected: the loop vectorises)
        const float own_r = own_root[o + l], own_t = own_tip[o + l], fr_j = frj[q], ft_j = ftj[q];
        const bool root_side = row < root_degree[o + l];
        const float own = root_side ? own_r : own_t;
        const float other = root_side ? ft_j : fr_j;
        const float alpha = pairFactor(own, other, ownWeight(own_r < 0.0f, fr_j < 0.0f));
        const float len = std::sqrt(dx * dx + dy * dy + dz * dz);  // |x_ij|
        const float w = alpha * springCoefficient(strength[q], len, inv_h, norm_w);
        const float inv_r = len > 0.0f ? 1.0f / len : 0.0f;
        const float nx = dx * inv_r, ny = dy * inv_r, nz = dz * inv_r;
        const float closing = ux * nx + uy * ny + uz * nz;
        const float f = w * ((len - rest[q]) + gamma * closing);
        const bool valid = row < degree[o + l];
        weight[q] = w;
        fx[l] = valid ? fx[l] + f * nx : fx[l];
        fy[l] = valid ? fy[l] + f * ny : fy[l];
        fz[l] = valid ? fz[l] + f * nz : fz[l];
        // the implicit solve's n, by division (its own rounding, kept)
        const float mx = len > 0.0f ? dx / len : 0.0f, my = len > 0.0f ? dy / len : 0.0f,
                    mz = len > 0.0f ? dz / len : 0.0f;
        nx_out[q] = mx;
        ny_out[q] = my;
        nz_out[q] = mz;
        const float g = w * (mx * ux + my * uy + mz * uz);
        px[l] = valid ? px[l] + g * mx : px[l];
        py[l] = valid ? py[l] + g * my : py[l];
        pz[l] = valid ? pz[l] + g * mz : pz[l];
      }
    }
    for (std::size_t l = 0; l < L; ++l) {
      fx_out[o + l] = fx[l];
      fy_out[o + l] = fy[l];
      fz_out[o + l] = fz[l];
      px_out[o + l] = px[l];
      py_out[o + l] = py[l];
      pz_out[o + l] = pz[l];
    }
  }
}

}  // namespace

void accumulateSpringForces(const SpringSettings& settings, const SlicedConnections& sl, std::size_t n,
                            SpringScratch& s, std::span<glm::vec3> force, int threads) {
  constexpr std::size_t L = ConnectionSlices::kLanes;
  const ConnectionSlices& cs = sl.layout;
  const CubicKernel k1(settings.h1);
  const SpringKernel sk(k1);
  const SpringTerms terms{sk.inv_h, sk.norm_w, settings.damping};
  // the first 8 columns of each: the two records' 4 + 4 floats (gatherRecordPairs)
  enum { XJ, YJ, ZJ, FRJ, VXJ, VYJ, VZJ, FTJ, kEntryColumns };
  enum { XI, YI, ZI, OWN_R, VXI, VYI, VZI, OWN_T, FX, FY, FZ, PX, PY, PZ, kLaneColumns };
  assert(s.spring_records.size() == 2 * n);  // made by computeSpringFactors
  const float* records = &s.spring_records[0].x;
  parallel::run(threads, [&] {
    SliceColumns& col = threadSliceColumns();
    forOwnWorkItems(cs, [&](const SliceRun& run) {
      const std::size_t q0 = run.q0, s0 = run.s0;
      col.reserve(run.entries, kEntryColumns, run.lanes, kLaneColumns);
      const std::uint32_t* partner = cs.partner.data() + q0;
      const std::uint32_t* owner = cs.owner.data() + s0 * L;
      run.prefetchNext(cs.partner.data(), sl.strength.data(), sl.rest.data(), s.weight.data());
      // (x, a_r) and (v, a_t) of the partners and of the owners
      gatherRecordPairs(records, partner, run.entries, run.gatherAhead(n * 2 * sizeof(glm::vec4)), col.entry(XJ),
                        col.entryStride());
      gatherRecordPairs(records, owner, run.lanes, 0, col.lane(XI), col.laneStride());
      springSlices(run.s1 - s0, run.rows, terms, cs.degree.data() + s0 * L, cs.root_degree.data() + s0 * L,
                   col.lane(XI), col.lane(YI), col.lane(ZI), col.lane(VXI), col.lane(VYI), col.lane(VZI),
                   col.lane(OWN_R), col.lane(OWN_T), col.entry(XJ), col.entry(YJ), col.entry(ZJ), col.entry(VXJ),
                   col.entry(VYJ), col.entry(VZJ), col.entry(FRJ), col.entry(FTJ), sl.strength.data() + q0,
                   sl.rest.data() + q0, s.weight.data() + q0, s.unit_x.data() + q0, s.unit_y.data() + q0,
                   s.unit_z.data() + q0, col.lane(FX), col.lane(FY), col.lane(FZ), col.lane(PX), col.lane(PY),
                   col.lane(PZ));
      for (std::size_t l = 0; l < run.used; ++l) {
        force[owner[l]] = glm::vec3(col.lane(FX)[l], col.lane(FY)[l], col.lane(FZ)[l]);
        s.pull[owner[l]] = glm::vec3(col.lane(PX)[l], col.lane(PY)[l], col.lane(PZ)[l]);
      }
    });
  });
}

}  // namespace loosehair
