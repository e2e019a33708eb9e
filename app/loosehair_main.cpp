// loosehair: headless command line.
//
//   loosehair simulate SCENE [--frames N] [--threads T] [--dump DIR] [--seed S]
//   loosehair render SCENE [--frames N] [--size WxH] [--camera PRESET] [--out DIR]
//                          [--video FILE.mp4] [...]
//
// Runs the scene, shows progress on a terminal, prints per-stage timings and
// ends with the line "state-hash: <hex>". Errors go to stderr with a
// non-zero exit code (2 for bad usage, 1 for anything else).
#include "headless_gl.hpp"
#include "png.hpp"
#include "scene_bodies.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: loosehair simulate SCENE [--frames N] [--threads T] [--dump DIR] [--seed S]\n"
    "       loosehair render SCENE [--frames N] [--size WxH] [--camera PRESET] [--out DIR]\n"
    "                              [--video FILE.mp4] [--threads T] [--seed S] [--color C]\n"
    "                              [--no-shadows] [--debug VIEW] [--yaw D] [--pitch D]\n"
    "                              [--distance M] [--fov D] [--light X,Y,Z]\n"
    "\n"
    "  simulate   run SCENE (a JSON scene file) headless and print the state hash\n"
    "    --frames N   number of frames (default: the scene's \"frames\")\n"
    "    --threads T  worker threads (default: all cores); results do not depend on it\n"
    "    --dump DIR   write DIR/frame_00001.ply ... (binary PLY, world coordinates)\n"
    "    --seed S     random seed of the hair sampling (default: the scene's \"seed\")\n"
    "  render     simulate SCENE and draw every frame to DIR/frame_00001.png ... with\n"
    "             software OpenGL (OSMesa: no display, no GPU)\n"
    "    --size WxH       image size (default 640x480)\n"
    "    --camera PRESET  front, side, back or three-quarter (default)\n"
    "    --out DIR        where the PNGs go (default render-out)\n"
    "    --video FILE     also encode the frames to FILE (H.264 MP4) with ffmpeg\n"
    "    --color C        hair colour: black, brown (default), blonde or red\n"
    "    --no-shadows     no self-shadowing (opacity shadow maps)\n"
    "    --debug VIEW     density, speed (points), connections or directions (lines)\n"
    "    --yaw, --pitch, --distance, --fov   orbit the preset camera (degrees, metres)\n"
    "    --light X,Y,Z    direction towards the (parallel) light\n";

struct UsageError {
  std::string message;
};

long long parseInteger(const std::string& flag, const std::string& value, long long lo,
                       long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw UsageError{flag + " needs an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + value + "'"};
  return v;
}

struct Options {
  std::string scene;
  std::optional<int> frames, threads;
  std::optional<std::uint64_t> seed;
  std::string dump_dir;
};

Options parseSimulate(const std::vector<std::string>& args) {
  Options o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) throw UsageError{a + " needs a value"};
      return args[++k];
    };
    if (a == "--frames")
      o.frames = static_cast<int>(parseInteger(a, value(), 1, 10000000));
    else if (a == "--threads")
      o.threads = static_cast<int>(parseInteger(a, value(), 1, 1024));
    else if (a == "--seed")
      o.seed = static_cast<std::uint64_t>(parseInteger(a, value(), 0, INT64_MAX));
    else if (a == "--dump")
      o.dump_dir = value();
    else if (!a.empty() && a[0] == '-')
      throw UsageError{"unknown option " + a};
    else if (o.scene.empty())
      o.scene = a;
    else
      throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'"};
  }
  if (o.scene.empty()) throw UsageError{"simulate needs a scene file"};
  return o;
}

