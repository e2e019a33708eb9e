// Styling (method.md §6.2): member-strand generation at about 10k and 100k
// strands, an edit and its 20k-strand preview (issue 44's goal: under
// 100 ms), a settle of the bob, seeding 10k and 50k particles from a
// style's strands, and the cost of the shape-keeping term in a step (the
// bob on the bundled head, 5,888 particles: a step with and without it,
// and the term alone).
//
//   build/release/benchmarks/loosehair_bench_style
#include "loosehair/loosehair.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"
#include "loosehair/style_settle.hpp"
#include "solver/shape_keeping.hpp"
#include "style/style_seeding.hpp"

#include <benchmark/benchmark.h>

namespace {

using namespace loosehair;

const std::string kStyles = LOOSEHAIR_SOURCE_DIR "/data/styles";

const Style& bob() {
  static const Style s = loadStyle(kStyles + "/bob.json");
  return s;
}

const HeadModel& bobHead() {
  static const HeadModel h = HeadModel::build(bob().head, bob().source);
  return h;
}

// The bob (about 10.5k strands at its own density) and at ten times it.
void BM_MemberStrands(benchmark::State& state) {
  Style s = bob();
  for (Wisp& w : s.wisps) w.params.density *= static_cast<float>(state.range(0));
  StrandSet strands;
  for (auto _ : state) strands = buildMemberStrands(s, bobHead());
  state.counters["strands"] = static_cast<double>(strands.size());
  state.counters["points"] = static_cast<double>(strands.points.size());
}
BENCHMARK(BM_MemberStrands)->Arg(1)->Arg(10)->ArgName("density_x")->Unit(benchmark::kMillisecond);

// One edit as the styling mode makes it, and the preview it shows: a drag
// step of one control point (StyleEditor::dragged, setKeyStrand amending
// the drag's undo step) and the bob's member strands grown again as the
// preview grows them (6 mm point spacing, pushed out of the head by the
// bodies' grids, two threads), with blend 0 or 1 (the file's), at about
// 20,000 strands (1.5 times the bob's density). The goal: under
// 100 ms.
void BM_EditAndPreview(benchmark::State& state) {
  Style s = bob();
  for (Wisp& w : s.wisps) {
    w.params.density *= 1.5f;
    w.params.blend = static_cast<float>(state.range(0));
  }
  StyleEditor ed(s, bobHead());
  const std::vector<glm::vec3> start = ed.style().wisps[3].key_strand;
  StrandSet strands;
  int step = 0;
  for (auto _ : state) {
    const glm::vec3 offset(0.0f, 0.0f, 0.002f * static_cast<float>(step % 10));
    ed.setKeyStrand(3, ed.dragged(start, 2, offset, 0.06f), step > 0);
    strands = buildMemberStrands(ed.style(), bobHead(), 0.006f, {}, 2, false);
    ++step;
  }
  state.counters["strands"] = static_cast<double>(strands.size());
}
BENCHMARK(BM_EditAndPreview)->Arg(0)->Arg(1)->ArgName("blend")->Unit(benchmark::kMillisecond)->UseRealTime();

// The styling mode's Settle on the bob: grown at 3,000 particles, 1.5 s of
// plain LCP on a still head, the key strands read back (the goal:
// a few seconds at most for a bundled style).
void BM_SettleStyle(benchmark::State& state) {
  SettleOptions o;
  o.threads = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(settledKeyStrands(bob(), o));
}
BENCHMARK(BM_SettleStyle)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

void BM_SeedParticles(benchmark::State& state) {
  static const StrandSet strands = buildMemberStrands(bob(), bobHead());
  StrandSeeding seeded;
  for (auto _ : state) seeded = seedFromStrands(strands, static_cast<int>(state.range(0)), 1);
  state.counters["particles"] = static_cast<double>(seeded.samples.size());
}
BENCHMARK(BM_SeedParticles)->Arg(10000)->Arg(50000)->Unit(benchmark::kMillisecond);

// One solver step of the bob on a still head, shape keeping on (1 Hz) or
// off, every step from the same styled state (restored untimed before each):
// the difference is the term's own cost. (Left to run on, the hair without
// the term collapses and each step has more contacts, which hides it.)
void BM_StepShapeKeeping(benchmark::State& state) {
  SceneDesc scene = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/hang.json");
  scene.hair.style = kStyles + "/bob.json";
  scene.sim.shape_keeping = state.range(0) ? 1.0f : 0.0f;
  scene.shape_keeping_auto = false;
  scene.sim.threads = 2;
  Solver solver = buildSolver(scene);
  const Particles start = solver.particles();
  for (auto _ : state) {
    state.PauseTiming();
    solver.setKinematicState(start.position, start.velocity, start.direction);
    state.ResumeTiming();
    solver.step();
  }
  state.counters["particles"] = static_cast<double>(solver.particles().size());
}
BENCHMARK(BM_StepShapeKeeping)->Arg(0)->Arg(1)->ArgName("shape_keeping")->Unit(benchmark::kMillisecond)->MinTime(2.0);

// The term alone, as the external-force pass evaluates it (one thread): the
// pull and the prestress of every particle of the bob's 5,888, added to a
// force. Its share of a step is this over BM_StepShapeKeeping.
void BM_ShapeKeepingTerm(benchmark::State& state) {
  static Solver solver = [] {
    SceneDesc scene = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/hang.json");
    scene.hair.style = kStyles + "/bob.json";
    return buildSolver(scene);
  }();
  const Particles& p = solver.particles();
  const std::vector<glm::vec3> force0 = solver.internalForces();
  const ShapeKeeping term(1.0f, p.position, p.mass, force0, glm::vec3(0, -9.81f, 0));
  std::vector<glm::vec3> force(p.size(), glm::vec3(0.0f));
  for (auto _ : state) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (!p.is_root[i]) force[i] += p.mass[i] * term.acceleration(i, p.position[i]);
    benchmark::DoNotOptimize(force.data());
    benchmark::ClobberMemory();
  }
  state.counters["particles"] = static_cast<double>(p.size());
}
BENCHMARK(BM_ShapeKeepingTerm)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
