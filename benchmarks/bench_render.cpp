// Frame time of the renderer on this machine's OpenGL, split into the
// back-to-front sort, the light pass (16 opacity slices) and the camera
// pass: billboards for the hang scene at 2k, 20k and 100k particles and two
// image sizes; strands (10k and 50k, 24 points, 2x2 supersampled) with the
// time to carry them, at 640x480 and 1280x720, through OSMesa and through
// EGL (a GPU where there is one; llvmpipe here). Shadows on.
//
//   build/release/benchmarks/loosehair_bench_render
#include "headless_gl.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render/strand_carry_gpu.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
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

// The default scene after 1 s with its strands carried (the rest of the
// state as above); 6k particles.
struct StrandScene {
  SceneDesc desc;
  BuildReport build;
  std::unique_ptr<Solver> solver;
  std::unique_ptr<StrandField> field;
  render::FrameInput frame;
  TriangleMesh head, torso;
};

StrandScene& strandScene(std::size_t strands) {
  static std::map<std::size_t, std::unique_ptr<StrandScene>> cache;
  auto& slot = cache[strands];
  if (!slot) {
    slot = std::make_unique<StrandScene>();
    slot->desc = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/hang.json");
    slot->solver = std::make_unique<Solver>(buildSolver(slot->desc, &slot->build));
    RenderStrandOptions so;
    so.strands = strands;
    so.points = 24;
    slot->field =
        std::make_unique<StrandField>(bindSceneStrands(slot->desc, slot->solver->particles(), slot->build, so, 2));
    slot->solver->advance(30 * slot->build.substeps);
    slot->frame = render::frameFromSolver(*slot->solver, slot->build.mean_neighbor_distance);
    slot->frame.strand_points_each = so.points;
    slot->head = decimate(loadMesh(slot->desc.head_mesh.path), 16000);
    slot->torso = decimate(loadMesh(slot->desc.torso_mesh.path), 8000);
  }
  return *slot;
}

// The strands carried by a compute shader (render::GpuStrandCarry) out of
// the head and the torso, as the viewer does where it can: the particles'
// motions on the CPU, the rest on this machine's OpenGL, waited for.
// volume_s: sampling the bodies' distance volumes (once).
void BM_CarryStrandsGpu(benchmark::State& state) {
  StrandScene& s = strandScene(static_cast<std::size_t>(state.range(0)));
  const auto provider = state.range(1) ? app::GLProvider::EGL : app::GLProvider::OSMesa;
  app::HeadlessGL gl(64, 64, provider);
  render::GpuStrandCarry gpu(*s.field);
  const auto bodies = s.solver->bodyPlacements();
  const glm::mat4 to_world = render::headToWorld(s.solver->head().pose);
  const Particles& p = s.solver->particles();
  gpu.carry(p.position, p.direction, bodies, to_world, 2);
  gpu.wait();
  for (auto _ : state) {
    gpu.carry(p.position, p.direction, bodies, to_world, 2);
    gpu.wait();
  }
  state.counters["volume_s"] = gpu.volumeSeconds();
  state.SetLabel(gl.renderer());
}
BENCHMARK(BM_CarryStrandsGpu)
    ->ArgNames({"strands", "egl"})
    ->ArgsProduct({{12000, 50000, 100000}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// gpu: carried by GpuStrandCarry (carry_ms then counts its work, waited for)
void BM_RenderStrands(benchmark::State& state) {
  StrandScene& s = strandScene(static_cast<std::size_t>(state.range(0)));
  const int w = static_cast<int>(state.range(1)), h = static_cast<int>(state.range(2));
  const auto provider = state.range(3) ? app::GLProvider::EGL : app::GLProvider::OSMesa;
  const bool on_gpu = state.range(4) != 0;
  app::HeadlessGL gl(w, h, provider);
  render::Renderer renderer;
  renderer.setBodies(&s.head, &s.torso);
  const render::Camera camera = render::Camera::preset("three-quarter");
  render::RenderSettings settings;
  settings.hair = render::HairGeometry::Strands;
  settings.supersample = static_cast<int>(state.range(5));
  std::unique_ptr<render::GpuStrandCarry> gpu;
  const auto bodies = s.solver->bodyPlacements();
  const glm::mat4 to_world = render::headToWorld(s.solver->head().pose);
  const Particles& particles = s.solver->particles();
  render::FrameInput frame = s.frame;
  auto carryOnce = [&] {
    if (!on_gpu) {
      s.field->deformWorld(*s.solver, frame.strand_points, 2);
      return;
    }
    gpu->carry(particles.position, particles.direction, bodies, to_world, 2);
    gpu->wait();
  };
  if (on_gpu) {
    gpu = std::make_unique<render::GpuStrandCarry>(*s.field);
    frame.strand_buffer = gpu->buffer();
    frame.strand_buffer_points = gpu->points();
    frame.strand_mean_length = gpu->meanLength();
  }
  carryOnce();
  renderer.render(frame, camera, settings, w, h);
  render::FrameTimes sum;
  double carry = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    carryOnce();
    carry += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    renderer.render(frame, camera, settings, w, h);
    const auto& t = renderer.lastTimes();
    sum.upload += t.upload;
    sum.light_pass += t.light_pass;
    sum.camera_pass += t.camera_pass;
    sum.resolve += t.resolve;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["carry_ms"] = 1e3 * carry / n;
  state.counters["upload_ms"] = 1e3 * sum.upload / n;
  state.counters["light_ms"] = 1e3 * sum.light_pass / n;
  state.counters["camera_ms"] = 1e3 * sum.camera_pass / n;
  state.counters["resolve_ms"] = 1e3 * sum.resolve / n;
  state.SetLabel(gl.renderer());
}
BENCHMARK(BM_RenderStrands)
    ->ArgNames({"strands", "w", "h", "egl", "gpu", "ss"})
    ->ArgsProduct({{10000, 50000}, {640}, {480}, {0, 1}, {0, 1}, {2}})
    ->ArgsProduct({{10000, 50000}, {1280}, {720}, {0, 1}, {0, 1}, {2}})
    // the viewer's picture: no supersampling, 12k strands (its default)
    ->ArgsProduct({{12000}, {640}, {360}, {0}, {1}, {1}})
    ->ArgsProduct({{12000}, {1280}, {720}, {0}, {1}, {1}})
    ->ArgsProduct({{100000}, {1920}, {1080}, {1}, {1}, {2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
