// loosehair-view: plays a scene in a window (GLFW, OpenGL 3.3 core) with a
// panel (Dear ImGui) to run it, move the head and change the picture.
//
//   loosehair-view [SCENE] [--size WxH] [--camera PRESET] [--color C] [--threads T]
//                  [--seed S] [--paused] [--frames N [--screenshot FILE.png]]
//                  [--script FILE]
//
// The simulation runs on its own thread (viewer/simulation_thread.hpp) at
// the scene's fixed step, paced to real time; the window draws the newest
// finished frame and handles input every displayed frame however slow the
// simulation is. Links GLFW and libGL as the GL provider, never OSMesa
// (method.md §7.4).
#include "loosehair/loosehair.hpp"
#include "loosehair/render/frame.hpp"
#include "loosehair/render/gl_loader.hpp"
#include "loosehair/render/renderer.hpp"
#include "cli_args.hpp"
#include "png.hpp"
#include "scene_bodies.hpp"
#include "loosehair/render/overlay.hpp"
#include "viewer/controller.hpp"
#include "viewer/head_drag.hpp"
#include "viewer/panel.hpp"
#include "viewer/script.hpp"
#include "viewer/simulation_thread.hpp"
#include "viewer/viewer_values.hpp"
#include "viewer/window_strands.hpp"

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
#include <cstdlib>
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
  std::string script;
  std::optional<double> seconds;
  bool allow_expensive = false;
  std::string strand_carry = "auto";
  bool hair_given = false;  // --hair
  std::optional<int> strand_budget;  // --playing-strands
};

// Strands drawn while the hair moves on software OpenGL (llvmpipe): about
// 4 frames a second with all 12,000 at 1280x720, 2 cores; see
// docs/performance.md.
constexpr int kSoftwareStrandBudget = 4000;

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

// What the input handlers need. Scripted input calls the same handlers with
// `scripted` set: it addresses the 3-D view, never the panel.
struct Window {
  viewer::Controller* c = nullptr;
  GLFWwindow* glfw = nullptr;
  bool orbiting = false, turning = false, brushing = false, shift = false;
  bool styling_drag = false;  // a left drag of a control point, arrow or key strand
  bool stroking = false;      // a left drag of a strand brush (StylingSession::Tool)
  glm::vec2 stroke_at{0.0f};  // where the stroke's last dab was
  glm::vec2 anchor_px{0.0f};  // a script's anchored drag: where its anchor was seen at the press
  // per mouse button: the 3-D view took its press (the panel sees nothing
  // of it until the release)
  bool view_holds[GLFW_MOUSE_BUTTON_LAST + 1] = {};
  double last_x = 0, last_y = 0;
  int width = 1, height = 1;  // of the framebuffer
  // input to picture: the first head move not yet on screen (when, and the
  // newest simulated frame then: it lands in a later one)
  std::optional<std::chrono::steady_clock::time_point> input_at;
  std::int64_t input_frame = -1;
};

Window& of(GLFWwindow* w) { return *static_cast<Window*>(glfwGetWindowUserPointer(w)); }

template <class E>
E next(E value, E last) {
  return static_cast<E>((static_cast<int>(value) + 1) % (static_cast<int>(last) + 1));
}

render::Ray rayAt(const Window& w, double x, double y) {
  return w.c->view().camera.ray(x, y, w.width, w.height);
}

void key(Window& w, int key, int mods, bool scripted) {
  if (!scripted && ImGui::GetIO().WantCaptureKeyboard) return;
  viewer::Controller& c = *w.c;
  viewer::ViewState& v = c.view();
  viewer::StylingSession* st = c.mode() == viewer::Mode::Styling ? c.styling() : nullptr;
  const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0, shift = (mods & GLFW_MOD_SHIFT) != 0;
  if (st) {
    switch (key) {
      case GLFW_KEY_Z:
        if (ctrl) {
          (shift ? st->redo() : st->undo());
          c.clearError();
        }
        return;
      case GLFW_KEY_T: st->axis = StylingAxis::Tangent; return;
      case GLFW_KEY_G: st->axis = StylingAxis::Normal; return;
      case GLFW_KEY_B: st->axis = StylingAxis::Binormal; return;
      case GLFW_KEY_UP: c.attempt([&] { st->moveSelected(0.005f); }); return;
      case GLFW_KEY_DOWN: c.attempt([&] { st->moveSelected(-0.005f); }); return;
      case GLFW_KEY_DELETE: c.attempt([&] { st->deleteSelectedPoint(); }); return;
      default: break;
    }
  }
  switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: v.quit = true; break;
    case GLFW_KEY_SPACE: c.sim().setPaused(!c.sim().paused()); break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT: c.sim().stepOnce(); break;
    case GLFW_KEY_R: c.restart(); break;
    case GLFW_KEY_S: v.settings.shadows = !v.settings.shadows; break;
    case GLFW_KEY_C:
      v.settings.color = next(v.settings.color, render::HairColor::Red);
      v.settings.custom_color.reset();
      break;
    case GLFW_KEY_D: v.settings.debug = next(v.settings.debug, render::DebugView::Directions); break;
    case GLFW_KEY_L: v.light_from_camera = !v.light_from_camera; break;
    case GLFW_KEY_P: v.screenshot = true; break;
    case GLFW_KEY_TAB: v.show_panel = !v.show_panel; break;
    case GLFW_KEY_H: v.show_help = !v.show_help; break;
    case GLFW_KEY_F2:
      if (c.mode() == viewer::Mode::Styling)
        c.enterSimulate();
      else
        c.enterStyling();
      break;
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


// How near (m, at the depth of what is picked) the pointer must be to a
// control point, an arrow or a key strand: about 8 pixels at 720 rows.
float pickTolerance(viewer::Controller& c) { return 0.01f * c.view().camera.distance; }

void mouseButton(Window& w, int button, bool press, bool shift, double x, double y) {
  w.last_x = x, w.last_y = y;
  w.shift = shift;
  viewer::Controller& c = *w.c;
  viewer::StylingSession* st = c.mode() == viewer::Mode::Styling ? c.styling() : nullptr;
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    if (press && st && st->tool == viewer::StylingSession::Tool::Tie) {  // a tie where the wisps pass
      const render::Ray r = rayAt(w, x, y);
      // the key strands within the brush circle (its radius in metres at
      // the camera's distance), or at least those picked at the click
      const render::Camera& cam = c.view().camera;
      const float brush = st->brush_pixels * 2.0f * cam.distance *
                          std::tan(0.5f * glm::radians(cam.fov_deg)) / static_cast<float>(std::max(1, w.height));
      c.attempt([&] {
        st->tieAt(r, std::max(3.0f * pickTolerance(c), brush));
        c.note("tied: the ring goes round the key strands there");
      });
      return;
    }
    if (press && st && st->tool != viewer::StylingSession::Tool::Select) {  // a strand brush stroke
      w.stroking = true;
      w.stroke_at = glm::vec2(static_cast<float>(x), static_cast<float>(y));
      c.attempt([&] { st->brushDab(c.view().camera, w.width, w.height, w.stroke_at, w.stroke_at, shift); });
      return;
    }
    if (press && st) {
      // a control point, arrow or key strand under the cursor is selected
      // and dragged; on the scalp the brush paints; elsewhere the camera
      // orbits
      const render::Ray r = rayAt(w, x, y);
      if (st->beginDrag(r, pickTolerance(c))) {
        w.styling_drag = true;
        return;
      }
      w.brushing = st->brush(r);
      w.orbiting = !w.brushing;
      return;
    }
    w.orbiting = press;
    if (!press) {
      w.brushing = false;
      if (w.styling_drag && c.styling()) c.styling()->endDrag();
      w.styling_drag = false;
      if (w.stroking && c.styling()) c.attempt([&] { c.styling()->endStroke(); });
      w.stroking = false;
    }
  }
  if (button == GLFW_MOUSE_BUTTON_RIGHT && !st) w.turning = press;
}

