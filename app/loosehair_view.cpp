// loosehair-view: plays a scene in a window (GLFW, OpenGL 3.3 core).
//
//   loosehair-view SCENE [--size WxH] [--camera PRESET] [--color C] [--threads T]
//                        [--seed S] [--paused] [--frames N [--screenshot FILE.png]]
//
// Each displayed frame advances the simulation by one scene frame (the
// scene's substeps), so playback runs as fast as the machine simulates; the
// title shows frames/s and how that compares with real time. Links GLFW and
// libGL as the GL provider, never OSMesa (SPEC §7.4).
//
// Mouse: left drag orbits, scroll zooms. Keys: see kControls.
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "png.hpp"
#include "scene_bodies.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <GL/gl.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace loosehair;

constexpr const char* kUsage =
    "usage: loosehair-view SCENE [--size WxH] [--camera PRESET] [--color C] [--threads T]\n"
    "                            [--seed S] [--paused] [--frames N [--screenshot FILE.png]]\n"
    "\n"
    "Plays SCENE in a window, one scene frame per displayed frame.\n"
    "  --size WxH          window size (default 960x720)\n"
    "  --camera PRESET     front, side, back, three-quarter (default three-quarter)\n"
    "  --color C           black, brown, blonde, red (default brown)\n"
    "  --threads T         simulation threads (default: all cores)\n"
    "  --seed S            sampling seed (default: the scene's)\n"
    "  --paused            start paused\n"
    "  --frames N          close after N displayed frames (for scripts and tests)\n"
    "  --screenshot FILE   with --frames: save the last frame as a PNG\n";

constexpr const char* kControls =
    "controls: left drag orbit, scroll zoom | space play/pause, N (or right arrow) one frame,\n"
    "          R restart, S shadows, C hair colour, D debug view, 1-4 camera presets,\n"
    "          L light from the camera, P screenshot, H this help, Esc or Q quit\n";

struct UsageError {
  std::string message;
};

struct ViewOptions {
  std::string scene;
  int width = 960, height = 720;
  std::string camera = "three-quarter";
  render::RenderSettings settings;
  std::optional<int> threads;
  std::optional<std::uint64_t> seed;
  bool paused = false;
  std::optional<int> frames;
  std::string screenshot;
};

long long parseInteger(const std::string& what, const std::string& text, long long lo, long long hi) {
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || v < lo || v > hi)
    throw UsageError{what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got '" + text + "'"};
  return v;
}

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
      } else if (a == "--paused") {
        o.paused = true;
      } else if (a == "--frames") {
        o.frames = static_cast<int>(parseInteger("--frames", value(), 1, 10000000));
      } else if (a == "--screenshot") {
        o.screenshot = value();
      } else if (!a.empty() && a[0] == '-') {
        throw UsageError{"unknown option " + a};
      } else if (o.scene.empty()) {
        o.scene = a;
      } else {
        throw UsageError{"more than one scene given: '" + o.scene + "' and '" + a + "'"};
      }
    } catch (const render::RenderError& e) {
      throw UsageError{a + ": " + e.what()};
    }
  }
  if (o.scene.empty()) throw UsageError{"loosehair-view needs a scene file"};
  if (!o.screenshot.empty() && !o.frames) throw UsageError{"--screenshot needs --frames N"};
  return o;
}

// The window's frame as RGBA8, top row first (read before the buffers swap).
std::vector<std::uint8_t> readFramebuffer(int width, int height) {
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  std::vector<std::uint8_t> out(rows.size());
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height; ++y)
    std::memcpy(&out[static_cast<std::size_t>(y) * row], &rows[static_cast<std::size_t>(height - 1 - y) * row], row);
  for (std::size_t p = 3; p < out.size(); p += 4) out[p] = 255;  // opaque picture
  return out;
}

// Share of pixels that differ from the background colour (a blank window
// gives 0): printed with screenshots, so scripts can tell a picture was drawn.
double drawnFraction(const std::vector<std::uint8_t>& rgba, glm::vec3 background) {
  const int bg[3] = {static_cast<int>(std::lround(background.r * 255.0f)),
                     static_cast<int>(std::lround(background.g * 255.0f)),
                     static_cast<int>(std::lround(background.b * 255.0f))};
  std::size_t drawn = 0;
  for (std::size_t p = 0; p + 3 < rgba.size(); p += 4) {
    int diff = 0;
    for (int c = 0; c < 3; ++c) diff = std::max(diff, std::abs(static_cast<int>(rgba[p + c]) - bg[c]));
    drawn += diff > 8 ? 1 : 0;
  }
  return rgba.empty() ? 0.0 : static_cast<double>(drawn) / static_cast<double>(rgba.size() / 4);
}

