// Solver speed on the sphere-hang scene at growing particle counts, with 1
// and 2 threads. Figures are particle-steps per second (items/s).
//
//   build/release/benchmarks/loosehair_bench --benchmark_filter=Step
//
// Each benchmark family grows its own scene per particle count and steps it
// 20 times first; every benchmark then starts from that state.
#include "loosehair/loosehair.hpp"
#include "neighbor_grid.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

namespace {

using namespace loosehair;

enum class Family { Neighbors, Density, Step };

struct Cached {
  std::unique_ptr<Solver> solver;
  Particles after_warmup;  // the state after the first 20 steps
};

// The scene at `particles`, back at its state after 20 steps (hanging hair
// bunches as it falls, so a step's cost depends on how long it has run:
// every benchmark starts from the same state, so 1 and 2 threads time the
// same steps).
Solver& sceneWith(int particles, Family family) {
  static std::map<std::pair<int, Family>, Cached> cache;
  auto& slot = cache[{particles, family}];
  if (!slot.solver) {
    SceneDesc scene = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/sphere-hang.json");
    scene.hair.particles = particles;
    slot.solver = std::make_unique<Solver>(buildSolver(scene));
    slot.solver->advance(20);  // leave the exact initial state
    slot.after_warmup = slot.solver->particles();
  } else {
    const Particles& p = slot.after_warmup;
    slot.solver->setKinematicState(p.position, p.velocity, p.direction);
    slot.solver->step();  // the step after a reset absorbs its corrections: not timed
  }
  return *slot.solver;
}

void counts(benchmark::internal::Benchmark* b) {
  for (int n : {2000, 10000, 50000, 100000, 200000})
    for (int threads : {1, 2}) b->Args({n, threads});
  b->ArgNames({"particles", "threads"});
  b->Unit(benchmark::kMillisecond);
}

void BM_NeighborSearch(benchmark::State& state) {
  Solver& solver = sceneWith(static_cast<int>(state.range(0)), Family::Neighbors);
  NeighborGrid grid;
  const auto& x = solver.particles().position;
  for (auto _ : state) {
    grid.build(x, 2.0f * solver.params().h2, static_cast<int>(state.range(1)));
    benchmark::DoNotOptimize(grid.pairCount());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
  state.counters["dense"] = grid.usedDenseLayout() ? 1 : 0;
  state.counters["pairs/particle"] =
      static_cast<double>(grid.pairCount()) / static_cast<double>(x.size());
}
BENCHMARK(BM_NeighborSearch)->Apply(counts);

// One solver stage, timed by the solver itself inside full steps.
template <double StageTimes::*Stage>
void BM_Stage(benchmark::State& state) {
  Solver& solver = sceneWith(static_cast<int>(state.range(0)), Family::Density);
  solver.setThreadCount(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    solver.step();
    state.SetIterationTime(solver.stats().last.*Stage);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(solver.particles().size()));
}
BENCHMARK(BM_Stage<&StageTimes::density>)->Name("BM_Density")->Apply(counts)->UseManualTime();

void BM_Step(benchmark::State& state) {
  Solver& solver = sceneWith(static_cast<int>(state.range(0)), Family::Step);
  solver.setThreadCount(static_cast<int>(state.range(1)));
  for (auto _ : state) solver.step();
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(solver.particles().size()));
  const StageTimes& s = solver.stats().last;
  state.counters["neighbors_ms"] = s.neighbors * 1e3;
  state.counters["springs_ms"] = s.springs * 1e3;
  state.counters["hairhair_ms"] = s.hair_hair * 1e3;
  state.counters["strain_ms"] = s.strain_limit * 1e3;
  state.counters["density_ms"] = s.density * 1e3;
  state.counters["ext_int_ms"] = (s.external + s.integrate) * 1e3;
  state.counters["directions_ms"] = s.directions * 1e3;
}
BENCHMARK(BM_Step)->Apply(counts);

}  // namespace

BENCHMARK_MAIN();
