// loosehair-view: plays a scene in a window (GLFW, OpenGL 3.3 core) with a
// panel (Dear ImGui) to run it, move the head and change the picture.
//
//   loosehair-view [SCENE] [--size WxH] [--camera PRESET] [--color C] [--threads T]
//                  [--seed S] [--paused] [--frames N [--screenshot FILE.png]]
//
// The simulation runs on its own thread (viewer/simulation_thread.hpp) at
// the scene's fixed step, paced to real time; the window draws the newest
// finished frame and handles input every displayed frame however slow the
// simulation is. Links GLFW and libGL as the GL provider, never OSMesa
// (SPEC §7.4).
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/renderer.hpp"
#include "png.hpp"
#include "scene_bodies.hpp"
#include "viewer/head_drag.hpp"
#include "viewer/panel.hpp"
#include "viewer/simulation_thread.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <GL/gl.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace loosehair;

constexpr const char* kUsage =
    "usage: loosehair-view [SCENE] [--size WxH] [--camera PRESET] [--color C] [--threads T]\n"
    "                              [--seed S] [--paused] [--frames N [--screenshot FILE.png]]\n"
    "\n"
    "Plays SCENE (default: the bundled data/scenes/hang.json) in a window with a\n"
    "panel, in real time at most (the panel sets the speed).\n"
    "  --size WxH          window size (default 960x720)\n"
    "  --camera PRESET     front, side, back, three-quarter (default three-quarter)\n"
    "  --color C           black, brown, blonde, red (default brown)\n"
    "  --threads T         simulation threads (default: all cores)\n"
    "  --seed S            sampling seed (default: the scene's)\n"
    "  --paused            start paused\n"
    "  --frames N          simulate N frames, draw the last and close (scripts, tests)\n"
    "  --screenshot FILE   with --frames: save that frame as a PNG\n"
    "\n";

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

// The bundled default scene: data/scenes/hang.json under the working
// directory, else in the source tree the program was built from.
std::string defaultScene() {
  const std::string here = "data/scenes/hang.json";
  if (std::filesystem::exists(here)) return here;
  return LOOSEHAIR_DEFAULT_SCENE;
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
  if (o.scene.empty()) o.scene = defaultScene();
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

struct GlfwSession {
  GlfwSession() {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) throw std::runtime_error("cannot open a window: GLFW could not initialise (no display?)");
  }
  ~GlfwSession() { glfwTerminate(); }
};

// What the callbacks need: the view, the head drag and the simulation.
struct Window {
  viewer::ViewState view;
  viewer::HeadDrag head;
  viewer::SimulationThread* sim = nullptr;
  bool orbiting = false, turning = false;
  double last_x = 0, last_y = 0;
};

Window& of(GLFWwindow* w) { return *static_cast<Window*>(glfwGetWindowUserPointer(w)); }

template <class E>
E next(E value, E last) {
  return static_cast<E>((static_cast<int>(value) + 1) % (static_cast<int>(last) + 1));
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  if (ImGui::GetIO().WantCaptureKeyboard) return;
  Window& w = of(window);
  viewer::ViewState& v = w.view;
  switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: v.quit = true; break;
    case GLFW_KEY_SPACE: w.sim->setPaused(!w.sim->paused()); break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT: w.sim->stepOnce(); break;
    case GLFW_KEY_R: w.sim->restart(w.sim->scene()); break;
    case GLFW_KEY_S: v.settings.shadows = !v.settings.shadows; break;
    case GLFW_KEY_C: v.settings.color = next(v.settings.color, render::HairColor::Red); break;
    case GLFW_KEY_D: v.settings.debug = next(v.settings.debug, render::DebugView::Directions); break;
    case GLFW_KEY_L: v.light_from_camera = !v.light_from_camera; break;
    case GLFW_KEY_P: v.screenshot = true; break;
    case GLFW_KEY_TAB: v.show_panel = !v.show_panel; break;
    case GLFW_KEY_H: std::fputs(viewer::kShortcuts, stdout); break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4: {
      static const char* presets[] = {"front", "side", "back", "three-quarter"};
      const render::Camera p = render::Camera::preset(presets[key - GLFW_KEY_1]);
      v.camera.yaw_deg = p.yaw_deg;
      v.camera.pitch_deg = p.pitch_deg;
      break;
    }
    default: break;
  }
}

void onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
  Window& w = of(window);
  if (action == GLFW_PRESS && ImGui::GetIO().WantCaptureMouse) return;
  glfwGetCursorPos(window, &w.last_x, &w.last_y);
  if (button == GLFW_MOUSE_BUTTON_LEFT) w.orbiting = action == GLFW_PRESS;
  if (button == GLFW_MOUSE_BUTTON_RIGHT) w.turning = action == GLFW_PRESS;
}

