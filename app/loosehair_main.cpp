// loosehair: headless command line.
//
//   loosehair simulate SCENE [--frames N] [--threads T] [--dump DIR] [--seed S]
//   loosehair render SCENE [--frames N] [--size WxH] [--camera PRESET] [--out DIR]
//                          [--video FILE.mp4] [...]
//   loosehair style STYLE [--strands OUT]   (or --import GROOM --head F --out STYLE)
//
// Runs the scene, shows progress on a terminal, prints per-stage timings and
// ends with the line "state-hash: <hex>". Errors go to stderr with a
// non-zero exit code (2 for bad usage, 1 for anything else).
#include "cli_args.hpp"
#include "headless_gl.hpp"
#include "png.hpp"
#include "process.hpp"
#include "video.hpp"
#include "scene_bodies.hpp"
#include "style_command.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/strand_files.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render/strand_carry_gpu.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cctype>
#include <cinttypes>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace {

constexpr const char* kSimulateUsage =
    "usage: loosehair simulate SCENE [--frames N] [--threads T] [--seed S]\n"
    "                            [--dump DIR [--overwrite]]\n"
    "                            [--save-state FILE [--save-every N]] [--resume FILE]\n"
    "                            [--style STYLE.json] [--no-shape-keeping] [--motion FILE]\n"
    "                            [--dump-strands DIR [--strands N] [--strand-points P]]\n"
    "\n"
    "  Runs SCENE (a JSON scene file) headless and prints the state hash.\n"
    "    --frames N       number of frames (default: the scene's \"frames\"); with\n"
    "                     --resume, the frames to run after the snapshot's\n"
    "    --threads T      exactly T worker threads (default: all cores, or one while\n"
    "                     other programs keep them busy); results do not depend on it\n"
    "    --dump DIR       write DIR/frame_00001.ply ... (binary PLY, world coordinates)\n"
    "    --dump-strands DIR  write each frame's render strands, carried by the\n"
    "                     particles, to DIR/strands_00001.ply (polylines) and .hair\n"
    "                     (cyHair), world coordinates, for other renderers\n"
    "    --strands N      about N render strands (default 12000)\n"
    "    --strand-points P  points a strand, 2..256 (default 24)\n"
    "    --overwrite      let --dump (or render's --out) replace the frames of an\n"
    "                     earlier run in DIR (they are removed first)\n"
    "    --seed S         random seed of the hair sampling (default: the scene's \"seed\")\n"
    "    --allow-expensive  start scenes beyond the cost limits (very many\n"
    "                     particles, steps, air particles, mesh triangles,\n"
    "                     distance-grid cells, style strands or render-strand\n"
    "                     points; see data/scenes/README.md), which are refused\n"
    "                     by default with what to change\n"
    "    --save-state F   write a snapshot of the whole state to F at the end (and\n"
    "                     every N frames with --save-every N); --resume F goes on\n"
    "                     from it, bit-identically\n"
    "    --style STYLE    grow the hair from STYLE's wisps instead of the scene's hair\n"
    "                     (on the scene's head; see data/styles/README.md)\n"
    "    --no-shape-keeping  plain LCP: no pull towards the styled shape\n"
    "    --motion FILE    the head moves as FILE says ({\"motion\": {...}}, as in a\n"
    "                     scene; the viewer's \"save head motion\" writes one)\n";