void cursor(Window& w, double x, double y) {
  const double dx = x - w.last_x, dy = y - w.last_y;
  w.last_x = x, w.last_y = y;
  viewer::Controller& c = *w.c;
  render::Camera& cam = c.view().camera;
  if (w.stroking && c.styling()) {
    const glm::vec2 at(static_cast<float>(x), static_cast<float>(y));
    c.attempt([&] { c.styling()->brushDab(cam, w.width, w.height, at, w.stroke_at, w.shift); });
    w.stroke_at = at;
  } else if (w.styling_drag && c.styling()) {
    c.styling()->dragTo(rayAt(w, x, y));
  } else if (w.brushing && c.styling()) {
    c.styling()->brush(rayAt(w, x, y));
  } else if (w.orbiting) {
    cam.yaw_deg -= static_cast<float>(dx) * 0.4f;
    cam.pitch_deg = std::clamp(cam.pitch_deg + static_cast<float>(dy) * 0.4f, -85.0f, 85.0f);
  }
  if (c.mode() == viewer::Mode::Styling && c.styling() && !w.styling_drag && !w.brushing && !w.orbiting &&
      !w.stroking)
    c.styling()->hoverAt(rayAt(w, x, y), pickTolerance(c));
  if (w.turning) {
    c.head().drag(dx, dy, w.shift, cam);
    c.sim().setHeadTarget(c.head().pose());
    if (!w.input_at) {
      w.input_at = std::chrono::steady_clock::now();
      w.input_frame = c.sim().latest()->frame;
    }
  }
}

// Whether window point (x, y) (window coordinates, as GLFW reports the
// cursor) is on the panel or another window of the interface, as last drawn,
// or a popup (an open combo box) waits for a click.
bool onInterface(const Window& w, double x, double y) {
  if (ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId)) return true;
  for (const glm::vec4& r : w.c->view().ui_rects)
    if (x >= r.x && x < r.z && y >= r.y && y < r.w) return true;
  return false;
}

// A press belongs to the panel or to the 3-D view, decided where the cursor
// is at the press (not by the last drawn frame's hover, which lags by a
// frame); its drag and release go to the same one. Scrolls likewise.
void onMouseButton(GLFWwindow* window, int button, int action, int mods) {
  Window& w = of(window);
  if (button < 0 || button > GLFW_MOUSE_BUTTON_LAST) return;
  double wx = 0, wy = 0;
  glfwGetCursorPos(window, &wx, &wy);
  const bool press = action == GLFW_PRESS;
  if (press) w.view_holds[button] = !onInterface(w, wx, wy);
  if (!w.view_holds[button]) {
    ImGui_ImplGlfw_MouseButtonCallback(window, button, action, mods);
    return;
  }
  if (!press) w.view_holds[button] = false;
  // window coordinates to framebuffer pixels (equal but on high-density screens)
  int ww = 1, wh = 1;
  glfwGetWindowSize(window, &ww, &wh);
  const double x = wx * static_cast<double>(w.width) / std::max(ww, 1);
  const double y = wy * static_cast<double>(w.height) / std::max(wh, 1);
  mouseButton(w, button, press, (mods & GLFW_MOD_SHIFT) != 0, x, y);
}

void onCursor(GLFWwindow* window, double x, double y) {
  Window& w = of(window);
  int ww = 1, wh = 1;
  glfwGetWindowSize(window, &ww, &wh);
  w.shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  cursor(w, x * w.width / std::max(ww, 1), y * w.height / std::max(wh, 1));
}

