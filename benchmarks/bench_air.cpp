// The air grid's two costs (sim/src/wind/air_grid.hpp) on a box the size of the
// wind scene's (0.6 x 0.65 x 0.5 m, 3 cm cells: 7,480 cells) with 6,000
// hair particles in a block inside it, with 1 and 2 threads:
//
//   build/release/benchmarks/loosehair_bench_air
//
// - Exchange: one hair step's drag exchange (AirGrid::exchangeDrag), every
//   run from the same air (the state is restored untimed, so the hair does
//   not slowly stop the air and the figures stay comparable).
// - Advance: one air step (viscosity, advection, boundaries, pressure
//   projection) with a ball in the box, from the same state each run.
#include "wind/air_grid.hpp"
#include "util/random.hpp"

#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>

#include <vector>

namespace {

using namespace loosehair;

WindParams windBox() {
  WindParams w;
  w.model = AirModel::Grid;
  w.direction = glm::vec3(1, 0, 0);
  w.speed = 3.0f;
  w.box_center = glm::vec3(0);
  w.box_size = glm::vec3(0.6f, 0.65f, 0.5f);
  w.spacing = 0.03f;
  return w;
}

struct Hair {
  std::vector<glm::vec3> x, v, f;
  std::vector<float> m;
  std::vector<std::uint8_t> root;
};

Hair hairBlock(std::size_t n) {
  Hair h;
  Random rng(3);
  for (std::size_t i = 0; i < n; ++i) {
    const float x = static_cast<float>(rng.uniform(-0.1, 0.1));
    const float y = static_cast<float>(rng.uniform(-0.2, 0.1));
    const float z = static_cast<float>(rng.uniform(-0.1, 0.1));
    h.x.emplace_back(x, y, z);
    h.v.emplace_back(static_cast<float>(rng.uniform(-0.3, 0.3)), 0.0f, 0.0f);
  }
  h.f.assign(n, glm::vec3(0));
  h.m.assign(n, 0.08f / 6000.0f);
  h.root.assign(n, 0);
  return h;
}

void BM_AirExchange(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  AirGrid air(windBox());
  air.fill(0.0, {});
  const AirGrid::State start = air.state();
  Hair h = hairBlock(6000);
  const HeadKinematics still;
  for (auto _ : state) {
    state.PauseTiming();
    air.restore(start);
    state.ResumeTiming();
    air.exchangeDrag(still, h.x, h.v, h.m, h.root, h.f, 1.0f / 90.0f, threads);
  }
  benchmark::DoNotOptimize(h.f.data());
  state.SetItemsProcessed(state.iterations() * 6000);
}
BENCHMARK(BM_AirExchange)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_AirAdvance(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  AirGrid air(windBox());
  const AirGrid::BodySampler ball = [](const glm::vec3* x, std::size_t n, float* phi, glm::vec3* v) {
    for (std::size_t k = 0; k < n; ++k) {
      phi[k] = glm::length(x[k] - glm::vec3(-0.05f, 0.0f, 0.0f)) - 0.1f;
      v[k] = glm::vec3(0);
    }
  };
  air.fill(0.0, ball);
  // a few steps in, so the flow around the ball has formed
  for (int s = 1; s <= 10; ++s) {
    (void)air.due(0.025f);
    air.advance(0.025 * s, {}, threads);
  }
  const AirGrid::State start = air.state();
  for (auto _ : state) {
    state.PauseTiming();
    air.restore(start);
    (void)air.due(0.025f);
    state.ResumeTiming();
    air.advance(0.275, {}, threads);
  }
  state.counters["cg_iterations"] = air.lastIterations();
}
BENCHMARK(BM_AirAdvance)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