constexpr const char* kRenderUsage =
    "usage: loosehair render SCENE [--frames N] [--size WxH] [--camera PRESET] [--out DIR]\n"
    "                              [--overwrite] [--video FILE.mp4] [--threads T] [--seed S]\n"
    "                              [--color C] [--no-shadows] [--debug VIEW] [--yaw D]\n"
    "                              [--pitch D] [--distance M] [--fov D] [--light X,Y,Z] [--no-lod]\n"
    "                              [--style STYLE.json] [--no-shape-keeping]\n"
    "                              [--hair strands|billboards] [--shading kajiya-kay|marschner]\n"
    "                              [--supersample N] [--strands N] [--strand-points P]\n"
    "                              [--gl osmesa|egl] [--strand-carry cpu|gpu] [--motion FILE]\n"
    "\n"
    "  Simulates SCENE and draws every frame to DIR/frame_00001.png ... with\n"
    "  software OpenGL (OSMesa: no display, no GPU).\n"
    "    --size WxH       image size (default 640x480)\n"
    "    --camera PRESET  front, side, back or three-quarter (default)\n"
    "    --out DIR        where the PNGs go (default render-out); must be empty or new\n"
    "                     unless --overwrite is given\n"
    "    --video FILE     also encode the frames to FILE with ffmpeg (H.264 in .mp4,\n"
    "                     .m4v, .mov or .mkv, by the name)\n"
    "    --color C        hair colour: black, brown (default), blonde or red\n"
    "    --no-shadows     no self-shadowing (opacity shadow maps)\n"
    "    --debug VIEW     density, speed (points), connections or directions (lines)\n"
    "    --yaw, --pitch, --distance, --fov   orbit the preset camera (degrees, metres)\n"
    "    --no-lod         draw every strand however small the hair is in the picture\n"
    "    --light X,Y,Z    direction towards the (parallel) light (default: above, right\n"
    "                     and in front of the camera, turning with it)\n"
    "    --hair H         strands (default: thin strands the particles carry) or\n"
    "                     billboards (one a particle, the LCP paper's picture)\n"
    "    --shading S      strands lit by kajiya-kay (default) or marschner\n"
    "    --supersample N  draw N x N times the pixels and filter down (1..4;\n"
    "                     default 2 for strands, 1 for billboards)\n"
    "    --strands N      about N strands (default 12000); --strand-points P, 2..256\n"
    "    --gl P           osmesa (default: software, llvmpipe) or egl (a GPU where\n"
    "                     there is one, else Mesa's surfaceless platform); no X server\n"
    "    --strand-carry C cpu (default: exact contacts) or gpu (a compute shader and\n"
    "                     the bodies' sampled distances: for speed on a GPU; within\n"
    "                     a few mm of the CPU's, docs/design.md)\n"
    "    --frames, --threads, --seed, --allow-expensive, --style,\n"
    "    --no-shape-keeping, --motion   as for simulate\n"
    "  Options may also be written --flag=value.\n";

constexpr const char* kUsage =
    "usage: loosehair simulate SCENE [options]   run a scene headless, print its state hash\n"
    "       loosehair render SCENE [options]     simulate and draw frames (PNG, MP4)\n"
    "       loosehair style STYLE [options]      build a style's strands, export them,\n"
    "                                            or import a groom as a style\n"
    "       loosehair COMMAND --help             the options of a command\n"
    "       loosehair --version\n";

using loosehair::app::UsageError;

// Render strands of simulate --dump-strands and render unless --strands says
// otherwise: 12,000 keep the README's default render under a minute on two
// cores (43 s with the video; 20,000 took 62 s): docs/performance.md
constexpr std::size_t kDefaultStrands = 12000;

// The most frames a run may have (--frames, and a resumed run's frames).
constexpr std::uint64_t kMaxFrames = 10000000;
using loosehair::app::parseInteger;
using loosehair::app::parseReal;

// --style and --no-shape-keeping of simulate and render: the style's member
// strands replace the scene's hair (on the scene's head, retargeted by
// (u, v) when the style was made on another one).
void overrideHair(loosehair::SceneDesc& scene, const std::string& style, bool no_shape_keeping) {
  if (!style.empty()) {
    scene.hair.style = style;
    scene.hair.style_data.reset();
  }
  if (no_shape_keeping) {
    scene.sim.shape_keeping = 0.0f;
    scene.shape_keeping_auto = false;
  }
}

void printStyle(const loosehair::BuildReport& b, const std::string& style_file) {
  if (b.style_strands == 0) return;
  char keeping[32] = "off";
  if (b.shape_keeping > 0) std::snprintf(keeping, sizeof keeping, "%.3g Hz", b.shape_keeping);
  std::printf(
      "style: %s: %zu wisps, %zu member strands, %zu points; %zu particles held by ties; "
      "shape keeping %s\n",
      style_file.c_str(), b.style_wisps, b.style_strands, b.style_points, b.tied_particles, keeping);
}