void onScroll(GLFWwindow* window, double dx, double dy) {
  Window& w = of(window);
  double x = 0, y = 0;
  glfwGetCursorPos(window, &x, &y);
  if (onInterface(w, x, y)) {
    ImGui_ImplGlfw_ScrollCallback(window, dx, dy);
    return;
  }
  render::Camera& cam = w.c->view().camera;
  cam.distance = std::clamp(cam.distance * static_cast<float>(std::pow(0.9, dy)), 0.1f, 5.0f);
}

void onKey(GLFWwindow* window, int k, int scancode, int action, int mods) {
  ImGui_ImplGlfw_KeyCallback(window, k, scancode, action, mods);
  if (action == GLFW_PRESS || action == GLFW_REPEAT) key(of(window), k, mods, false);
}

// After the backend has read the mouse for a new frame: a button the 3-D
// view holds is up as far as the panel knows (the backend polls the buttons).
void hideViewPressesFromInterface(const Window& w) {
  ImGuiIO& io = ImGui::GetIO();
  for (int b = 0; b < IM_ARRAYSIZE(io.MouseDown) && b <= GLFW_MOUSE_BUTTON_LAST; ++b)
    if (w.view_holds[b]) io.MouseDown[b] = false;
}

// Dear ImGui on the window, for the lifetime of this object.
struct ImGuiSession {
  explicit ImGuiSession(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsLight();
    // the window's callbacks (run()) hand ImGui what is its own
    ImGui_ImplGlfw_InitForOpenGL(window, false);
    glfwSetCharCallback(window, ImGui_ImplGlfw_CharCallback);
    glfwSetWindowFocusCallback(window, ImGui_ImplGlfw_WindowFocusCallback);
    glfwSetCursorEnterCallback(window, ImGui_ImplGlfw_CursorEnterCallback);
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~ImGuiSession() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
};

int glfwKeyNamed(const std::string& name, const std::string& where) {
  static const std::pair<const char*, int> named[] = {
      {"space", GLFW_KEY_SPACE}, {"right", GLFW_KEY_RIGHT}, {"left", GLFW_KEY_LEFT}, {"up", GLFW_KEY_UP},
      {"down", GLFW_KEY_DOWN},   {"tab", GLFW_KEY_TAB},     {"escape", GLFW_KEY_ESCAPE}, {"delete", GLFW_KEY_DELETE},
      {"f2", GLFW_KEY_F2}};
  for (const auto& [n, k] : named)
    if (name == n) return k;
  if (name.size() == 1 && std::isalnum(static_cast<unsigned char>(name[0])))
    return std::toupper(static_cast<unsigned char>(name[0]));  // GLFW_KEY_A.. and _0.. are ASCII
  throw std::runtime_error(where + ": unknown key \"" + name + "\"");
}

// Hair yaw: the mean turn of the hair about the vertical through the head's
// pivot since the script started (a scripted drag shows the lag with it).
double meanYawDeg(const std::vector<glm::vec3>& now, const std::vector<glm::vec3>& start, glm::vec3 pivot) {
  double s = 0, c = 0;
  const std::size_t n = std::min(now.size(), start.size());
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec2 a(start[i].x - pivot.x, start[i].z - pivot.z), b(now[i].x - pivot.x, now[i].z - pivot.z);
    if (glm::length(a) < 0.03f || glm::length(b) < 0.03f) continue;  // near the axis the angle means little
    const double ang = std::atan2(static_cast<double>(a.x * b.y - a.y * b.x), static_cast<double>(glm::dot(a, b)));
    s += std::sin(ang), c += std::cos(ang);
  }
  return -glm::degrees(std::atan2(s, c));  // yaw about +Y, as the head's
}

struct ScriptRun {
  std::deque<viewer::ScriptEvent> events;
  std::vector<glm::vec3> start;  // the hair when the script began
  int warmup = 2;                // displayed frames before the first event (the panel lays itself out)
};

