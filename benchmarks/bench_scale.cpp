// Real time at scale (issue "real time at scale"): simulated seconds per
// wall second of the bundled hang, head-shake and wind scenes with their
// particle count changed, the old solver (explicit springs, weakly
// compressible air particles) against the new one (implicit springs, the
// air on a grid), two threads, in one run; for wind also the implicit
// springs with the projected air particles (solver 2); for hang and
// head-shake also the defaults with the spring solve stopped at its old
// tolerance, 5e-3 (solver 3: what the tighter default costs).
//
//   build/release/benchmarks/loosehair_bench_scale
//
// Each case builds the scene (substeps "auto": the explicit solver takes as
// many as its stable step needs, the implicit one as many as accuracy
// needs), runs 1 s untimed so the hair lies on the head, then times whole
// frames. Counters: substeps a frame, ms a step, simulated s per wall s.
#include "loosehair/loosehair.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <string>
#include <tuple>
#include <memory>

namespace {

using namespace loosehair;

struct Case {
  std::unique_ptr<Solver> solver;
  int substeps = 0;
};

const char* const kScenes[] = {"hang", "head-shake", "wind"};

// solver 0: explicit springs, weakly compressible air particles; 1: the
// defaults (implicit springs, air grid); 2: implicit springs, projected air
// particles; 3: the defaults with implicit_tolerance 5e-3
Case& sceneWith(int which, int particles, int solver) {
  static std::map<std::tuple<int, int, int>, Case> cache;
  Case& c = cache[{which, particles, solver}];
  if (!c.solver) {
    SceneDesc scene = loadScene(std::string(LOOSEHAIR_SOURCE_DIR "/data/scenes/") + kScenes[which] + ".json");
    scene.hair.particles = particles;
    scene.sim.implicit_springs = solver != 0;
    if (scene.has_wind) {
      scene.wind.model = solver == 1 ? AirModel::Grid : AirModel::Particles;
      scene.wind.projection_iterations = solver == 0 ? 0 : WindParams{}.projection_iterations;
    }
    if (solver == 3) scene.sim.implicit_tolerance = 5e-3f;
    scene.sim.threads = 2;
    scene.substeps = 0;
    scene.limits.max_substeps = 1000;
    BuildReport report;
    c.solver = std::make_unique<Solver>(buildSolver(scene, &report));
    c.substeps = report.substeps;
    c.solver->advance(30 * c.substeps);
  }
  return c;
}

void BM_Frame(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int particles = static_cast<int>(state.range(1));
  const int solver = static_cast<int>(state.range(2));
  state.SetLabel(kScenes[which]);
  Case& c = sceneWith(which, particles, solver);
  double wall = 0;
  std::int64_t frames = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    c.solver->advance(c.substeps);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++frames;
  }
  state.counters["substeps"] = c.substeps;
  state.counters["step_ms"] = wall / static_cast<double>(frames * c.substeps) * 1e3;
  state.counters["sim_s_per_wall_s"] = static_cast<double>(frames) / 30.0 / wall;
}

// scene 0 hang, 1 head-shake, 2 wind; solver 0 = the old solver, 1 = the
// defaults, 2 = implicit springs with the projected air particles, 3 = the
// defaults with the spring solve's old tolerance
BENCHMARK(BM_Frame)
    ->ArgNames({"scene", "particles", "solver"})
    ->ArgsProduct({{0, 1}, {6000, 20000, 50000, 100000}, {0, 1}})
    ->ArgsProduct({{0, 1}, {6000, 20000}, {3}})
    ->ArgsProduct({{2}, {6000}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