// Makes `dir` ready for a run's frames: created if missing. A directory that
// already holds files is refused unless `overwrite`, and then the frames of
// the earlier run (frame_NNNNN.*, air_NNNNN.ply, and temporary files of an
// interrupted write) are removed first, so old and new frames never mix.
void prepareOutputDirectory(const std::string& dir, bool overwrite, const char* flag) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw std::runtime_error(dir + ": " + flag + " needs a directory, and this is a file");
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create the directory: " + ec.message());
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir, ec)) entries.push_back(entry.path());
  if (ec) throw std::runtime_error(dir + ": cannot list the directory: " + ec.message());
  if (entries.empty()) return;
  if (!overwrite)
    throw std::runtime_error(dir + ": the directory is not empty (" + std::to_string(entries.size()) +
                             " entries, e.g. " + entries.front().filename().string() +
                             "); choose an "
                             "empty one or give --overwrite to replace the frames of the earlier run");
  auto isFrame = [](const std::string& name) {
    for (const char* prefix : {"frame_", "air_", "strands_"}) {
      const std::size_t p = std::strlen(prefix);
      if (name.rfind(prefix, 0) != 0 || name.size() < p + 5) continue;
      bool digits = true;
      for (std::size_t k = p; k < p + 5; ++k) digits = digits && std::isdigit(static_cast<unsigned char>(name[k]));
      if (digits && name[p + 5] == '.') return true;
    }
    return false;
  };
  for (const fs::path& path : entries) {
    if (!isFrame(path.filename().string()) || !fs::is_regular_file(path, ec)) continue;
    if (!fs::remove(path, ec) || ec)
      throw std::runtime_error(path.string() + ": cannot remove the earlier run's frame: " + ec.message());
  }
}

struct Options {
  std::string scene;
  std::optional<int> frames, threads;
  std::optional<std::uint64_t> seed;
  std::string dump_dir, save_state, resume, style, motion, strands_dir;
  int save_every = 0;
  std::size_t strand_count = kDefaultStrands;
  int strand_points = 24;
  bool overwrite = false, allow_expensive = false, no_shape_keeping = false;
};

Options parseSimulate(const std::vector<std::string>& args) {
  Options o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) throw UsageError{a + " needs a value", kSimulateUsage};
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
    else if (a == "--overwrite")
      o.overwrite = true;
    else if (a == "--dump-strands")
      o.strands_dir = value();
    else if (a == "--strands")
      o.strand_count = static_cast<std::size_t>(parseInteger(a, value(), 1, 2000000));
    else if (a == "--strand-points")
      o.strand_points = static_cast<int>(parseInteger(a, value(), 2, 256));
    else if (a == "--allow-expensive")
      o.allow_expensive = true;
    else if (a == "--save-state")
      o.save_state = value();
    else if (a == "--save-every")
      o.save_every = static_cast<int>(parseInteger(a, value(), 1, 10000000));
    else if (a == "--resume")
      o.resume = value();
    else if (a == "--style")
      o.style = value();
    else if (a == "--no-shape-keeping")
      o.no_shape_keeping = true;
    else if (a == "--motion")
      o.motion = value();
    else if (!a.empty() && a[0] == '-')
      throw loosehair::app::unknownOption(a, kSimulateUsage);
    else if (o.scene.empty())
      o.scene = a;
    else
      throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'", kSimulateUsage};
  }
  if (o.scene.empty()) throw UsageError{"simulate needs a scene file", kSimulateUsage};
  if (o.save_every > 0 && o.save_state.empty())
    throw UsageError{"--save-every needs --save-state FILE", kSimulateUsage};
  return o;
}