// One script event; false when the script asks to stop.
bool runEvent(const viewer::ScriptEvent& e, Window& w, viewer::Panel& panel, ScriptRun& run) {
  viewer::Controller& c = *w.c;
  viewer::ViewState& v = c.view();
  const nlohmann::json& a = e.args;
  const std::string& what = e.what;
  auto text = [&](const char* f) { return a.at(f).get<std::string>(); };
  if (a.value("window", false) || what == "hover" || what == "scroll") {
    // as a person's input: the pointer moves there and the window's own
    // handlers decide whether the panel or the view gets it
    const double x = a.contains("x") ? a["x"].get<double>() : a["at"][0].get<double>();
    const double y = a.contains("x") ? a["y"].get<double>() : a["at"][1].get<double>();
    int ww = 1, wh = 1;
    glfwGetWindowSize(w.glfw, &ww, &wh);
    const double wx = x * ww / std::max(w.width, 1), wy = y * wh / std::max(w.height, 1);
    glfwSetCursorPos(w.glfw, wx, wy);
    if (what == "scroll") {
      onScroll(w.glfw, 0.0, a["dy"].get<double>());
    } else if (what == "hover" || what == "mouse_move") {
      onCursor(w.glfw, wx, wy);
    } else {
      const int button = a["button"] == "left" ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT;
      onMouseButton(w.glfw, button, what == "mouse_down" ? GLFW_PRESS : GLFW_RELEASE,
                    a["shift"].get<bool>() ? GLFW_MOD_SHIFT : 0);
    }
  } else if (what == "mouse_down" || what == "mouse_up" || what == "mouse_move") {
    const int button = a["button"] == "left" ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT;
    double x = a["x"].get<double>(), y = a["y"].get<double>();
    if (a.contains("anchor")) {  // pixels from a control point, arrow or key strand, as seen at the press
      if (what == "mouse_down") {
        viewer::StylingSession* st = c.mode() == viewer::Mode::Styling ? c.styling() : nullptr;
        if (!st) throw std::runtime_error(e.where + ": an anchored drag needs the styling mode");
        const std::size_t wi = a["anchor"][0].get<std::size_t>(), k = a["anchor"][1].get<std::size_t>();
        const std::string on = a["on"].get<std::string>();
        glm::vec3 p;
        try {
          if (on == "point") {
            (void)st->handlePoint(wi, k, st->axis);  // names a wisp or point that does not exist
            p = st->style().wisps[wi].key_strand[k];
          } else if (on == "strand") {
            p = st->strandPoint(wi, k);
          } else {
            p = st->handlePoint(wi, k, on == "tangent" ? StylingAxis::Tangent : on == "normal" ? StylingAxis::Normal
                                                                                           : StylingAxis::Binormal);
          }
        } catch (const std::exception& err) {
          throw std::runtime_error(e.where + ": anchor: " + err.what());
        }
        w.anchor_px = c.view().camera.pixel(p, w.width, w.height);
      }
      x += w.anchor_px.x;
      y += w.anchor_px.y;
    }
    if (what == "mouse_move") {
      w.shift = a["shift"].get<bool>();
      cursor(w, x, y);
    } else {
      mouseButton(w, button, what == "mouse_down", a["shift"].get<bool>(), x, y);
    }
  } else if (what == "key") {
    key(w, glfwKeyNamed(text("key"), e.where), (a.value("ctrl", false) ? GLFW_MOD_CONTROL : 0) |
                                                (a.value("shift", false) ? GLFW_MOD_SHIFT : 0), true);
  } else if (what == "set") {
    const std::string name = text("name");
    if (!a["value"].is_number() && !a["value"].is_boolean()) throw std::runtime_error(e.where + ": value must be a number");
    const double raw = a["value"].is_boolean() ? (a["value"].get<bool>() ? 1.0 : 0.0) : a["value"].get<double>();
    if (!viewer::isViewerValue(name)) {
      c.setParam(name, raw, e.where);  // a solver parameter, checked as the scene file's
    } else {
      // values of the styling session (only in the styling mode) and of the
      // wisps the brush creates, by their script names
      using Session = viewer::StylingSession;
      static const std::pair<const char*, float Session::*> session[] = {
          {"styling.brush_radius", &Session::brush_radius},     {"styling.drag_falloff", &Session::drag_falloff},
          {"styling.wisp_length", &Session::new_wisp_length},   {"styling.settle_seconds", &Session::settle_seconds},
          {"styling.brush_pixels", &Session::brush_pixels},     {"styling.brush_strength", &Session::brush_strength},
          {"styling.curl_radius", &Session::curl_radius},       {"styling.curl_period", &Session::curl_period}};
      static const std::pair<const char*, float WispParams::*> new_wisp[] = {
          {"styling.density", &WispParams::density},     {"styling.offset_radius", &WispParams::offset_radius},
          {"styling.blend", &WispParams::blend},         {"styling.edge_ramp", &WispParams::edge_ramp},
          {"styling.length_variation", &WispParams::length_variation}};
      const auto* in_session = std::find_if(std::begin(session), std::end(session),
                                            [&](const auto& f) { return name == f.first; });
      const auto* in_wisp = std::find_if(std::begin(new_wisp), std::end(new_wisp),
                                         [&](const auto& f) { return name == f.first; });
      if (in_session != std::end(session) && !c.styling())
        throw std::runtime_error(e.where + ": " + name + " is set in styling mode");
      const double value = viewer::checkViewerValue(name, raw, e.where);
      if (in_session != std::end(session))
        c.styling()->*(in_session->second) = static_cast<float>(value);
      else if (in_wisp != std::end(new_wisp))
        c.new_wisp.*(in_wisp->second) = static_cast<float>(value);
      else if (name == "speed")
        c.sim().setSpeed(value);
      else if (name == "particles")
        c.pending().hair.particles = static_cast<int>(value);
      else if (name == "seed")
        c.pending().seed = static_cast<std::uint64_t>(value);
      else if (name == "wind.speed")
        c.pending().wind.speed = static_cast<float>(value);
      else if (name == "shake.amplitude_deg")
        panel.shake_amplitude_deg = static_cast<float>(value);
      else if (name == "shake.frequency_hz")
        panel.shake_frequency_hz = static_cast<float>(value);
      else if (name == "styling.step_mm")
        panel.move_step_mm = static_cast<float>(value);
    }
  } else if (what == "view") {
    const std::string name = text("name");
    const nlohmann::json& val = a["value"];
    if (name == "camera") {
      v.camera = render::Camera::preset(val.get<std::string>());
    } else if (name == "shadows") {
      v.settings.shadows = val.get<bool>();
    } else if (name == "hair") {
      c.setHair(render::parseHairGeometry(val.get<std::string>()));
    } else if (name == "shading") {
      v.settings.shading = render::parseHairShading(val.get<std::string>());
    } else if (name == "debug") {
      v.settings.debug = render::parseDebugView(val.get<std::string>());
    } else if (name == "color") {
      v.settings.color = render::parseHairColor(val.get<std::string>());
    } else if (name == "panel") {
      v.show_panel = val.get<bool>();
    } else if (name == "section") {
      v.open_section = val.get<std::string>();
    } else if (name == "grid") {
      v.show_grid = val.get<bool>();
      c.sim().setPublishGrid(v.show_grid);
    } else if (name == "air") {
      v.show_air = val.get<bool>();
      c.sim().setPublishAir(v.show_air);
    } else if (name == "select" && c.styling()) {  // [wisp, control point], as a click on it
      if (!val.is_array() || val.size() != 2 || !val[0].is_number_unsigned() || !val[1].is_number_unsigned())
        throw std::runtime_error(e.where + ": select needs [wisp, control point]");
      viewer::StylingSession& st = *c.styling();
      st.wisp = val[0].get<std::size_t>();
      st.point = val[1].get<std::size_t>();
      st.clampSelection();
    } else if (name == "axis" && c.styling()) {
      const std::string ax = val.get<std::string>();
      if (ax != "tangent" && ax != "normal" && ax != "binormal")
        throw std::runtime_error(e.where + ": axis must be tangent, normal or binormal");
      c.styling()->axis = ax == "tangent" ? StylingAxis::Tangent : ax == "normal" ? StylingAxis::Normal : StylingAxis::Binormal;
    } else if (name == "tool" && c.styling()) {
      using Tool = viewer::StylingSession::Tool;
      const std::string t = val.is_string() ? val.get<std::string>() : std::string();
      static const std::pair<const char*, Tool> tools[] = {{"select", Tool::Select}, {"comb", Tool::Comb},
                                                           {"length", Tool::Length}, {"puff", Tool::Puff},
                                                           {"smooth", Tool::Smooth}, {"curl", Tool::Curl},
                                                           {"tie", Tool::Tie}};
      const auto* found = std::find_if(std::begin(tools), std::end(tools), [&](const auto& e2) { return t == e2.first; });
      if (found == std::end(tools))
        throw std::runtime_error(e.where + ": tool must be select, comb, length, puff, smooth, curl or tie");
      c.styling()->tool = found->second;
    } else if (name == "coverage" && c.styling()) {
      if (!val.is_boolean()) throw std::runtime_error(e.where + ": coverage must be true or false");
      c.styling()->show_coverage = val.get<bool>();
    } else if (name == "mirror" && c.styling()) {
      if (!val.is_boolean()) throw std::runtime_error(e.where + ": mirror must be true or false");
      c.styling()->mirror_editing = val.get<bool>();
    } else {
      throw std::runtime_error(e.where + ": unknown view setting \"" + name + "\"");
    }
  } else if (what == "press") {
    const std::string name = text("name");
    viewer::StylingSession* st = c.styling();
    auto need = [&]() -> viewer::StylingSession& {
      if (!st || c.mode() != viewer::Mode::Styling) throw std::runtime_error(e.where + ": \"" + name + "\" needs the styling mode");
      return *st;
    };
    const float step = 1e-3f * panel.move_step_mm;
    if (name == "play") c.sim().setPaused(false);
    else if (name == "pause") c.sim().setPaused(true);
    else if (name == "step") c.sim().stepOnce();
    else if (name == "restart") c.restart();
    else if (name == "shake" || name == "nod") c.shake(panel.shake_amplitude_deg, panel.shake_frequency_hz, name == "nod");
    else if (name == "centre_head") c.centreHead();
    else if (name == "wind_on" || name == "wind_off") c.setWind(name == "wind_on");
    else if (name == "stop_recording") c.stopRecording();
    else if (name == "styling") c.enterStyling();
    else if (name == "simulate") c.enterSimulate();
    else if (name == "create_wisp") c.attempt([&] { need().createWispFromBrush(c.new_wisp); });
    else if (name == "set_region") c.attempt([&] { need().setRegionFromBrush(); });
    else if (name == "clear_brush") need().clearBrush();
    else if (name == "move_plus") c.attempt([&] { need().moveSelected(step); });
    else if (name == "move_minus") c.attempt([&] { need().moveSelected(-step); });
    else if (name == "add_point") c.attempt([&] { need().addPointAfterSelected(); });
    else if (name == "delete_point") c.attempt([&] { need().deleteSelectedPoint(); });
    else if (name == "delete_wisp") c.attempt([&] { need().deleteSelectedWisp(); });
    else if (name == "copy") c.attempt([&] { need().copySelected(); });
    else if (name == "paste") c.attempt([&] { need().pasteOnSelected(); });
    else if (name == "mirror") c.attempt([&] { need().mirrorSelected(); });
    else if (name == "tie") c.attempt([&] { need().tieAtSelected(0.015f); });
    else if (name == "apply_params") c.attempt([&] {
      viewer::StylingSession& ss = need();
      if (!ss.wisp) throw StyleError("select a wisp first to set its parameters");
      ss.editor().setParams(*ss.wisp, c.new_wisp);
    });
    else if (name == "undo") need().undo(), c.clearError();
    else if (name == "redo") need().redo(), c.clearError();
    else if (name == "settle") c.attempt([&] {  // a script waits for it: the next event sees the settled style
      viewer::StylingSession& ss = need();
      ss.startSettle();
      if (ss.finishSettle(true)) c.note("settled the style: the key strands lie where the hair came to rest");
    });
    else throw std::runtime_error(e.where + ": no panel action called \"" + name + "\"");
  } else if (what == "open") {
    c.open(text("path"));
  } else if (what == "screenshot") {
    v.screenshot = true;
    v.screenshot_path = text("path");
  } else if (what == "hash") {
    const std::shared_ptr<const viewer::PublishedFrame> f = c.sim().latest();
    const glm::vec3 pivot(c.head().pivot());
    std::printf("script: %s frame %lld t %.4f head-yaw %.2f hair-yaw %.2f camera-distance %.4f state-hash %016llx\n",
                a.value("label", "hash").c_str(), static_cast<long long>(f->frame), f->time, c.head().eulerDeg().x,
                meanYawDeg(f->input.position, run.start, pivot), static_cast<double>(v.camera.distance),
                static_cast<unsigned long long>(f->state_hash));
    std::fflush(stdout);
  } else if (what == "save_motion") {
    c.saveHeadMotion(text("path"));
  } else if (what == "save_snapshot") {
    c.saveSnapshot(text("path"));
  } else if (what == "load_snapshot") {
    c.loadSnapshot(text("path"));
  } else if (what == "save_style") {
    c.attempt([&] {
      if (!c.styling()) throw std::runtime_error("there is no style to save: enter the styling mode first");
      c.styling()->save(text("path"));
      c.note("saved the style to " + text("path"));
    });
  } else if (what == "record") {
    c.startRecording(text("dir"), a.value("video", ""));
  } else if (what == "quit") {
    return false;
  }
  return true;
}

