// The viewer's command line: its options and their parsing.
#include "viewer/view_options.hpp"

#include "cli_args.hpp"
#include "loosehair/file_io.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include <filesystem>

namespace loosehair::viewer {

const char* const kUsage =
    "usage: loosehair-view [SCENE] [--size WxH] [--camera PRESET] [--color C] [--threads T]\n"
    "                              [--seed S] [--paused] [--frames N [--screenshot FILE.png]]\n"
    "                              [--script FILE] [--seconds S] [--no-shadows] [--hair H]\n"
    "                              [--strand-carry auto|cpu|gpu] [--playing-strands N]\n"
    "\n"
    "Plays SCENE (default: the bundled data/scenes/hang.json) in a window with a\n"
    "panel, in real time at most (the panel sets the speed).\n"
    "  --size WxH          window size (default 960x720)\n"
    "  --camera PRESET     front, side, back, three-quarter (default three-quarter)\n"
    "  --color C           black, brown, blonde, red (default brown)\n"
    "  --threads T         simulation threads (default: all cores)\n"
    "  --seed S            sampling seed (default: the scene's)\n"
    "  --paused            start paused\n"
    "  --no-shadows        start without self-shadowing\n"
    "  --hair H            strands (default: thin strands the particles carry) or\n"
    "                      billboards (one a particle); the panel switches\n"
    "  --playing-strands N at most N strands drawn while the hair moves, each standing\n"
    "                      for several (all when paused or recording; 0: always all;\n"
    "                      default 4000 on software OpenGL, all where a GPU draws)\n"
    "  --strand-carry C    where the strands are carried: auto (default: by a compute\n"
    "                      shader where OpenGL has them, 4.3 or later, software OpenGL\n"
    "                      too; else on a thread of the CPU), cpu, or gpu\n"
    "  --frames N          simulate N frames, draw the last and close (scripts, tests)\n"
    "  --screenshot FILE   with --frames: save that frame as a PNG\n"
    "  --script FILE       play FILE's timed input events and exit (docs/viewer-scripts.md)\n"
    "  --seconds S         play for S seconds of wall time, then print the frames drawn\n"
    "                      per second and the real-time factor, and close (measuring)\n"
    "  --allow-expensive   open scenes beyond the cost limits (more than 2 million\n"
    "                      particles, 2000 steps a frame, meshes of 10 million\n"
    "                      triangles, ...: loosehair simulate --help lists them),\n"
    "                      this one and any opened from the viewer\n"
    "\n";

namespace {

long long parseInteger(const std::string& what, const std::string& text, long long lo, long long hi) {
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || v < lo || v > hi)
    throw UsageError{what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                     text + "'"};
  return v;
}

// The bundled default scene: data/scenes/hang.json under the working
// directory, else in the source tree the program was built from.
std::string defaultScene() {
  const std::string here = "data/scenes/hang.json";
  if (std::filesystem::exists(here)) return here;
  return LOOSEHAIR_DEFAULT_SCENE;
}

}  // namespace

ViewOptions parseOptions(const std::vector<std::string>& args) {
  ViewOptions o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= args.size()) throw UsageError{a + " needs a value"};
      return args[++k];
    };
    try {
      if (a == "--size") {
        const std::string v = value();
        const auto x = v.find('x');
        if (x == std::string::npos) throw UsageError{"--size needs WxH, got '" + v + "'"};
        o.width = static_cast<int>(parseInteger("--size width", v.substr(0, x), 64, 8192));
        o.height = static_cast<int>(parseInteger("--size height", v.substr(x + 1), 64, 8192));
      } else if (a == "--camera") {
        o.camera = value();
        (void)render::Camera::preset(o.camera);
      } else if (a == "--color") {
        o.settings.color = render::parseHairColor(value());
      } else if (a == "--threads") {
        o.threads = static_cast<int>(parseInteger("--threads", value(), 1, 1024));
      } else if (a == "--seed") {
        o.seed = static_cast<std::uint64_t>(parseInteger("--seed", value(), 0, INT64_MAX));
      } else if (a == "--no-shadows") {
        o.settings.shadows = false;
      } else if (a == "--hair") {
        o.settings.hair = render::parseHairGeometry(value());
        o.hair_given = true;
      } else if (a == "--strand-carry") {
        o.strand_carry = value();
        if (o.strand_carry != "auto" && o.strand_carry != "cpu" && o.strand_carry != "gpu")
          throw UsageError{"--strand-carry must be auto, cpu or gpu, got '" + o.strand_carry + "'"};
      } else if (a == "--playing-strands") {
        o.strand_budget = static_cast<int>(parseInteger("--playing-strands", value(), 0, 10000000));
      } else if (a == "--allow-expensive") {
        o.allow_expensive = true;
      } else if (a == "--paused") {
        o.paused = true;
      } else if (a == "--frames") {
        o.frames = static_cast<int>(parseInteger("--frames", value(), 1, 10000000));
      } else if (a == "--screenshot") {
        o.screenshot = value();
      } else if (a == "--script") {
        o.script = value();
      } else if (a == "--seconds") {
        const std::string v = value();
        char* end = nullptr;
        const double sec = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(sec > 0 && sec <= 86400))
          throw UsageError{"--seconds must be a number of seconds in (0, 86400], got '" + v + "'"};
        o.seconds = sec;
      } else if (!a.empty() && a[0] == '-') {
        throw UsageError{app::unknownOption(a, kUsage).message};
      } else if (o.scene.empty()) {
        o.scene = a;
      } else {
        throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'"};
      }
    } catch (const render::RenderError& e) {
      throw UsageError{a + ": " + e.what()};
    }
  }
  if (o.scene.empty()) o.scene = defaultScene();
  if (!o.screenshot.empty() && !o.frames) throw UsageError{"--screenshot needs --frames N"};
  if (!o.script.empty() && o.frames) throw UsageError{"--script and --frames do not go together"};
  return o;
}

}  // namespace loosehair::viewer