// Everything the window's callbacks change.
struct ViewState {
  render::Camera camera;
  render::RenderSettings settings;
  bool paused = false, step_once = false, restart = false, screenshot = false;
  bool light_from_camera = false;
  bool dragging = false;
  double last_x = 0, last_y = 0;
};

template <class E>
E next(E value, E last) {
  return static_cast<E>((static_cast<int>(value) + 1) % (static_cast<int>(last) + 1));
}

const char* colorName(render::HairColor c) {
  switch (c) {
    case render::HairColor::Black: return "black";
    case render::HairColor::Brown: return "brown";
    case render::HairColor::Blonde: return "blonde";
    case render::HairColor::Red: return "red";
  }
  return "?";
}

const char* debugName(render::DebugView d) {
  switch (d) {
    case render::DebugView::None: return "none (hair)";
    case render::DebugView::Density: return "density";
    case render::DebugView::Speed: return "speed";
    case render::DebugView::Connections: return "connections";
    case render::DebugView::Directions: return "directions";
  }
  return "?";
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  auto& s = *static_cast<ViewState*>(glfwGetWindowUserPointer(window));
  switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(window, GLFW_TRUE); break;
    case GLFW_KEY_SPACE: s.paused = !s.paused; break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT: s.paused = true, s.step_once = true; break;
    case GLFW_KEY_R: s.restart = true; break;
    case GLFW_KEY_S:
      s.settings.shadows = !s.settings.shadows;
      std::printf("shadows %s\n", s.settings.shadows ? "on" : "off");
      break;
    case GLFW_KEY_C:
      s.settings.color = next(s.settings.color, render::HairColor::Red);
      std::printf("hair colour %s\n", colorName(s.settings.color));
      break;
    case GLFW_KEY_D:
      s.settings.debug = next(s.settings.debug, render::DebugView::Directions);
      std::printf("debug view %s\n", debugName(s.settings.debug));
      break;
    case GLFW_KEY_L:
      s.light_from_camera = !s.light_from_camera;
      std::printf("light %s\n", s.light_from_camera ? "from the camera" : "fixed");
      break;
    case GLFW_KEY_P: s.screenshot = true; break;
    case GLFW_KEY_H: std::fputs(kControls, stdout); break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4: {
      static const char* presets[] = {"front", "side", "back", "three-quarter"};
      const render::Camera p = render::Camera::preset(presets[key - GLFW_KEY_1]);
      s.camera.yaw_deg = p.yaw_deg;
      s.camera.pitch_deg = p.pitch_deg;
      break;
    }
    default: break;
  }
}

void onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
  auto& s = *static_cast<ViewState*>(glfwGetWindowUserPointer(window));
  if (button != GLFW_MOUSE_BUTTON_LEFT) return;
  s.dragging = action == GLFW_PRESS;
  glfwGetCursorPos(window, &s.last_x, &s.last_y);
}

void onCursor(GLFWwindow* window, double x, double y) {
  auto& s = *static_cast<ViewState*>(glfwGetWindowUserPointer(window));
  if (!s.dragging) return;
  s.camera.yaw_deg -= static_cast<float>(x - s.last_x) * 0.4f;
  s.camera.pitch_deg = std::clamp(s.camera.pitch_deg + static_cast<float>(y - s.last_y) * 0.4f, -85.0f, 85.0f);
  s.last_x = x, s.last_y = y;
}

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  auto& s = *static_cast<ViewState*>(glfwGetWindowUserPointer(window));
  s.camera.distance = std::clamp(s.camera.distance * static_cast<float>(std::pow(0.9, dy)), 0.1f, 5.0f);
}

struct GlfwSession {
  GlfwSession() {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) throw std::runtime_error("cannot open a window: GLFW could not initialise (no display?)");
  }
  ~GlfwSession() { glfwTerminate(); }
};