// The overlay of this frame: styling previews, arrows, debug cells and air.
void buildOverlay(viewer::Controller& c, const viewer::PublishedFrame& frame, render::OverlayLines& hidden,
                  render::OverlayLines& on_top) {
  hidden.clear();
  on_top.clear();
  viewer::ViewState& v = c.view();
  if (c.mode() == viewer::Mode::Styling && c.styling()) {
    c.styling()->overlay(hidden, on_top);
    return;
  }
  const glm::vec3 centre = glm::vec3(frame.input.head_pose[3]) + glm::vec3(0.0f, 0.05f, 0.0f);
  if (frame.wind && c.pending().has_wind && v.show_wind_arrow) {
    const glm::vec3 d = glm::normalize(c.pending().wind.direction);
    const glm::vec3 above = centre + glm::vec3(0.0f, 0.13f, 0.0f);  // over the head, along the wind
    on_top.arrow(above - 0.1f * d, above + 0.1f * d, glm::vec4(0.1f, 0.45f, 0.95f, 1.0f));
  }
  if (!v.light_from_camera && v.show_light_arrow && v.show_panel) {
    const glm::vec3 l = v.settings.light_direction;
    on_top.arrow(centre + 0.2f * l, centre + 0.12f * l, glm::vec4(0.95f, 0.8f, 0.1f, 1.0f));
  }
  if (v.show_grid) {
    const float h = frame.grid_cell;
    const glm::mat4& m = frame.input.head_pose;
    for (const glm::vec3& lo : frame.neighbor_cells) {
      glm::vec3 corner[8];
      for (int k = 0; k < 8; ++k)
        corner[k] = glm::vec3(m * glm::vec4(lo + h * glm::vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1), 1.0f));
      for (int k = 0; k < 8; ++k)
        for (int bit : {1, 2, 4})
          if (!(k & bit)) hidden.line(corner[k], corner[k | bit], glm::vec4(0.2f, 0.5f, 0.2f, 0.35f));
    }
  }
  if (v.show_air)
    for (const glm::vec3& p : frame.air) hidden.cross(p, 0.003f, glm::vec4(0.1f, 0.4f, 0.9f, 0.6f));
}