void drawProgress(int done, int total, double elapsed) {
  constexpr int kWidth = 30;
  const int filled = total > 0 ? done * kWidth / total : kWidth;
  std::fprintf(stderr, "\r[%.*s%*s] frame %d/%d  %.1f s", filled, "##############################", kWidth - filled, "",
               done, total, elapsed);
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

// What the run starts from: the scene, its particles and connections, the
// sampling's lengths, the step, and the warnings.
void printRunStart(const Options& o, const loosehair::SceneDesc& scene, const loosehair::Solver& solver,
                   const loosehair::BuildReport& build, const loosehair::StrandField* strands, double init_seconds) {
  using namespace loosehair;
  const InitReport& r = solver.initReport();
  std::printf("scene: %s (%s), seed %" PRIu64 "\n", scene.name.c_str(), o.scene.c_str(), scene.seed);
  if (build.head_triangles > 0)
    std::printf(
        "head mesh: %zu triangles (signed distance %s, %.2f s), scalp: %zu triangles, %.0f cm^2, "
        "harmonic map %.2f s%s\n",
        build.head_triangles, build.sdf_from_cache ? "from cache" : "baked", build.seconds_sdf, build.scalp_triangles,
        build.scalp_area * 1e4, build.seconds_scalp, build.scalp_mean_value ? " (mean-value weights)" : "");
  std::printf("particles: %zu (%zu roots", r.particles, r.roots);
  if (build.stragglers_pulled > 0) std::printf("; %zu drawn in to the hair nearer the root", build.stragglers_pulled);
  if (build.stragglers_dropped > 0)
    std::printf("; %zu dropped, with nothing nearer the root within reach", build.stragglers_dropped);
  std::printf("), connections: %zu pairs, degree mean %.1f min %u max %u\n", r.connection_pairs, r.mean_degree,
              r.min_degree, r.max_degree);
  std::printf("Poisson radius %.4f m, mean nearest neighbour %.4f m, h1 = %.4f m, h2 = %.4f m\n", build.poisson_radius,
              build.mean_neighbor_distance, solver.params().h1, solver.params().h2);
  std::printf("time step %.4f ms x %d per frame (stable limit %.4f ms), %d threads, init %.2f s\n",
              build.time_step * 1e3, build.substeps, r.stable_time_step * 1e3, solver.threadCount(), init_seconds);
  printStyle(build, scene.hair.style);
  if (strands)
    std::printf("render strands: %zu of %d points, carried by the particles\n", strands->strandCount(),
                o.strand_points);
  for (const std::string& w : build.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (r.unanchored > 0)
    std::fprintf(stderr,
                 "warning: %zu particles cannot reach a root through root-side connections and "
                 "will fall (raise hair.h1_scale a little, or hair.particles)\n",
                 r.unanchored);
  if (build.time_step > r.stable_time_step && !solver.params().implicit_springs)
    std::fprintf(stderr,
                 "warning: the time step %.4f ms is above the stable limit %.4f ms; the scene "
                 "may blow up (use \"substeps\": \"auto\" or more substeps)\n",
                 build.time_step * 1e3, r.stable_time_step * 1e3);
}

// One frame's outputs: the particles (and the air) as PLY, the carried
// strands as PLY and .hair. Returns the seconds the strands took to carry.
double writeFrame(const Options& o, const loosehair::Solver& solver, const loosehair::StrandField* strands,
                  loosehair::StrandSet& strand_set, int f) {
  using namespace loosehair;
  double deform_seconds = 0;
  if (!o.dump_dir.empty()) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.ply", f);
    writeParticlePly((std::filesystem::path(o.dump_dir) / name).string(), solver);
    if (solver.hasWind()) {
      std::snprintf(name, sizeof name, "air_%05d.ply", f);
      writeAirPly((std::filesystem::path(o.dump_dir) / name).string(), solver);
    }
  }
  if (strands) {
    const auto t_def = std::chrono::steady_clock::now();
    strands->deformWorld(solver, strand_set.points, solver.threadCount());
    deform_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_def).count();
    for (const char* ext : {"ply", "hair"}) {
      char name[32];
      std::snprintf(name, sizeof name, "strands_%05d.%s", f, ext);
      writeStrands(strand_set, (std::filesystem::path(o.strands_dir) / name).string());
    }
  }
  return deform_seconds;
}

// The run's timings, a step's stage by stage, and the last step's counts.
void printRunStats(const loosehair::Solver& solver, bool strands, int to_run, double deform_seconds, double wall) {
  using namespace loosehair;
  const InitReport& r = solver.initReport();
  const StepStats& st = solver.stats();
  const double steps = static_cast<double>(st.steps);
  const StageTimes& s = st.sum;
  if (strands && to_run > 0)
    std::printf("render strands: %.2f ms a frame to carry (%d threads)\n", 1e3 * deform_seconds / to_run,
                solver.threadCount());
  std::printf("simulated %.3f s in %" PRIu64 " steps, %.2f s wall (%.1f frames/s)\n", solver.time(), st.steps, wall,
              wall > 0 ? to_run / wall : 0.0);
  std::printf("stage timings, ms per step (mean):\n");
  const struct {
    const char* name;
    double seconds;
  } rows[] = {{"neighbors", s.neighbors},
              {"density", s.density},
              {"springs", s.springs},
              {"hair-hair", s.hair_hair},
              {"external", s.external},
              {"integrate", s.integrate},
              {"strain limit", s.strain_limit},
              {"tethers", s.tethers},
              {"body contacts", s.body_contacts},
              {"directions", s.directions},
              {"air", s.air}};
  const double total = s.total();
  for (const auto& row : rows) {
    if (std::string(row.name) == "air" && !solver.hasWind()) continue;
    std::printf("  %-13s %8.3f  %5.1f%%\n", row.name, row.seconds / steps * 1e3,
                total > 0 ? 100.0 * row.seconds / total : 0.0);
  }
  std::printf("  %-13s %8.3f  (%.2f M particle-steps/s)\n", "total", total / steps * 1e3,
              total > 0 ? static_cast<double>(r.particles) * steps / total * 1e-6 : 0.0);
  std::printf(
      "last step: %zu neighbour pairs, %zu active connections, %zu body contacts, %zu "
      "clamped sides, %zu particles strain-limited\n",
      st.neighbor_pairs / 2, st.active_connections, st.body_contacts, st.clamped_sides, st.strain_limited);
  if (solver.params().implicit_springs)
    std::printf("implicit springs: %d conjugate-gradient iterations, relative residual %.1e, last step\n",
                st.spring_iterations, static_cast<double>(st.spring_residual));
  if (solver.windOnGrid())
    std::printf("wind: air grid of %zu cells, %zu hair particles in it, %d pressure iterations, last step\n",
                st.air_particles, st.coupled_hair, st.air_iterations);
  else if (solver.hasWind())
    std::printf("wind: %zu air particles, %zu hair-air pairs, last step\n", st.air_particles, st.hair_air_pairs);
}

