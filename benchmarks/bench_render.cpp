// Frame time of the renderer on this machine's software OpenGL (OSMesa,
// llvmpipe), split into the back-to-front sort, the light pass (16 opacity
// slices) and the camera pass, for the hang scene at 2k, 20k and 100k
// particles and two image sizes, shadows on.
//
//   build/release/benchmarks/loosehair_bench_render
#include "headless_gl.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

namespace {

using namespace loosehair;

struct Scene {
  render::FrameInput frame;
  TriangleMesh head, torso;
};

const Scene& hangScene(int particles) {
  static std::map<int, std::unique_ptr<Scene>> cache;
  auto& slot = cache[particles];
  if (!slot) {
    SceneDesc desc = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/hang.json");
    desc.hair.particles = particles;
    BuildReport build;
    Solver solver = buildSolver(desc, &build);
    slot = std::make_unique<Scene>();
    slot->frame = render::frameFromSolver(solver, build.mean_neighbor_distance);
    // as `loosehair render` draws them
    slot->head = decimate(loadMesh(desc.head_mesh.path), 16000);
    slot->torso = decimate(loadMesh(desc.torso_mesh.path), 8000);
  }
  return *slot;
}

void BM_RenderFrame(benchmark::State& state) {
  const Scene& s = hangScene(static_cast<int>(state.range(0)));
  const int w = static_cast<int>(state.range(1)), h = static_cast<int>(state.range(2));
  app::HeadlessGL gl(w, h);
  render::Renderer renderer;
  renderer.setBodies(&s.head, &s.torso);
  const render::Camera camera = render::Camera::preset("three-quarter");
  const render::RenderSettings settings;
  renderer.render(s.frame, camera, settings, w, h);  // llvmpipe compiles shaders on first use
  render::FrameTimes sum;
  for (auto _ : state) {
    renderer.render(s.frame, camera, settings, w, h);
    const auto& t = renderer.lastTimes();
    sum.sort += t.sort;
    sum.upload += t.upload;
    sum.light_pass += t.light_pass;
    sum.camera_pass += t.camera_pass;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["sort_ms"] = 1e3 * sum.sort / n;
  state.counters["upload_ms"] = 1e3 * sum.upload / n;
  state.counters["light_ms"] = 1e3 * sum.light_pass / n;
  state.counters["camera_ms"] = 1e3 * sum.camera_pass / n;
  state.counters["fps"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)
    ->ArgNames({"particles", "w", "h"})
    ->Args({2000, 512, 512})
    ->Args({2000, 1280, 720})
    ->Args({20000, 512, 512})
    ->Args({20000, 1280, 720})
    ->Args({100000, 512, 512})
    ->Args({100000, 1280, 720})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