void onCursor(GLFWwindow* window, double x, double y) {
  Window& w = of(window);
  const double dx = x - w.last_x, dy = y - w.last_y;
  w.last_x = x, w.last_y = y;
  if (w.orbiting) {
    w.view.camera.yaw_deg -= static_cast<float>(dx) * 0.4f;
    w.view.camera.pitch_deg = std::clamp(w.view.camera.pitch_deg + static_cast<float>(dy) * 0.4f, -85.0f, 85.0f);
  }
  if (w.turning) {
    const bool move = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                      glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    w.head.drag(dx, dy, move, w.view.camera);
    w.sim->setHeadTarget(w.head.pose());
  }
}

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  if (ImGui::GetIO().WantCaptureMouse) return;
  Window& w = of(window);
  w.view.camera.distance = std::clamp(w.view.camera.distance * static_cast<float>(std::pow(0.9, dy)), 0.1f, 5.0f);
}

// Dear ImGui on the window, for the lifetime of this object.
struct ImGuiSession {
  explicit ImGuiSession(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsLight();
    ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains the callbacks set before
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~ImGuiSession() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
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

  // --frames: run exactly to that frame, then draw it and stop
  viewer::SimulationThread sim(scene, o.paused || o.frames.has_value());
  if (o.frames) {
    sim.setSpeed(0.0);
    sim.runUntil(*o.frames);
  }
  Window w{viewer::ViewState{}, viewer::HeadDrag(viewer::neckPivot(bodies.head)), &sim};
  w.view.camera = render::Camera::preset(o.camera);
  w.view.settings = o.settings;
  {
    const glm::vec3 l = glm::normalize(o.settings.light_direction);
    w.view.light_yaw_deg = glm::degrees(std::atan2(l.x, l.z));
    w.view.light_pitch_deg = glm::degrees(std::asin(l.y));
  }
  glfwSetWindowUserPointer(window.get(), &w);
  glfwSetKeyCallback(window.get(), onKey);
  glfwSetMouseButtonCallback(window.get(), onMouseButton);
  glfwSetCursorPosCallback(window.get(), onCursor);
  glfwSetScrollCallback(window.get(), onScroll);
  ImGuiSession imgui(window.get());
  viewer::Panel panel(sim, w.head);

  std::printf("scene: %s, %zu particles, %d substeps a frame at %g frames/s, %s\n", scene.name.c_str(),
              sim.latest()->particles, sim.buildReport().substeps, scene.frame_rate,
              reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  std::fputs(viewer::kShortcuts, stdout);

  int shown = 0, shots = 0;
  double fps = 0;
  auto last_count = std::chrono::steady_clock::now();
  int frames_since = 0;
  bool done = false;
  while (!glfwWindowShouldClose(window.get()) && !w.view.quit && !done) {
    glfwPollEvents();
    if (const std::string e = sim.takeError(); !e.empty()) {
      w.view.message = e;
      std::fprintf(stderr, "loosehair-view: %s\n", e.c_str());
    }
    std::shared_ptr<const viewer::PublishedFrame> frame = sim.latest();
    if (o.frames) {  // wait for the last frame, then show it
      if (frame->frame < *o.frames && sim.waitForFrame(*o.frames)) frame = sim.latest();
      done = true;
    }
    viewer::ViewState& v = w.view;
    v.settings.light_direction = v.light_from_camera ? glm::normalize(v.camera.eye() - v.camera.target)
                                                     : viewer::lightFromAngles(v.light_yaw_deg, v.light_pitch_deg);
    int width = 0, height = 0;
    glfwGetFramebufferSize(window.get(), &width, &height);
    if (width <= 0 || height <= 0) continue;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    panel.draw(v, *frame, fps);
    ImGui::Render();
    renderer.render(frame->input, v.camera, v.settings, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++shown;
    if (v.screenshot || (done && !o.screenshot.empty())) {
      char name[40];
      std::snprintf(name, sizeof name, "loosehair-%05d.png", ++shots);
      const std::string path = done && !o.screenshot.empty() ? o.screenshot : std::string(name);
      const std::vector<std::uint8_t> pixels = readFramebuffer(width, height);
      try {
        app::writePng(path, pixels, width, height);
        std::printf("screenshot: %s (%dx%d, %.0f%% of the picture drawn over the background)\n", path.c_str(),
                    width, height, 100.0 * drawnFraction(pixels, v.settings.background));
        v.message.clear();
      } catch (const std::exception& e) {
        v.message = e.what();
        std::fprintf(stderr, "loosehair-view: %s\n", e.what());
      }
      v.screenshot = false;
    }
    glfwSwapBuffers(window.get());
    ++frames_since;
    const auto now = std::chrono::steady_clock::now();
    const double span = std::chrono::duration<double>(now - last_count).count();
    if (span >= 0.5) {
      fps = frames_since / span;
      last_count = now;
      frames_since = 0;
    }
  }
  const std::shared_ptr<const viewer::PublishedFrame> last = sim.latest();
  std::printf("showed %d frames, simulated %.2f s; state-hash: %016llx\n", shown, last->time,
              static_cast<unsigned long long>(last->state_hash));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::fputs(kUsage, stdout);
    std::fputs(loosehair::viewer::kShortcuts, stdout);
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