void drawProgress(int done, int total, double elapsed) {
  constexpr int kWidth = 30;
  const int filled = total > 0 ? done * kWidth / total : kWidth;
  std::fprintf(stderr, "\r[%.*s%*s] frame %d/%d  %.1f s", filled,
               "##############################", kWidth - filled, "", done, total, elapsed);
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

int simulate(const Options& o) {
  using namespace loosehair;
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  const int frames = o.frames.value_or(scene.frames);
  if (!o.dump_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.dump_dir, ec);
    if (ec) throw std::runtime_error(o.dump_dir + ": cannot create the dump directory: " + ec.message());
  }

  const auto t_init = std::chrono::steady_clock::now();
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  const double init_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_init).count();
  const InitReport& r = solver.initReport();
  std::printf("scene: %s (%s), seed %" PRIu64 "\n", scene.name.c_str(), o.scene.c_str(), scene.seed);
  if (build.head_triangles > 0)
    std::printf("head mesh: %zu triangles (signed distance %s, %.2f s), scalp: %zu triangles, %.0f cm^2, "
                "harmonic map %.2f s%s\n",
                build.head_triangles, build.sdf_from_cache ? "from cache" : "baked",
                build.seconds_sdf, build.scalp_triangles, build.scalp_area * 1e4, build.seconds_scalp,
                build.scalp_mean_value ? " (mean-value weights)" : "");
  std::printf("particles: %zu (%zu roots), connections: %zu pairs, degree mean %.1f min %u max %u\n",
              r.particles, r.roots, r.connection_pairs, r.mean_degree, r.min_degree, r.max_degree);
  std::printf("Poisson radius %.4f m, mean nearest neighbour %.4f m, h1 = %.4f m, h2 = %.4f m\n",
              build.poisson_radius, build.mean_neighbor_distance, solver.params().h1,
              solver.params().h2);
  std::printf("time step %.4f ms x %d per frame (stable limit %.4f ms), %d threads, init %.2f s\n",
              build.time_step * 1e3, build.substeps, r.stable_time_step * 1e3,
              solver.threadCount(), init_seconds);
  if (r.unanchored > 0)
    std::fprintf(stderr,
                 "warning: %zu particles cannot reach a root through root-side connections and "
                 "will fall (h1 too small for the sampling?)\n",
                 r.unanchored);
  if (build.time_step > r.stable_time_step)
    std::fprintf(stderr,
                 "warning: the time step %.4f ms is above the stable limit %.4f ms; the scene "
                 "may blow up (use \"substeps\": \"auto\" or more substeps)\n",
                 build.time_step * 1e3, r.stable_time_step * 1e3);

  const bool tty = isatty(fileno(stderr)) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 1; f <= frames; ++f) {
    solver.advance(build.substeps);
    if (!o.dump_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.ply", f);
      writeParticlePly((std::filesystem::path(o.dump_dir) / name).string(), solver);
      if (solver.hasWind()) {
        std::snprintf(name, sizeof name, "air_%05d.ply", f);
        writeAirPly((std::filesystem::path(o.dump_dir) / name).string(), solver);
      }
    }
    if (tty) {
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      drawProgress(f, frames, elapsed);
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const StepStats& st = solver.stats();
  const double steps = static_cast<double>(st.steps);
  const StageTimes& s = st.sum;
  std::printf("simulated %.3f s in %" PRIu64 " steps, %.2f s wall (%.1f frames/s)\n", solver.time(),
              st.steps, wall, frames / wall);
  std::printf("stage timings, ms per step (mean):\n");
  const struct {
    const char* name;
    double seconds;
  } rows[] = {{"neighbors", s.neighbors}, {"density", s.density},
              {"springs", s.springs},     {"hair-hair", s.hair_hair},
              {"external", s.external},   {"integrate", s.integrate},
              {"constraints", s.strain_limit}, {"directions", s.directions},
              {"air", s.air}};
  const double total = s.total();
  for (const auto& row : rows) {
    if (std::string(row.name) == "air" && !solver.hasWind()) continue;
    std::printf("  %-13s %8.3f  %5.1f%%\n", row.name, row.seconds / steps * 1e3,
                total > 0 ? 100.0 * row.seconds / total : 0.0);
  }
  std::printf("  %-13s %8.3f  (%.2f M particle-steps/s)\n", "total", total / steps * 1e3,
              total > 0 ? static_cast<double>(r.particles) * steps / total * 1e-6 : 0.0);
  std::printf("last step: %zu neighbour pairs, %zu active connections, %zu body contacts, %zu "
              "clamped sides, %zu particles strain-limited\n",
              st.neighbor_pairs / 2, st.active_connections, st.body_contacts, st.clamped_sides,
              st.strain_limited);
  if (solver.hasWind())
    std::printf("wind: %zu air particles, %zu hair-air pairs, last step\n", st.air_particles,
                st.hair_air_pairs);
  std::printf("state-hash: %016" PRIx64 "\n", solver.stateHash());
  return 0;
}

// ---- render -------------------------------------------------------------------
double parseReal(const std::string& flag, const std::string& value, double lo, double hi) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
    throw UsageError{flag + " needs a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                     value + "'"};
  return v;
}

struct RenderOptions {
  std::optional<double> yaw, pitch, distance, fov;
  std::string scene, out_dir = "render-out", video, camera = "three-quarter";
  std::optional<int> frames, threads;
  std::optional<std::uint64_t> seed;
  int width = 640, height = 480;
  loosehair::render::RenderSettings settings;
};

RenderOptions parseRender(const std::vector<std::string>& args) {
  RenderOptions o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) throw UsageError{a + " needs a value"};
      return args[++k];
    };
    try {
      if (a == "--frames") o.frames = static_cast<int>(parseInteger(a, value(), 1, 10000000));
      else if (a == "--threads") o.threads = static_cast<int>(parseInteger(a, value(), 1, 1024));
      else if (a == "--seed") o.seed = static_cast<std::uint64_t>(parseInteger(a, value(), 0, INT64_MAX));
      else if (a == "--out") o.out_dir = value();
      else if (a == "--video") o.video = value();
      else if (a == "--camera") {
        o.camera = value();
        (void)loosehair::render::Camera::preset(o.camera);
      } else if (a == "--color") o.settings.color = loosehair::render::parseHairColor(value());
      else if (a == "--debug") o.settings.debug = loosehair::render::parseDebugView(value());
      else if (a == "--no-shadows") o.settings.shadows = false;
      else if (a == "--yaw") o.yaw = parseReal(a, value(), -360, 360);
      else if (a == "--pitch") o.pitch = parseReal(a, value(), -89, 89);
      else if (a == "--distance") o.distance = parseReal(a, value(), 0.05, 100);
      else if (a == "--fov") o.fov = parseReal(a, value(), 5, 150);
      else if (a == "--light") {
        const std::string v = value();
        float c[3];
        if (std::sscanf(v.c_str(), "%f,%f,%f", &c[0], &c[1], &c[2]) != 3 || !std::isfinite(c[0] + c[1] + c[2]) ||
            !(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-12f))
          throw UsageError{"--light needs a non-zero direction x,y,z, got '" + v + "'"};
        o.settings.light_direction = glm::vec3(c[0], c[1], c[2]);
      }
      else if (a == "--size") {
        const std::string v = value();
        const auto x = v.find('x');
        if (x == std::string::npos) throw UsageError{"--size needs WxH, got '" + v + "'"};
        o.width = static_cast<int>(parseInteger("--size width", v.substr(0, x), 16, 8192));
        o.height = static_cast<int>(parseInteger("--size height", v.substr(x + 1), 16, 8192));
      } else if (!a.empty() && a[0] == '-') throw UsageError{"unknown option " + a};
      else if (o.scene.empty()) o.scene = a;
      else throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'"};
    } catch (const loosehair::render::RenderError& e) {
      throw UsageError{a + ": " + e.what()};
    }
  }
  if (o.scene.empty()) throw UsageError{"render needs a scene file"};
  return o;
}