int simulate(const Options& o) {
  using namespace loosehair;
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  if (o.allow_expensive) scene.limits = loosehair::SceneDesc::CostLimits::unlimited();
  overrideHair(scene, o.style, o.no_shape_keeping);
  if (!o.motion.empty()) scene.motion = loadMotion(o.motion);
  // an output that cannot be written is refused before the run, not after it
  if (!o.save_state.empty()) (void)checkOutputTarget(o.save_state);

  const auto t_init = std::chrono::steady_clock::now();
  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  if (!o.dump_dir.empty()) prepareOutputDirectory(o.dump_dir, o.overwrite, "--dump");
  // the render strands are bound to the rest state, before any snapshot
  std::optional<StrandField> strands;
  if (!o.strands_dir.empty()) {
    if (o.strands_dir != o.dump_dir) prepareOutputDirectory(o.strands_dir, o.overwrite, "--dump-strands");
    RenderStrandOptions so;
    so.strands = o.strand_count;
    so.points = o.strand_points;
    strands.emplace(bindSceneStrands(scene, solver.particles(), build, so, solver.threadCount()));
  }
  const double init_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_init).count();
  printRunStart(o, scene, solver, build, strands ? &*strands : nullptr, init_seconds);
  // Frames already run (a resumed snapshot's): the dump's numbering and the
  // scene's frame count go on from there.
  int done = 0;
  if (!o.resume.empty()) {
    loadSnapshot(solver, o.resume);
    const std::uint64_t frames_done = solver.stepCount() / static_cast<std::uint64_t>(build.substeps);
    if (frames_done > kMaxFrames)
      throw std::runtime_error(o.resume + ": the snapshot is " + std::to_string(frames_done) +
                               " frames into its run, more than the " + std::to_string(kMaxFrames) +
                               " frames a run may have");
    done = static_cast<int>(frames_done);
    std::printf("resumed from %s: t = %.4f s, %d frames done\n", o.resume.c_str(), solver.time(), done);
  }
  const int to_run = o.frames ? *o.frames : std::max(0, scene.frames - done);
  auto save = [&] { saveSnapshot(solver, o.save_state); };

  StrandSet strand_set;
  if (strands) strand_set = strands->rest();
  double deform_seconds = 0;
  const bool tty = isatty(fileno(stderr)) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 1; k <= to_run; ++k) {
    const int f = done + k;
    solver.advance(build.substeps);
    deform_seconds += writeFrame(o, solver, strands ? &*strands : nullptr, strand_set, f);
    if (o.save_every > 0 && k % o.save_every == 0 && k < to_run) save();
    if (tty) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      drawProgress(k, to_run, elapsed);
    }
  }
  if (!o.save_state.empty()) {
    save();
    std::printf("state saved: %s (t = %.4f s, %d frames)\n", o.save_state.c_str(), solver.time(), done + to_run);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  printRunStats(solver, strands.has_value(), to_run, deform_seconds, wall);
  std::printf("state-hash: %016" PRIx64 "\n", solver.stateHash());
  return 0;
}

