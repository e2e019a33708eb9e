// Solver speed on the sphere-hang scene at growing particle counts, with 1
// and 2 threads. Figures are particle-steps per second (items/s).
//
//   build/release/benchmarks/loosehair_bench --benchmark_filter=Step
//
// Each benchmark family grows its own scene per particle count and steps it
// 20 times first; every benchmark then starts from that state (and one
// untimed step after it), and the
// Density and Step families time the same steps for 1 and 2 threads
// (runCycles). For comparisons on a shared machine, run the repetitions
// interleaved:
//
//   --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
#include "loosehair/loosehair.hpp"
#include "solver/neighbor_grid.hpp"
#include "util/parallel.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

namespace {

using namespace loosehair;

enum class Family { Neighbors, Density, Step };

struct Cached {
  std::unique_ptr<Solver> solver;
  Particles after_warmup;  // the state after the first 20 steps
};

// The scene at `particles`, back at its state after 20 steps and then one
// step on (hanging hair bunches as it falls, so a step's cost depends on how
// long it has run: every call, the first included, leaves the same state,
// so 1 and 2 threads time the same steps).
Solver& sceneWith(int particles, Family family) {
  static std::map<std::pair<int, Family>, Cached> cache;
  auto& slot = cache[{particles, family}];
  if (!slot.solver) {
    SceneDesc scene = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/sphere-hang.json");
    scene.hair.particles = particles;
    slot.solver = std::make_unique<Solver>(buildSolver(scene));
    slot.solver->advance(20);  // leave the exact initial state
    slot.after_warmup = slot.solver->particles();
  }
  const Particles& p = slot.after_warmup;
  slot.solver->setKinematicState(p.position, p.velocity, p.direction);
  slot.solver->step();  // the step after a reset absorbs its corrections: not timed
  return *slot.solver;
}

constexpr int kCounts[] = {2000, 10000, 50000, 100000, 200000};

// Besides the usual aggregates, repetitions report their lowest mean
// ("min"): on a shared machine other tenants only ever add time.
double lowest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void counts(benchmark::internal::Benchmark* b) {
  for (int n : kCounts)
    for (int threads : {1, 2}) b->Args({n, threads});
  b->ArgNames({"particles", "threads"});
  b->Unit(benchmark::kMillisecond);
  b->ComputeStatistics("min", lowest);
}

void BM_NeighborSearch(benchmark::State& state) {
  Solver& solver = sceneWith(static_cast<int>(state.range(0)), Family::Neighbors);
  NeighborGrid grid;
  const auto& x = solver.particles().position;
  for (auto _ : state) {
    // as the solver searches: lists of positions in the search order
    grid.build(x, 2.0f * solver.params().h2, static_cast<int>(state.range(1)), NeighborGrid::ListIndex::SearchOrder);
    benchmark::DoNotOptimize(grid.pairCount());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
  state.counters["dense"] = grid.usedDenseLayout() ? 1 : 0;
  state.counters["pairs/particle"] = static_cast<double>(grid.pairCount()) / static_cast<double>(x.size());
}
BENCHMARK(BM_NeighborSearch)->Apply(counts);

// The machine's memory bandwidth with 1 and 2 threads, for reading the
// solver's figures: reading (and, in the copy, also writing) 256 MB arrays,
// far larger than any cache, as the large-N stages stream their per-entry
// data. Where two threads read DRAM barely faster than one, the part of a
// step that waits on DRAM cannot gain 2x from the second thread.
std::vector<float>& streamArray(int which) {
  static std::vector<float> arrays[2];
  auto& a = arrays[which];
  if (a.empty()) a.assign(std::size_t{64} << 20, 1.0f);  // 256 MB
  return a;
}

void BM_MemoryRead(benchmark::State& state) {
  const std::vector<float>& a = streamArray(0);
  const auto n = static_cast<std::int64_t>(a.size());
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    float totals[2] = {};
    parallel::run(threads, [&] {
      float acc[16] = {};  // 16 independent sums: the loop vectorises without reassociation
      const auto [first, last] = parallel::share(static_cast<std::size_t>(n / 16));
      for (std::size_t g = first; g < last; ++g)
        for (std::size_t l = 0; l < 16; ++l) acc[l] += a[16 * g + l];
      for (float v : acc) totals[parallel::threadIndex()] += v;
    });
    benchmark::DoNotOptimize(totals);
  }
  state.SetBytesProcessed(state.iterations() * n * static_cast<std::int64_t>(sizeof(float)));
}
BENCHMARK(BM_MemoryRead)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_MemoryCopy(benchmark::State& state) {
  const std::vector<float>& a = streamArray(0);
  std::vector<float>& b = streamArray(1);
  const auto n = static_cast<std::int64_t>(a.size());
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    parallel::forEach(threads, static_cast<std::size_t>(n), [&](std::size_t i) { b[i] = a[i]; });
    benchmark::ClobberMemory();
  }
  // bytes read plus bytes written
  state.SetBytesProcessed(state.iterations() * 2 * n * static_cast<std::int64_t>(sizeof(float)));
}
BENCHMARK(BM_MemoryCopy)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// Steps for the Density and Step families, in cycles: back to the state
// after 20 steps, one untimed step (the step after a reset absorbs its
// corrections), then kStepCycle timed steps. A run is a fixed whole number
// of cycles for 1 and 2 threads alike, so both time exactly the same steps:
// with a free iteration count the faster run would time later steps, and
// the hair bunches as it falls (more pairs a particle).
constexpr int kStepCycle = 5;
int stepsFor(int particles) {
  // about 4 M particle-steps a run: 4 cycles at 200k, 400 at 2k
  const int cycles = std::max(4, 4'000'000 / (kStepCycle * particles));
  return cycles * kStepCycle;
}