int run(const ViewOptions& o) {
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  const app::DrawableBodies bodies = app::drawableBodies(scene);

  GlfwSession glfw;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  std::unique_ptr<GLFWwindow, void (*)(GLFWwindow*)> window(
      glfwCreateWindow(o.width, o.height, ("loosehair - " + scene.name).c_str(), nullptr, nullptr),
      glfwDestroyWindow);
  if (!window) throw std::runtime_error("cannot open a window with an OpenGL 3.3 core context");
  glfwMakeContextCurrent(window.get());
  glfwSwapInterval(1);

  render::Renderer renderer;
  renderer.setBodies(&bodies.head, bodies.torso ? &*bodies.torso : nullptr);

  ViewState state;
  state.camera = render::Camera::preset(o.camera);
  state.settings = o.settings;
  state.paused = o.paused;
  glfwSetWindowUserPointer(window.get(), &state);
  glfwSetKeyCallback(window.get(), onKey);
  glfwSetMouseButtonCallback(window.get(), onMouseButton);
  glfwSetCursorPosCallback(window.get(), onCursor);
  glfwSetScrollCallback(window.get(), onScroll);

  BuildReport build;
  auto solver = std::make_unique<Solver>(buildSolver(scene, &build));
  std::printf("scene: %s, %zu particles, %d substeps a frame at %g frames/s, %s\n", scene.name.c_str(),
              solver->particles().size(), build.substeps, scene.frame_rate,
              reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  std::fputs(kControls, stdout);

  const glm::vec3 fixed_light = state.settings.light_direction;
  int shown = 0, shots = 0;
  double fps = 0, sim_ms = 0;
  auto last_title = std::chrono::steady_clock::now();
  int frames_since_title = 0;
  double sim_since_title = 0;
  while (!glfwWindowShouldClose(window.get())) {
    glfwPollEvents();
    if (state.restart) {
      state.restart = false;
      solver = std::make_unique<Solver>(buildSolver(scene, &build));
      std::printf("restarted\n");
    }
    if (!state.paused || state.step_once) {
      const auto t0 = std::chrono::steady_clock::now();
      solver->advance(build.substeps);
      sim_since_title += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      state.step_once = false;
    }
    state.settings.light_direction = state.light_from_camera ? glm::normalize(state.camera.eye() - state.camera.target)
                                                             : fixed_light;
    int width = 0, height = 0;
    glfwGetFramebufferSize(window.get(), &width, &height);
    if (width > 0 && height > 0) {
      const render::FrameInput input = render::frameFromSolver(*solver, build.mean_neighbor_distance);
      renderer.render(input, state.camera, state.settings, width, height);
      ++shown;
      const bool last = o.frames && shown >= *o.frames;
      if (state.screenshot || (last && !o.screenshot.empty())) {
        char name[40];
        std::snprintf(name, sizeof name, "loosehair-%05d.png", ++shots);
        const std::string path = last && !o.screenshot.empty() ? o.screenshot : std::string(name);
        const std::vector<std::uint8_t> pixels = readFramebuffer(width, height);
        app::writePng(path, pixels, width, height);
        std::printf("screenshot: %s (%dx%d, %.0f%% of the picture drawn over the background)\n", path.c_str(),
                    width, height, 100.0 * drawnFraction(pixels, state.settings.background));
        state.screenshot = false;
      }
      glfwSwapBuffers(window.get());
      if (last) break;
    }
    ++frames_since_title;
    const auto now = std::chrono::steady_clock::now();
    const double span = std::chrono::duration<double>(now - last_title).count();
    if (span >= 0.5) {
      fps = frames_since_title / span;
      sim_ms = 1e3 * sim_since_title / frames_since_title;
      char title[256];
      std::snprintf(title, sizeof title, "loosehair - %s - %.1f frames/s (%.2fx real time, simulation %.0f ms) - t = %.2f s%s",
                    scene.name.c_str(), fps, state.paused ? 0.0 : fps / scene.frame_rate, sim_ms, solver->time(),
                    state.paused ? " - paused" : "");
      glfwSetWindowTitle(window.get(), title);
      last_title = now;
      frames_since_title = 0;
      sim_since_title = 0;
    }
  }
  std::printf("showed %d frames, simulated %.2f s; state-hash: %016llx\n", shown, solver->time(),
              static_cast<unsigned long long>(solver->stateHash()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::fputs(kUsage, stdout);
    std::fputs(kControls, stdout);
    return 0;
  }
  try {
    return run(parseOptions(args));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "loosehair-view: %s\n\n%s", e.message.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair-view: %s\n", e.what());
    return 1;
  }
}