// ---- render -------------------------------------------------------------------
// What render draws unless told otherwise: strands, 2x2 supersampled.
loosehair::render::RenderSettings defaultRenderSettings() {
  loosehair::render::RenderSettings s;
  s.hair = loosehair::render::HairGeometry::Strands;
  s.supersample = 2;
  return s;
}

struct RenderOptions {
  bool light_given = false;     // --light; otherwise the camera's key light
  bool strands_on_gpu = false;  // --strand-carry gpu
  std::optional<double> yaw, pitch, distance, fov;
  std::string scene, out_dir = "render-out", video, camera = "three-quarter", style, motion;
  bool overwrite = false, allow_expensive = false, no_shape_keeping = false;
  std::optional<int> frames, threads;
  std::optional<std::uint64_t> seed;
  int width = 640, height = 480;
  loosehair::app::GLProvider gl = loosehair::app::GLProvider::OSMesa;
  std::size_t strand_count = kDefaultStrands;
  int strand_points = 24;
  bool supersample_given = false;
  loosehair::render::RenderSettings settings = defaultRenderSettings();
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
      if (a == "--frames")
        o.frames = static_cast<int>(parseInteger(a, value(), 1, 10000000));
      else if (a == "--threads")
        o.threads = static_cast<int>(parseInteger(a, value(), 1, 1024));
      else if (a == "--seed")
        o.seed = static_cast<std::uint64_t>(parseInteger(a, value(), 0, INT64_MAX));
      else if (a == "--out")
        o.out_dir = value();
      else if (a == "--overwrite")
        o.overwrite = true;
      else if (a == "--allow-expensive")
        o.allow_expensive = true;
      else if (a == "--video")
        o.video = value();
      else if (a == "--style")
        o.style = value();
      else if (a == "--no-shape-keeping")
        o.no_shape_keeping = true;
      else if (a == "--camera") {
        o.camera = value();
        (void)loosehair::render::Camera::preset(o.camera);
      } else if (a == "--color")
        o.settings.color = loosehair::render::parseHairColor(value());
      else if (a == "--debug")
        o.settings.debug = loosehair::render::parseDebugView(value());
      else if (a == "--no-shadows")
        o.settings.shadows = false;
      else if (a == "--gl") {
        try {
          o.gl = loosehair::app::parseGLProvider(value());
        } catch (const std::invalid_argument& e) {
          throw UsageError{std::string("--gl: ") + e.what(), kRenderUsage};
        }
      } else if (a == "--hair")
        o.settings.hair = loosehair::render::parseHairGeometry(value());
      else if (a == "--shading")
        o.settings.shading = loosehair::render::parseHairShading(value());
      else if (a == "--supersample") {
        o.settings.supersample = static_cast<int>(parseInteger(a, value(), 1, 4));
        o.supersample_given = true;
      } else if (a == "--strands")
        o.strand_count = static_cast<std::size_t>(parseInteger(a, value(), 1, 2000000));
      else if (a == "--strand-points")
        o.strand_points = static_cast<int>(parseInteger(a, value(), 2, 256));
      else if (a == "--yaw")
        o.yaw = parseReal(a, value(), -360, 360);
      else if (a == "--pitch")
        o.pitch = parseReal(a, value(), -89, 89);
      else if (a == "--distance")
        o.distance = parseReal(a, value(), 0.05, 100);
      else if (a == "--fov")
        o.fov = parseReal(a, value(), 5, 150);
      else if (a == "--no-lod")
        o.settings.strand_lod = false;
      else if (a == "--strand-carry") {
        const std::string v = value();
        if (v != "cpu" && v != "gpu")
          throw UsageError{"--strand-carry must be cpu or gpu, got '" + v + "'", kRenderUsage};
        o.strands_on_gpu = v == "gpu";
      } else if (a == "--light") {
        const std::string v = value();
        float c[3];
        if (std::sscanf(v.c_str(), "%f,%f,%f", &c[0], &c[1], &c[2]) != 3 || !std::isfinite(c[0] + c[1] + c[2]) ||
            !(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-12f))
          throw UsageError{"--light needs a non-zero direction x,y,z, got '" + v + "'"};
        o.settings.light_direction = glm::vec3(c[0], c[1], c[2]);
        o.light_given = true;
      } else if (a == "--size") {
        const std::string v = value();
        const auto x = v.find('x');
        if (x == std::string::npos) throw UsageError{"--size needs WxH, got '" + v + "'"};
        o.width = static_cast<int>(parseInteger("--size width", v.substr(0, x), 16, 8192));
        o.height = static_cast<int>(parseInteger("--size height", v.substr(x + 1), 16, 8192));
      } else if (a == "--motion")
        o.motion = value();
      else if (!a.empty() && a[0] == '-')
        throw loosehair::app::unknownOption(a, kRenderUsage);
      else if (o.scene.empty())
        o.scene = a;
      else
        throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'", kRenderUsage};
    } catch (const loosehair::render::RenderError& e) {
      throw UsageError{a + ": " + e.what(), kRenderUsage};
    }
  }
  if (o.scene.empty()) throw UsageError{"render needs a scene file", kRenderUsage};
  // billboards are drawn as before unless supersampling is asked for
  if (o.settings.hair == loosehair::render::HairGeometry::Billboards && !o.supersample_given)
    o.settings.supersample = 1;
  return o;
}