bool haveFfmpeg() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

int renderScene(const RenderOptions& o) {
  using namespace loosehair;
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  const int frames = o.frames.value_or(scene.frames);
  if (!o.video.empty() && !haveFfmpeg())
    throw std::runtime_error("--video needs ffmpeg, which is not installed (scripts/install-deps.sh installs it)");
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) throw std::runtime_error(o.out_dir + ": cannot create the output directory: " + ec.message());

  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  app::HeadlessGL gl(o.width, o.height);
  render::Renderer renderer;
  const app::DrawableBodies bodies = app::drawableBodies(scene);
  renderer.setBodies(&bodies.head, bodies.torso ? &*bodies.torso : nullptr);
  render::Camera camera = render::Camera::preset(o.camera);
  if (o.yaw) camera.yaw_deg = static_cast<float>(*o.yaw);
  if (o.pitch) camera.pitch_deg = static_cast<float>(*o.pitch);
  if (o.distance) camera.distance = static_cast<float>(*o.distance);
  if (o.fov) camera.fov_deg = static_cast<float>(*o.fov);
  std::printf("scene: %s, %zu particles, %d frames of %dx%d, camera %s, %s\n", scene.name.c_str(),
              solver.particles().size(), frames, o.width, o.height, o.camera.c_str(), gl.renderer().c_str());

  const bool tty = isatty(fileno(stderr)) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  render::FrameTimes sum;
  double sim_seconds = 0;
  for (int f = 1; f <= frames; ++f) {
    const auto ts = std::chrono::steady_clock::now();
    solver.advance(build.substeps);
    sim_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
    const render::FrameInput input = render::frameFromSolver(solver, build.mean_neighbor_distance);
    renderer.render(input, camera, o.settings, o.width, o.height);
    const auto& t = renderer.lastTimes();
    sum.sort += t.sort;
    sum.upload += t.upload;
    sum.light_pass += t.light_pass;
    sum.camera_pass += t.camera_pass;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    app::writePng((std::filesystem::path(o.out_dir) / name).string(), gl.pixels(), o.width, o.height);
    if (tty)
      drawProgress(f, frames, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("rendered %d frames in %.2f s (%.1f frames/s); per frame: simulation %.1f ms, sort %.2f ms, "
              "light pass %.1f ms, camera pass %.1f ms\n",
              frames, wall, frames / wall, 1e3 * sim_seconds / frames, 1e3 * sum.sort / frames,
              1e3 * sum.light_pass / frames, 1e3 * sum.camera_pass / frames);
  std::printf("frames: %s/frame_00001.png ... frame_%05d.png\n", o.out_dir.c_str(), frames);
  if (!o.video.empty()) {
    const std::string cmd = "ffmpeg -y -loglevel error -framerate " + std::to_string(scene.frame_rate) + " -i '" +
                            (std::filesystem::path(o.out_dir) / "frame_%05d.png").string() +
                            "' -c:v libx264 -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" + o.video + "'";
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("ffmpeg could not encode " + o.video);
    std::printf("video: %s\n", o.video.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
      std::fputs(kUsage, args.empty() ? stderr : stdout);
      return args.empty() ? 2 : 0;
    }
    if (args[0] == "simulate")
      return simulate(parseSimulate(std::vector<std::string>(args.begin() + 1, args.end())));
    if (args[0] == "render")
      return renderScene(parseRender(std::vector<std::string>(args.begin() + 1, args.end())));
    throw UsageError{"unknown command '" + args[0] + "'"};
  } catch (const UsageError& e) {
    std::fprintf(stderr, "loosehair: %s\n\n%s", e.message.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair: error: %s\n", e.what());
    return 1;
  }
}
