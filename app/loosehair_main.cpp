// loosehair: headless command line.
//
//   loosehair simulate SCENE [--frames N] [--threads T] [--dump DIR] [--seed S]
//
// Runs the scene, shows progress on a terminal, prints per-stage timings and
// ends with the line "state-hash: <hex>". Errors go to stderr with a
// non-zero exit code (2 for bad usage, 1 for anything else).
#include "loosehair/loosehair.hpp"

#include <unistd.h>

#include <chrono>
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
    "\n"
    "  simulate   run SCENE (a JSON scene file) headless and print the state hash\n"
    "    --frames N   number of frames (default: the scene's \"frames\")\n"
    "    --threads T  worker threads (default: all cores); results do not depend on it\n"
    "    --dump DIR   write DIR/frame_00001.ply ... (binary PLY, world coordinates)\n"
    "    --seed S     random seed of the hair sampling (default: the scene's \"seed\")\n";

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
              "clamped sides\n",
              st.neighbor_pairs / 2, st.active_connections, st.body_contacts, st.clamped_sides);
  if (solver.hasWind())
    std::printf("wind: %zu air particles, %zu hair-air pairs, last step\n", st.air_particles,
                st.hair_air_pairs);
  std::printf("state-hash: %016" PRIx64 "\n", solver.stateHash());
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
    throw UsageError{"unknown command '" + args[0] + "'"};
  } catch (const UsageError& e) {
    std::fprintf(stderr, "loosehair: %s\n\n%s", e.message.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair: error: %s\n", e.what());
    return 1;
  }
}
