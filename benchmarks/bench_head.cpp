// The initialisation pipeline on the bundled head (mesh loading, the
// signed-distance bake, the harmonic scalp map, Poisson-disc sampling, the
// cantilever strands) and one step of the wind scene at 10k and 50k hair
// particles.
//
//   build/release/benchmarks/loosehair_bench_head
#include "init/length_map.hpp"
#include "init/mesh_scalp.hpp"
#include "init/poisson_pillar.hpp"
#include "loosehair/loosehair.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

namespace {

using namespace loosehair;

const std::string kData = LOOSEHAIR_SOURCE_DIR "/data";

const TriangleMesh& head() {
  static const TriangleMesh mesh = loadMesh(kData + "/meshes/head.ply");
  return mesh;
}

const GridSdfBody& headSdf() {
  static const auto body = GridSdfBody::bake(head(), {});
  return *body;
}

void BM_LoadHeadMesh(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(loadMesh(kData + "/meshes/head.ply").triangles.size());
  state.counters["triangles"] = static_cast<double>(head().triangles.size());
}
BENCHMARK(BM_LoadHeadMesh)->Unit(benchmark::kMillisecond);

// The bake without the cache, at the automatic spacing (1/128 of the
// mesh's extent) and at a finer one.
void BM_SdfBake(benchmark::State& state) {
  SdfBakeOptions opt;
  opt.voxel_size = static_cast<float>(state.range(0)) * 1e-4f;
  std::shared_ptr<GridSdfBody> body;
  for (auto _ : state) body = GridSdfBody::bake(head(), opt);
  state.counters["voxels"] = static_cast<double>(body->dims().x) * body->dims().y * body->dims().z;
}
BENCHMARK(BM_SdfBake)->Arg(0)->Arg(20)->ArgName("voxel_0.1mm")->Unit(benchmark::kMillisecond);

// Contact queries near the head's surface: points within +-range mm of it
// (placed along the vertex normals, in a fixed order), asked of the grid
// alone and of the exact mesh body (grid first, nearest triangle where the
// grid cannot decide), with the solver's contact limits 0 and 2 mm.
void contactQueries(benchmark::State& state, bool exact) {
  static const std::shared_ptr<GridSdfBody> grid = GridSdfBody::bake(head(), {});
  static const MeshBody mesh_body(head(), grid);
  const Body& body = exact ? static_cast<const Body&>(mesh_body) : *grid;
  const float range = static_cast<float>(state.range(0)) * 1e-3f;
  const float limit = static_cast<float>(state.range(1)) * 1e-3f;
  const auto normals = vertexNormals(head());
  std::vector<glm::vec3> p(4096);
  std::uint32_t h = 12345;
  for (std::size_t k = 0; k < p.size(); ++k) {
    h = h * 1664525u + 1013904223u;
    const std::size_t v = h % head().vertices.size();
    h = h * 1664525u + 1013904223u;
    const float off = range * (2.0f * static_cast<float>(h >> 8) / 16777216.0f - 1.0f);
    p[k] = head().vertices[v] + off * normals[v];
  }
  std::vector<float> phi(p.size());
  std::vector<glm::vec3> nrm(p.size());
  for (auto _ : state) {
    body.signedDistanceBelow(p.data(), p.size(), limit, phi.data(), nrm.data());
    benchmark::DoNotOptimize(phi.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(p.size()));
}
void BM_ContactQueryGrid(benchmark::State& state) { contactQueries(state, false); }
void BM_ContactQueryExact(benchmark::State& state) { contactQueries(state, true); }
BENCHMARK(BM_ContactQueryGrid)->Args({1, 0})->Args({5, 0})->Args({5, 2})->ArgNames({"range_mm", "limit_mm"});
BENCHMARK(BM_ContactQueryExact)->Args({1, 0})->Args({5, 0})->Args({5, 2})->ArgNames({"range_mm", "limit_mm"});

void BM_HarmonicScalpMap(benchmark::State& state) {
  const ScalpCurves curves = automaticScalpCurves(head(), headSdf());
  std::size_t triangles = 0;
  for (auto _ : state) {
    MeshScalp scalp(head(), headSdf(), curves, "head");
    triangles = scalp.report().triangles;
  }
  state.counters["scalp_triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_HarmonicScalpMap)->Unit(benchmark::kMillisecond);

void BM_PoissonSampling(benchmark::State& state) {
  static const MeshScalp scalp(head(), headSdf(), automaticScalpCurves(head(), headSdf()), "head");
  static const LengthMap map(kData + "/maps/hair_length.png");
  auto length = [](glm::vec2 uv) { return 0.32f * std::max(map(uv), 0.02f); };
  PillarOptions opt;
  opt.target_count = static_cast<int>(state.range(0));
  std::size_t n = 0;
  for (auto _ : state) n = samplePillar(scalp, length, 0.32f, opt).samples.size();
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}
BENCHMARK(BM_PoissonSampling)->Arg(10000)->Arg(50000)->ArgName("particles")->Unit(benchmark::kMillisecond);

// The whole scene build (mesh, cached bake, scalp, sampling, strands,
// connections) of hang.json.
void BM_BuildHangScene(benchmark::State& state) {
  SceneDesc scene = loadScene(kData + "/scenes/hang.json");
  scene.hair.particles = static_cast<int>(state.range(0));
  BuildReport r;
  for (auto _ : state) benchmark::DoNotOptimize(buildSolver(scene, &r).particles().size());
  state.counters["sampling_ms"] = r.seconds_sampling * 1e3;
  state.counters["strands_ms"] = r.seconds_strands * 1e3;
  state.counters["scalp_ms"] = r.seconds_scalp * 1e3;
}
BENCHMARK(BM_BuildHangScene)->Arg(10000)->Arg(50000)->ArgName("particles")->Unit(benchmark::kMillisecond);

Solver& windScene(int particles) {
  static std::map<int, std::unique_ptr<Solver>> cache;
  auto& slot = cache[particles];
  if (!slot) {
    SceneDesc scene = loadScene(kData + "/scenes/wind.json");
    scene.hair.particles = particles;
    slot = std::make_unique<Solver>(buildSolver(scene));
    // into the gust, so that the air streams through the hair
    slot->advance(static_cast<int>(0.5 / slot->params().time_step));
  }
  return *slot;
}

void BM_WindStep(benchmark::State& state) {
  Solver& solver = windScene(static_cast<int>(state.range(0)));
  solver.setThreadCount(static_cast<int>(state.range(1)));
  for (auto _ : state) solver.step();
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(solver.particles().size()));
  const StageTimes& s = solver.stats().last;
  state.counters["air_ms"] = s.air * 1e3;
  state.counters["hair_ms"] = (s.total() - s.air) * 1e3;
  state.counters["air_particles"] = static_cast<double>(solver.stats().air_particles);
  state.counters["hair_air_pairs"] = static_cast<double>(solver.stats().hair_air_pairs);
}
BENCHMARK(BM_WindStep)
    ->Args({10000, 1})
    ->Args({10000, 2})
    ->Args({50000, 2})
    ->ArgNames({"particles", "threads"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