int run(const ViewOptions& o) {
  SceneDesc scene = loadScene(o.scene);
  if (o.seed) scene.seed = *o.seed;
  if (o.threads) scene.sim.threads = *o.threads;
  if (o.allow_expensive) scene.limits = SceneDesc::CostLimits::unlimited();
  std::optional<ScriptRun> script;
  if (!o.script.empty()) {
    script.emplace();
    script->events = viewer::loadScript(o.script);
  }
  auto bodies = std::make_unique<app::DrawableBodies>(app::drawableBodies(scene));

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
  render::loadGL([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); });
  glfwSwapInterval(script || o.frames ? 0 : 1);

  render::Renderer renderer;
  render::OverlayRenderer overlay;
  renderer.setBodies(&bodies->head, bodies->torso ? &*bodies->torso : nullptr);

  // --frames and scripts: run exactly to the frames asked for, as fast as possible
  const bool exact = o.frames.has_value() || script.has_value();
  viewer::SimulationThread sim(scene, o.paused || exact);
  if (exact) sim.setSpeed(0.0);
  if (o.frames) sim.runUntil(*o.frames);
  viewer::ViewState view;
  viewer::HeadDrag head(viewer::neckPivot(bodies->head));
  viewer::Controller controller(sim, view, head, o.scene);
  controller.pending().sim = sim.latest()->params;
  view.camera = render::Camera::preset(o.camera);
  view.settings = o.settings;
  const GLubyte* gl_name = glGetString(GL_RENDERER);
  const std::string gl_renderer = gl_name ? reinterpret_cast<const char*>(gl_name) : "";
  // strands by default; software OpenGL draws a third of them while the
  // hair moves (all when paused), so that the window keeps answering
  const bool software_gl = gl_renderer.empty() || render::softwareRenderer(gl_renderer);
  if (!o.hair_given) view.settings.hair = render::HairGeometry::Strands;
  view.playing_strand_budget = o.strand_budget ? *o.strand_budget : software_gl ? kSoftwareStrandBudget : 0;
  if (view.settings.hair == render::HairGeometry::Strands) controller.setHair(render::HairGeometry::Strands);
  {
    const glm::vec3 l = glm::normalize(o.settings.light_direction);
    view.light_yaw_deg = glm::degrees(std::atan2(l.x, l.z));
    view.light_pitch_deg = glm::degrees(std::asin(l.y));
  }
  Window w;
  w.c = &controller;
  w.glfw = window.get();
  glfwSetWindowUserPointer(window.get(), &w);
  glfwSetKeyCallback(window.get(), onKey);
  glfwSetMouseButtonCallback(window.get(), onMouseButton);
  glfwSetCursorPosCallback(window.get(), onCursor);
  glfwSetScrollCallback(window.get(), onScroll);
  ImGuiSession imgui(window.get());
  viewer::Panel panel(controller);
  panel.gl_renderer = gl_renderer;
  // the strands carried by a compute shader wherever OpenGL runs one: on
  // a GPU it costs next to nothing, and even on llvmpipe the window showed
  // current strands (0 frames behind, against 15 from the carry thread,
  // which competes with the simulation for the cores) at the same rate
  {
    std::string why;
    const bool can = render::gpuStrandCarrySupported(&why);
    if (o.strand_carry == "gpu" && !can) {
      std::fprintf(stderr, "loosehair-view: --strand-carry gpu: %s\n", why.c_str());
      return 2;
    }
    sim.setStrandsOnGpu(o.strand_carry == "gpu" || (o.strand_carry == "auto" && can));
  }
  viewer::WindowStrands window_strands;  // in this window's context
  if (script) script->start = sim.latest()->input.position;

  std::printf("scene: %s, %zu particles, %d substeps a frame at %g frames/s, %s\n", scene.name.c_str(),
              sim.latest()->particles, sim.buildReport().substeps, scene.frame_rate,
              gl_renderer.c_str());
  std::printf("press H in the window for the shortcuts\n");

  int shown = 0, shots = 0;
  double fps = 0;
  auto last_count = std::chrono::steady_clock::now();
  int frames_since = 0;
  bool done = false;
  const auto started = std::chrono::steady_clock::now();
  const double started_sim = sim.latest()->time;
  std::int64_t last_carried = -1;  // the strands shown: how many frames carried, how late
  int latency_count = 0;           // input to picture (Window::input_at)
  double latency_sum = 0, latency_max = 0;
  int carried_shown = 0, strand_frames = 0;
  double carry_ms_sum = 0, strand_lag_sum = 0;
  render::FrameTimes pass_sum;  // the renderer's passes, summed over the frames drawn
  std::size_t strands_drawn_sum = 0;
  std::uint64_t generation = 0;
  std::unique_ptr<app::DrawableBodies> styling_bodies;
  const viewer::StylingSession* styling_bodies_of = nullptr;
  render::OverlayLines hidden, on_top;
  while (!glfwWindowShouldClose(window.get()) && !view.quit && !done) {
    glfwPollEvents();
    if (const std::string e = sim.takeError(); !e.empty()) controller.fail(e);
    if (sim.latest()->generation != generation) {  // another scene: its head
      generation = sim.latest()->generation;
      bodies = std::make_unique<app::DrawableBodies>(app::drawableBodies(sim.scene()));
      head.setPivot(viewer::neckPivot(bodies->head));
      // the panel shows and edits what runs (the scene's "auto" values
      // resolved; they stay automatic on restart until changed by hand)
      controller.pending() = sim.scene();
      controller.pending().sim = sim.latest()->params;
      if (script) script->start = sim.latest()->input.position;  // hair yaw from the new hair
    }
    // a script: the next event once the simulation has reached its frame
    if (script && script->warmup > 0) {
      --script->warmup;
    } else if (script) {
      if (script->events.empty()) {
        done = true;
      } else {
        const viewer::ScriptEvent& e = script->events.front();
        if (sim.latest()->frame < e.frame) {
          // recording: one frame at a time, so every frame is drawn and written
          const std::int64_t to = controller.recording() ? sim.latest()->frame + 1 : e.frame;
          sim.runUntil(to);
          if (!sim.waitForFrame(to)) {
            controller.fail(e.where + ": frame " + std::to_string(e.frame) +
                            " cannot be reached (the simulation is paused or stopped)");
            return 1;
          }
          sim.waitForStrands();  // a scripted picture shows its frame's strands
        }
        // a restart that finished meanwhile is taken in first (its head, the
        // panel's values), at the top of the next displayed frame
        if (sim.latest()->frame >= e.frame && sim.latest()->generation == generation) {
          const viewer::ScriptEvent ev = e;
          script->events.pop_front();
          try {
            if (!runEvent(ev, w, panel, *script)) done = true;
          } catch (const std::exception& x) {  // a wrong value: shown as a user's mistake, the script goes on
            const std::string m = x.what();
            controller.fail(m.rfind(ev.where, 0) == 0 ? m : ev.where + ": " + m);
          }
        }
      }
    }
    // recording by hand: the simulation waits for each frame to be drawn
    // and written (it runs as fast as frames can be drawn, never skips one)
    if (!script && controller.recording() && controller.mode() == viewer::Mode::Simulate) {
      const std::int64_t to = sim.latest()->frame + 1;
      sim.runUntil(to);
      sim.waitForFrame(to);
      sim.waitForStrands();
    }
    std::shared_ptr<const viewer::PublishedFrame> frame = sim.latest();
    if (o.frames) {  // wait for the last frame, then show it
      if (frame->frame < *o.frames && sim.waitForFrame(*o.frames)) frame = sim.latest();
      sim.waitForStrands();
      if (shown >= 2) done = true;  // two frames drawn before: the panel has its size
    }
    // the newest carried strands with the newest frame (they may be a frame
    // or two behind it: the carry runs on its own thread)
    render::FrameInput with_strands;
    const render::FrameInput* input = &frame->input;
    std::int64_t shown_frame = frame->frame;  // the simulated frame the hair on screen is from
    // fewer strands while the hair moves, where the view says so (software
    // OpenGL); all of them paused, recording, or for --frames' picture
    const bool full_detail = sim.paused() || o.frames || controller.recording();
    view.settings.strand_budget =
        full_detail ? 0 : static_cast<std::size_t>(std::max(0, view.playing_strand_budget));
    if (const auto strands = sim.latestStrands()) {
      shown_frame = strands->frame;
      if (strands->frame != last_carried) {
        last_carried = strands->frame;
        ++carried_shown;
        carry_ms_sum += strands->carry_ms;
      }
      ++strand_frames;
      strand_lag_sum += static_cast<double>(frame->frame - strands->frame);
      with_strands = frame->input;
      double gpu_ms = 0.0;
      const std::size_t strand_count = strands->field ? strands->field->rest().size()
                                       : strands->points_each > 0
                                           ? strands->points.size() / static_cast<std::size_t>(strands->points_each)
                                           : 0;
      window_strands.add(*strands, sim, with_strands, gpu_ms,
                         render::strandBudgetStride(strand_count, view.settings.strand_budget));
      panel.strands_bound = strand_count;
      if (gpu_ms > 0.0) {
        panel.gpu_carry_ms = gpu_ms;
        carry_ms_sum += gpu_ms;
      }
      input = &with_strands;
    }
    viewer::ViewState& v = view;
    v.settings.light_direction = v.light_from_camera ? v.camera.keyLight()
                                                     : viewer::directionFromAngles(v.light_yaw_deg, v.light_pitch_deg);
    int width = 0, height = 0;
    glfwGetFramebufferSize(window.get(), &width, &height);
    if (width <= 0 || height <= 0) continue;
    w.width = width, w.height = height;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    hideViewPressesFromInterface(w);
    ImGui::NewFrame();
    panel.legend = render::debugLegend(*input, v.settings);  // what the colours drawn below mean
    if (viewer::StylingSession* ss = controller.styling(); ss && ss->settling())
      controller.attempt([&] {
        if (ss->finishSettle()) controller.note("settled the style: the key strands lie where the hair came to rest");
      });
    panel.draw(*frame, fps);
    ImGui::Render();
    // the hair in the middle of what the panel leaves free
    {
      const float display_w = std::max(1.0f, ImGui::GetIO().DisplaySize.x);
      v.camera.shift_x = v.show_panel ? std::min(v.panel_width / display_w, 0.8f) : 0.0f;
    }
    const bool styling = controller.mode() == viewer::Mode::Styling && controller.styling();
    if (styling) {  // the style's head at rest, its preview as lines
      if (styling_bodies_of != controller.styling()) {
        SceneDesc sd;
        static_cast<HeadDesc&>(sd) = controller.styling()->style().head;
        styling_bodies = std::make_unique<app::DrawableBodies>(app::drawableBodies(sd));
        styling_bodies_of = controller.styling();
      }
      renderer.setBodies(&styling_bodies->head, styling_bodies->torso ? &*styling_bodies->torso : nullptr);
      render::FrameInput empty;
      empty.spacing = frame->input.spacing;
      renderer.render(empty, v.camera, v.settings, width, height);
      renderer.setBodies(&bodies->head, bodies->torso ? &*bodies->torso : nullptr);
    } else {
      renderer.render(*input, v.camera, v.settings, width, height);
      const render::FrameTimes& t = renderer.lastTimes();
      pass_sum.light_pass += t.light_pass;
      pass_sum.camera_pass += t.camera_pass;
      pass_sum.resolve += t.resolve;
      pass_sum.upload += t.upload + t.sort;
      strands_drawn_sum += t.strands_drawn;
      panel.strands_drawn = t.strands_drawn;
    }
    buildOverlay(controller, *frame, hidden, on_top);
    overlay.draw(hidden, on_top, v.camera, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++shown;
    std::string record = styling ? std::string() : controller.recordingPath(frame->frame);
    if (v.screenshot || !record.empty() || (done && !o.screenshot.empty())) {
      const std::vector<std::uint8_t> pixels = readFramebuffer(width, height);
      std::vector<std::string> paths;
      if (!record.empty()) paths.push_back(record);
      if (v.screenshot || (done && !o.screenshot.empty())) {
        char name[40];
        std::snprintf(name, sizeof name, "loosehair-%05d.png", ++shots);
        paths.push_back(done && !o.screenshot.empty() ? o.screenshot
                        : !v.screenshot_path.empty()   ? v.screenshot_path
                                                       : std::string(name));
      }
      for (const std::string& path : paths) {
        try {
          app::writePng(path, pixels, width, height);
          if (path != record)
            std::printf("screenshot: %s (%dx%d, %.0f%% of the picture drawn over the background)\n", path.c_str(),
                        width, height, 100.0 * drawnFraction(pixels, v.settings.background));
        } catch (const std::exception& e) {
          controller.fail(e.what());
          if (path == record) controller.stopRecording();
        }
      }
      v.screenshot = false;
      v.screenshot_path.clear();
    }
    glfwSwapBuffers(window.get());
    if (w.input_at && shown_frame > w.input_frame) {  // the head's move is on screen
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *w.input_at).count();
      ++latency_count;
      latency_sum += ms;
      latency_max = std::max(latency_max, ms);
      w.input_at.reset();
    }
    ++frames_since;
    const auto now = std::chrono::steady_clock::now();
    const double span = std::chrono::duration<double>(now - last_count).count();
    if (span >= 0.5) {
      fps = frames_since / span;
      last_count = now;
      frames_since = 0;
    }
    if (o.seconds && std::chrono::duration<double>(now - started).count() >= *o.seconds) done = true;
  }
  if (o.seconds || script) {  // measuring, or a script's report of what it drew
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::printf("measured: %d frames drawn in %.2f s = %.1f frames/s (%dx%d), simulation %.2fx real time\n", shown,
                wall, shown / wall, w.width, w.height, (sim.latest()->time - started_sim) / wall);
    if (strand_frames > 0)
      std::printf("strands: %d simulated frames carried and shown (%.0f ms a carry), drawn %.1f frames behind the "
                  "simulation on average\n",
                  carried_shown, carry_ms_sum / std::max(1, carried_shown), strand_lag_sum / strand_frames);
    if (shown > 0)
      std::printf("a frame drawn: light pass %.0f ms, camera pass %.0f ms, resolve %.0f ms, sort and upload %.0f "
                  "ms; %.0f strands drawn on average\n",
                  1e3 * pass_sum.light_pass / shown, 1e3 * pass_sum.camera_pass / shown, 1e3 * pass_sum.resolve / shown,
                  1e3 * pass_sum.upload / shown, static_cast<double>(strands_drawn_sum) / shown);
    if (latency_count > 0)
      std::printf("input to picture: %d head moves, %.0f ms on average, %.0f ms at most (from a move to the "
                  "first frame drawn with hair simulated after it)\n",
                  latency_count, latency_sum / latency_count, latency_max);
  }
  controller.stopRecording();
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
  if (!args.empty() && (args[0] == "--version" || args[0] == "version")) {
    std::printf("loosehair-view %s\n", LOOSEHAIR_VERSION);
    return 0;
  }
  loosehair::removeTemporariesOnSignal();
  try {
    return run(parseOptions(app::splitFlagValues(args)));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "loosehair-view: %s\n\n%s", e.message.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair-view: %s\n", e.what());
    return 1;
  }
}