int renderScene(const RenderOptions& o) {
  using namespace loosehair;
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  if (o.allow_expensive) scene.limits = loosehair::SceneDesc::CostLimits::unlimited();
  overrideHair(scene, o.style, o.no_shape_keeping);
  if (!o.motion.empty()) scene.motion = loadMotion(o.motion);
  const int frames = o.frames.value_or(scene.frames);
  std::string ffmpeg;
  if (!o.video.empty()) {
    (void)loosehair::app::checkVideoName(o.video, "--video");
    const std::filesystem::path parent = std::filesystem::absolute(o.video).parent_path();
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec || !std::filesystem::is_directory(parent))
      throw std::runtime_error(o.video + ": --video: cannot create the directory " + parent.string() +
                               (ec ? ": " + ec.message() : ""));
    const auto found = loosehair::app::findProgram("ffmpeg");
    if (!found)
      throw std::runtime_error("--video needs ffmpeg, which is not installed (scripts/install-deps.sh installs it)");
    ffmpeg = *found;
  }

  BuildReport build;
  Solver solver = buildSolver(scene, &build);
  printStyle(build, scene.hair.style);
  for (const std::string& w : build.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  prepareOutputDirectory(o.out_dir, o.overwrite, "--out");
  app::HeadlessGL gl(o.width, o.height, o.gl);
  render::Renderer renderer;
  const app::DrawableBodies bodies = app::drawableBodies(scene);
  renderer.setBodies(&bodies.head, bodies.torso ? &*bodies.torso : nullptr);
  render::Camera camera = render::Camera::preset(o.camera);
  if (o.yaw) camera.yaw_deg = static_cast<float>(*o.yaw);
  if (o.pitch) camera.pitch_deg = static_cast<float>(*o.pitch);
  if (o.distance) camera.distance = static_cast<float>(*o.distance);
  if (o.fov) camera.fov_deg = static_cast<float>(*o.fov);
  render::RenderSettings settings = o.settings;
  if (!o.light_given) settings.light_direction = camera.keyLight();  // lit from whichever side it is seen
  std::optional<StrandField> strands;
  if (o.settings.hair == render::HairGeometry::Strands) {
    RenderStrandOptions so;
    so.strands = o.strand_count;
    so.points = o.strand_points;
    strands.emplace(bindSceneStrands(scene, solver.particles(), build, so, solver.threadCount()));
  }
  std::unique_ptr<render::GpuStrandCarry> gpu_carry;
  if (strands && o.strands_on_gpu) {
    std::string why;
    if (!render::gpuStrandCarrySupported(&why)) throw std::runtime_error("--strand-carry gpu: " + why);
    gpu_carry = std::make_unique<render::GpuStrandCarry>(*strands);
  }
  std::printf("scene: %s, %zu particles, %d frames of %dx%d, camera %s, %s\n", scene.name.c_str(),
              solver.particles().size(), frames, o.width, o.height, o.camera.c_str(), gl.renderer().c_str());
  if (strands)
    std::printf("hair: %zu strands of %d points carried by the particles%s, %s shading, %dx%d supersampling\n",
                strands->strandCount(), o.strand_points, gpu_carry ? " (by a compute shader)" : "",
                o.settings.shading == render::HairShading::Marschner ? "Marschner" : "Kajiya-Kay",
                o.settings.supersample, o.settings.supersample);
  else
    std::printf("hair: a billboard a particle, %dx%d supersampling\n", o.settings.supersample, o.settings.supersample);

  const bool tty = isatty(fileno(stderr)) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  render::FrameTimes sum;
  double sim_seconds = 0, deform_seconds = 0;
  for (int f = 1; f <= frames; ++f) {
    const auto ts = std::chrono::steady_clock::now();
    solver.advance(build.substeps);
    sim_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
    render::FrameInput input = render::frameFromSolver(solver, build.mean_neighbor_distance);
    if (strands) {
      const auto td = std::chrono::steady_clock::now();
      if (gpu_carry) {
        gpu_carry->carry(solver.particles().position, solver.particles().direction, solver.bodyPlacements(),
                         render::headToWorld(solver.head().pose), solver.threadCount());
        gpu_carry->wait();  // for the timing
        input.strand_buffer = gpu_carry->buffer();
        input.strand_buffer_points = gpu_carry->points();
        input.strand_mean_length = gpu_carry->meanLength();
      } else {
        strands->deformWorld(solver, input.strand_points, solver.threadCount());
      }
      input.strand_points_each = o.strand_points;
      deform_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - td).count();
    }
    renderer.render(input, camera, settings, o.width, o.height);
    const auto& t = renderer.lastTimes();
    sum.sort += t.sort;
    sum.upload += t.upload;
    sum.light_pass += t.light_pass;
    sum.camera_pass += t.camera_pass;
    sum.resolve += t.resolve;
    sum.strands_drawn = t.strands_drawn;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    app::writePng((std::filesystem::path(o.out_dir) / name).string(), gl.pixels(), o.width, o.height);
    if (tty) drawProgress(f, frames, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "rendered %d frames in %.2f s (%.1f frames/s); per frame: simulation %.1f ms, strands %.1f ms, "
      "sort %.2f ms, upload %.1f ms, light pass %.1f ms, camera pass %.1f ms, resolve %.1f ms\n",
      frames, wall, frames / wall, 1e3 * sim_seconds / frames, 1e3 * deform_seconds / frames, 1e3 * sum.sort / frames,
      1e3 * sum.upload / frames, 1e3 * sum.light_pass / frames, 1e3 * sum.camera_pass / frames,
      1e3 * sum.resolve / frames);
  if (strands)
    std::printf("strands: %zu of %zu drawn from the camera in the last frame (level of detail%s)\n", sum.strands_drawn,
                strands->strandCount(), settings.strand_lod ? "" : " off");
  std::printf("frames: %s/frame_00001.png ... frame_%05d.png\n", o.out_dir.c_str(), frames);
  if (!o.video.empty()) {
    loosehair::app::encodeVideo(ffmpeg, o.out_dir, o.video, scene.frame_rate);
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
    if (args[0] == "--version" || args[0] == "version") {
      std::printf("loosehair %s\n", LOOSEHAIR_VERSION);
      return 0;
    }
    loosehair::removeTemporariesOnSignal();
    const std::vector<std::string> rest =
        loosehair::app::splitFlagValues(std::vector<std::string>(args.begin() + 1, args.end()));
    const bool help = std::find(rest.begin(), rest.end(), std::string("--help")) != rest.end() ||
                      std::find(rest.begin(), rest.end(), std::string("-h")) != rest.end();
    if (args[0] == "simulate") {
      if (help) return std::fputs(kSimulateUsage, stdout) < 0 ? 1 : 0;
      return simulate(parseSimulate(rest));
    }
    if (args[0] == "render") {
      if (help) return std::fputs(kRenderUsage, stdout) < 0 ? 1 : 0;
      return renderScene(parseRender(rest));
    }
    if (args[0] == "style") {
      if (help) return std::fputs(loosehair::app::kStyleUsage, stdout) < 0 ? 1 : 0;
      return loosehair::app::styleCommand(rest);
    }
    if (args[0].rfind('-', 0) == 0) throw loosehair::app::unknownOption(args[0], kUsage);
    throw UsageError{"unknown command '" + args[0] + "' (simulate, render or style)"};
  } catch (const UsageError& e) {
    const char* usage = e.usage;
    if (!usage && !args.empty())
      usage = args[0] == "simulate" ? kSimulateUsage
              : args[0] == "render" ? kRenderUsage
              : args[0] == "style"  ? loosehair::app::kStyleUsage
                                    : kUsage;
    if (!usage) usage = kUsage;
    std::fprintf(stderr, "loosehair: %s\n\n%s", e.message.c_str(), usage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair: error: %s\n", e.what());
    return 1;
  }
}
