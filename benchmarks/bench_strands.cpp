// Carrying render strands with the particles (issue "strands"): the bundled
// hang scene settled for a second, then StrandField::deform with and
// without the push out of the bodies, for 10k and 50k strands of 24 points,
// on two threads; the counter bind_ms is the binding's time (roots,
// cantilevers, carriers); BindStyleStrands binds the ponytail style's.
// Run: build/release/benchmarks/loosehair_bench_strands
#include "loosehair/loosehair.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <memory>

using namespace loosehair;

namespace {

struct Setup {
  SceneDesc scene;
  BuildReport build;
  std::unique_ptr<Solver> solver;
  std::unique_ptr<StrandField> field;
  double bind_ms = 0;  // binding the strands to the rest state (2 threads)
};

Setup& setup(std::size_t strands) {
  static std::map<std::size_t, std::unique_ptr<Setup>> cache;
  auto& s = cache[strands];
  if (!s) {
    s = std::make_unique<Setup>();
    s->scene = loadScene(std::string(LOOSEHAIR_SOURCE_DIR) + "/data/scenes/hang.json");
    s->solver = std::make_unique<Solver>(buildSolver(s->scene, &s->build));
    RenderStrandOptions so;
    so.strands = strands;
    so.points = 24;
    const auto t0 = std::chrono::steady_clock::now();
    s->field = std::make_unique<StrandField>(bindSceneStrands(s->scene, s->solver->particles(), s->build, so, 2));
    s->bind_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    s->solver->advance(30 * s->build.substeps);
  }
  return *s;
}

void BM_CarryStrands(benchmark::State& state) {
  Setup& s = setup(static_cast<std::size_t>(state.range(0)));
  const bool bodies = state.range(1) != 0;
  std::vector<glm::vec3> out;
  for (auto _ : state) {
    if (bodies)
      s.field->deform(*s.solver, out, 2);
    else
      s.field->deform(s.solver->particles().position, s.solver->particles().direction, nullptr, out, 2);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points"] = static_cast<double>(out.size());
  state.counters["bind_ms"] = s.bind_ms;
}

// Binding the render strands of a wisp style (the ponytail's 12k strands:
// long strands far from most particles' roots) to the settled-free rest
// state, on two threads.
void BM_BindStyleStrands(benchmark::State& state) {
  SceneDesc scene = loadScene(std::string(LOOSEHAIR_SOURCE_DIR) + "/data/scenes/hang.json");
  scene.hair.style = std::string(LOOSEHAIR_SOURCE_DIR) + "/data/styles/ponytail.json";
  scene.hair.style_data.reset();
  BuildReport build;
  const Solver solver = buildSolver(scene, &build);
  RenderStrandOptions so;
  so.strands = 12000;
  so.points = 24;
  std::size_t points = 0;
  for (auto _ : state) {
    const StrandField field = bindSceneStrands(scene, solver.particles(), build, so, 2);
    points = field.rest().points.size();
  }
  state.counters["points"] = static_cast<double>(points);
}

}  // namespace

BENCHMARK(BM_BindStyleStrands)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CarryStrands)
    ->ArgsProduct({{10000, 50000}, {0, 1}})
    ->ArgNames({"strands", "bodies"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