// The steps of one run; `paused` brackets the resets, which are not timed.
template <class Paused>
void runCycles(benchmark::State& state, Family family, Paused&& paused,
               void (*timed)(benchmark::State&, const StageTimes&), StageTimes& sum) {
  const int particles = static_cast<int>(state.range(0));
  Solver& solver = sceneWith(particles, family);
  solver.setThreadCount(static_cast<int>(state.range(1)));
  int in_cycle = 0;
  for (auto _ : state) {
    if (in_cycle == kStepCycle) {
      paused([&] { sceneWith(particles, family); });  // reset, and the untimed step
      in_cycle = 0;
    }
    solver.step();
    ++in_cycle;
    timed(state, solver.stats().last);
    sum += solver.stats().last;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(particles));
}

// The solver's density stage, timed by the solver itself inside full steps.
void BM_Density(benchmark::State& state) {
  StageTimes sum;
  runCycles(
      state, Family::Density, [](auto&& reset) { reset(); },
      [](benchmark::State& s, const StageTimes& t) { s.SetIterationTime(t.density); }, sum);
}

// Full steps, with the mean stage times of the timed steps as counters.
void BM_Step(benchmark::State& state) {
  StageTimes sum;
  runCycles(
      state, Family::Step,
      [&state](auto&& reset) {
        state.PauseTiming();
        reset();
        state.ResumeTiming();
      },
      [](benchmark::State&, const StageTimes&) {}, sum);
  const double ms = 1e3 / static_cast<double>(state.iterations());
  state.counters["neighbors_ms"] = sum.neighbors * ms;
  state.counters["density_ms"] = sum.density * ms;
  state.counters["springs_ms"] = sum.springs * ms;
  state.counters["hairhair_ms"] = sum.hair_hair * ms;
  state.counters["strain_ms"] = sum.strain_limit * ms;
  state.counters["tethers_ms"] = sum.tethers * ms;
  state.counters["bodies_ms"] = sum.body_contacts * ms;
  state.counters["ext_int_ms"] = (sum.external + sum.integrate) * ms;
  state.counters["directions_ms"] = sum.directions * ms;
}

// Registered per particle count for the fixed iteration counts.
benchmark::internal::Benchmark* cycled(const char* name, void (*fn)(benchmark::State&), int n, int threads) {
  return benchmark::RegisterBenchmark(name, fn)
      ->Args({n, threads})
      ->ArgNames({"particles", "threads"})
      ->Iterations(stepsFor(n))
      ->Unit(benchmark::kMillisecond)
      ->ComputeStatistics("min", lowest);
}
const bool kCycledRegistered = [] {
  for (int n : kCounts)
    for (int threads : {1, 2}) cycled("BM_Density", BM_Density, n, threads)->UseManualTime();
  for (int n : kCounts)
    for (int threads : {1, 2}) cycled("BM_Step", BM_Step, n, threads);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
