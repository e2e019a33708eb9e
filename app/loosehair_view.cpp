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
#include "viewer/script_runner.hpp"
#include "viewer/view_options.hpp"
#include "viewer/window_input.hpp"
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
using namespace loosehair::viewer;

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

// A script's next event, once the simulation has reached its frame; false
// when that frame cannot be reached. `done`: the script has ended.
bool playScript(ScriptRun& script, viewer::SimulationThread& sim, viewer::Controller& controller, Window& w,
                viewer::Panel& panel, std::uint64_t generation, bool& done) {
  if (script.warmup > 0) {
    --script.warmup;
  } else {
    if (script.events.empty()) {
      done = true;
    } else {
      const viewer::ScriptEvent& e = script.events.front();
      if (sim.latest()->frame < e.frame) {
        // recording: one frame at a time, so every frame is drawn and written
        const std::int64_t to = controller.recording() ? sim.latest()->frame + 1 : e.frame;
        sim.runUntil(to);
        if (!sim.waitForFrame(to)) {
          controller.fail(e.where + ": frame " + std::to_string(e.frame) +
                          " cannot be reached (the simulation is paused or stopped)");
          return false;
        }
        sim.waitForStrands();  // a scripted picture shows its frame's strands
      }
      // a restart that finished meanwhile is taken in first (its head, the
      // panel's values), at the top of the next displayed frame
      if (sim.latest()->frame >= e.frame && sim.latest()->generation == generation) {
        const viewer::ScriptEvent ev = e;
        script.events.pop_front();
        try {
          if (!runEvent(ev, w, panel, script)) done = true;
        } catch (const std::exception& x) {  // a wrong value: shown as a user's mistake, the script goes on
          const std::string m = x.what();
          controller.fail(m.rfind(ev.where, 0) == 0 ? m : ev.where + ": " + m);
        }
      }
    }
  }
  return true;
}

// The frame just drawn as PNGs: the recording's frame (`record`), a
// screenshot asked for (the view's), and the last frame's (`final_shot`).
void saveFrameImages(viewer::Controller& controller, viewer::ViewState& v, const std::string& final_shot,
                     const std::string& record, int width, int height, int& shots) {
  const std::vector<std::uint8_t> pixels = readFramebuffer(width, height);
  std::vector<std::string> paths;
  if (!record.empty()) paths.push_back(record);
  if (v.screenshot || !final_shot.empty()) {
    char name[40];
    std::snprintf(name, sizeof name, "loosehair-%05d.png", ++shots);
    paths.push_back(!final_shot.empty()          ? final_shot
                    : !v.screenshot_path.empty() ? v.screenshot_path
                                                 : std::string(name));
  }
  for (const std::string& path : paths) {
    try {
      app::writePng(path, pixels, width, height);
      if (path != record)
        std::printf("screenshot: %s (%dx%d, %.0f%% of the picture drawn over the background)\n", path.c_str(), width,
                    height, 100.0 * drawnFraction(pixels, v.settings.background));
    } catch (const std::exception& e) {
      controller.fail(e.what());
      if (path == record) controller.stopRecording();
    }
  }
  v.screenshot = false;
  v.screenshot_path.clear();
}

// What the window drew and how fast (--seconds, scripts).
struct Measures {
  int shown = 0;  // frames drawn
  int carried_shown = 0, strand_frames = 0;
  double carry_ms_sum = 0, strand_lag_sum = 0;
  render::FrameTimes pass_sum;  // the renderer's passes, summed over the frames drawn
  std::size_t strands_drawn_sum = 0;
  int latency_count = 0;  // input to picture (Window::input_at)
  double latency_sum = 0, latency_max = 0;
  /// The frame on screen shows hair simulated from `shown_frame`: a head
  /// move before it (Window::input_at) is on screen now.
  void headMoveShown(Window& w, std::int64_t shown_frame) {
    if (!w.input_at || shown_frame <= w.input_frame) return;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *w.input_at).count();
    ++latency_count;
    latency_sum += ms;
    latency_max = std::max(latency_max, ms);
    w.input_at.reset();
  }
};

void printMeasures(const Measures& m, const Window& w, double wall, double simulated) {
  std::printf("measured: %d frames drawn in %.2f s = %.1f frames/s (%dx%d), simulation %.2fx real time\n", m.shown,
              wall, m.shown / wall, w.width, w.height, simulated / wall);
  if (m.strand_frames > 0)
    std::printf(
        "strands: %d simulated frames carried and shown (%.0f ms a carry), drawn %.1f frames behind the "
        "simulation on average\n",
        m.carried_shown, m.carry_ms_sum / std::max(1, m.carried_shown), m.strand_lag_sum / m.strand_frames);
  if (m.shown > 0)
    std::printf(
        "a frame drawn: light pass %.0f ms, camera pass %.0f ms, resolve %.0f ms, sort and upload %.0f "
        "ms; %.0f strands drawn on average\n",
        1e3 * m.pass_sum.light_pass / m.shown, 1e3 * m.pass_sum.camera_pass / m.shown,
        1e3 * m.pass_sum.resolve / m.shown, 1e3 * m.pass_sum.upload / m.shown,
        static_cast<double>(m.strands_drawn_sum) / m.shown);
  if (m.latency_count > 0)
    std::printf(
        "input to picture: %d head moves, %.0f ms on average, %.0f ms at most (from a move to the "
        "first frame drawn with hair simulated after it)\n",
        m.latency_count, m.latency_sum / m.latency_count, m.latency_max);
}

using WindowHandle = std::unique_ptr<GLFWwindow, void (*)(GLFWwindow*)>;

// The window with an OpenGL 3.3 core context, current, its functions loaded;
// without vsync for --frames and scripts (they run as fast as they can).
WindowHandle openWindow(const ViewOptions& o, const std::string& scene_name, bool scripted) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  WindowHandle window(glfwCreateWindow(o.width, o.height, ("loosehair - " + scene_name).c_str(), nullptr, nullptr),
                      glfwDestroyWindow);
  if (!window) throw std::runtime_error("cannot open a window with an OpenGL 3.3 core context");
  glfwMakeContextCurrent(window.get());
  render::loadGL([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); });
  glfwSwapInterval(scripted || o.frames ? 0 : 1);
  return window;
}

// The view as the options ask, strands by default (fewer while the hair
// moves on software OpenGL), the light's angles from its direction.
// Returns the OpenGL renderer's name.
std::string setUpView(const ViewOptions& o, viewer::ViewState& view, viewer::Controller& controller) {
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
  return gl_renderer;
}

// the strands carried by a compute shader wherever OpenGL runs one: on
// a GPU it costs next to nothing, and even on llvmpipe the window showed
// current strands (0 frames behind, against 15 from the carry thread,
// which competes with the simulation for the cores) at the same rate
bool chooseStrandCarry(const std::string& carry, viewer::SimulationThread& sim) {
  std::string why;
  const bool can = render::gpuStrandCarrySupported(&why);
  if (carry == "gpu" && !can) {
    std::fprintf(stderr, "loosehair-view: --strand-carry gpu: %s\n", why.c_str());
    return false;
  }
  sim.setStrandsOnGpu(carry == "gpu" || (carry == "auto" && can));
  return true;
}

// The newest carried strands added to the frame's input (`with_strands`):
// they may be a frame or two behind it, the carry runs on its own thread.
// Returns the simulated frame they are from, or -1 when there are none.
std::int64_t addCarriedStrands(viewer::SimulationThread& sim, const viewer::PublishedFrame& frame,
                               const viewer::ViewState& view, viewer::WindowStrands& window_strands,
                               viewer::Panel& panel, std::int64_t& last_carried, Measures& m,
                               render::FrameInput& with_strands) {
  const auto strands = sim.latestStrands();
  if (!strands) return -1;
  if (strands->frame != last_carried) {
    last_carried = strands->frame;
    ++m.carried_shown;
    m.carry_ms_sum += strands->carry_ms;
  }
  ++m.strand_frames;
  m.strand_lag_sum += static_cast<double>(frame.frame - strands->frame);
  with_strands = frame.input;
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
    m.carry_ms_sum += gpu_ms;
  }
  return strands->frame;
}

// The bodies of the style being edited (its own head, at rest).
struct StylingBodies {
  std::unique_ptr<app::DrawableBodies> bodies;
  const viewer::StylingSession* of = nullptr;
};

// The hair and bodies: in the styling mode the style's head at rest (its
// preview is drawn as lines, buildOverlay), else the frame.
void drawHair(render::Renderer& renderer, viewer::Controller& controller, const viewer::PublishedFrame& frame,
              const render::FrameInput& input, const app::DrawableBodies& bodies, StylingBodies& styling_bodies,
              int width, int height, Measures& m, viewer::Panel& panel) {
  viewer::ViewState& v = controller.view();
  if (controller.mode() == viewer::Mode::Styling && controller.styling()) {
    if (styling_bodies.of != controller.styling()) {
      SceneDesc sd;
      static_cast<HeadDesc&>(sd) = controller.styling()->style().head;
      styling_bodies.bodies = std::make_unique<app::DrawableBodies>(app::drawableBodies(sd));
      styling_bodies.of = controller.styling();
    }
    renderer.setBodies(&styling_bodies.bodies->head,
                       styling_bodies.bodies->torso ? &*styling_bodies.bodies->torso : nullptr);
    render::FrameInput empty;
    empty.spacing = frame.input.spacing;
    renderer.render(empty, v.camera, v.settings, width, height);
    renderer.setBodies(&bodies.head, bodies.torso ? &*bodies.torso : nullptr);
  } else {
    renderer.render(input, v.camera, v.settings, width, height);
    const render::FrameTimes& t = renderer.lastTimes();
    m.pass_sum.light_pass += t.light_pass;
    m.pass_sum.camera_pass += t.camera_pass;
    m.pass_sum.resolve += t.resolve;
    m.pass_sum.upload += t.upload + t.sort;
    m.strands_drawn_sum += t.strands_drawn;
    panel.strands_drawn = t.strands_drawn;
  }
}

// The window's callbacks hand the input to `w` (window_input.hpp).
void attachInput(Window& w, GLFWwindow* window) {
  glfwSetWindowUserPointer(window, &w);
  glfwSetKeyCallback(window, onKey);
  glfwSetMouseButtonCallback(window, onMouseButton);
  glfwSetCursorPosCallback(window, onCursor);
  glfwSetScrollCallback(window, onScroll);
}

// Frames drawn a second, over half-second spans.
struct FrameRate {
  double fps = 0;
  std::chrono::steady_clock::time_point since = std::chrono::steady_clock::now();
  int frames = 0;
  void tick(std::chrono::steady_clock::time_point now) {
    ++frames;
    const double span = std::chrono::duration<double>(now - since).count();
    if (span >= 0.5) {
      fps = frames / span;
      since = now;
      frames = 0;
    }
  }
};

// The panel (Dear ImGui) of this frame, laid out and rendered into its draw
// data; the camera shifted so the hair sits in what the panel leaves free.
void drawPanel(Window& w, viewer::Panel& panel, const viewer::PublishedFrame& frame, const render::FrameInput& input,
               double fps) {
  viewer::Controller& controller = *w.c;
  viewer::ViewState& v = controller.view();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  hideViewPressesFromInterface(w);
  ImGui::NewFrame();
  panel.legend = render::debugLegend(input, v.settings);  // what the colours drawn below mean
  if (viewer::StylingSession* ss = controller.styling(); ss && ss->settling())
    controller.attempt([&] {
      if (ss->finishSettle()) controller.note("settled the style: the key strands lie where the hair came to rest");
    });
  panel.draw(frame, fps);
  ImGui::Render();
  {
    const float display_w = std::max(1.0f, ImGui::GetIO().DisplaySize.x);
    v.camera.shift_x = v.show_panel ? std::min(v.panel_width / display_w, 0.8f) : 0.0f;
  }
}

// Another scene runs (opened, restarted): its bodies to draw, the head's
// pivot, the panel's values, a script's reference hair.
std::unique_ptr<app::DrawableBodies> takeNewScene(viewer::SimulationThread& sim, viewer::Controller& controller,
                                                  viewer::HeadDrag& head, ScriptRun* script) {
  auto bodies = std::make_unique<app::DrawableBodies>(app::drawableBodies(sim.scene()));
  head.setPivot(viewer::neckPivot(bodies->head));
  // the panel shows and edits what runs (the scene's "auto" values
  // resolved; they stay automatic on restart until changed by hand)
  controller.pending() = sim.scene();
  controller.pending().sim = sim.latest()->params;
  if (script) script->start = sim.latest()->input.position;  // hair yaw from the new hair
  return bodies;
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
  const WindowHandle window = openWindow(o, scene.name, script.has_value());

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
  const std::string gl_renderer = setUpView(o, view, controller);
  Window w;
  w.c = &controller;
  w.glfw = window.get();
  attachInput(w, window.get());
  ImGuiSession imgui(window.get());
  viewer::Panel panel(controller);
  panel.gl_renderer = gl_renderer;
  if (!chooseStrandCarry(o.strand_carry, sim)) return 2;
  viewer::WindowStrands window_strands;  // in this window's context
  if (script) script->start = sim.latest()->input.position;

  std::printf("scene: %s, %zu particles, %d substeps a frame at %g frames/s, %s\n", scene.name.c_str(),
              sim.latest()->particles, sim.buildReport().substeps, scene.frame_rate, gl_renderer.c_str());
  std::printf("press H in the window for the shortcuts\n");

  Measures m;
  int shots = 0;
  FrameRate fps;
  bool done = false;
  const auto started = std::chrono::steady_clock::now();
  const double started_sim = sim.latest()->time;
  std::int64_t last_carried = -1;  // the strands shown: how many frames carried, how late
  std::uint64_t generation = 0;
  StylingBodies styling_bodies;
  render::OverlayLines hidden, on_top;
  while (!glfwWindowShouldClose(window.get()) && !view.quit && !done) {
    glfwPollEvents();
    if (const std::string e = sim.takeError(); !e.empty()) controller.fail(e);
    if (sim.latest()->generation != generation) {  // another scene: its head
      generation = sim.latest()->generation;
      bodies = takeNewScene(sim, controller, head, script ? &*script : nullptr);
    }
    // a script: the next event once the simulation has reached its frame
    if (script && !playScript(*script, sim, controller, w, panel, generation, done)) return 1;
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
      if (m.shown >= 2) done = true;  // two frames drawn before: the panel has its size
    }
    // the newest carried strands with the newest frame (they may be a frame
    // or two behind it: the carry runs on its own thread)
    render::FrameInput with_strands;
    const render::FrameInput* input = &frame->input;
    std::int64_t shown_frame = frame->frame;  // the simulated frame the hair on screen is from
    // fewer strands while the hair moves, where the view says so (software
    // OpenGL); all of them paused, recording, or for --frames' picture
    const bool full_detail = sim.paused() || o.frames || controller.recording();
    view.settings.strand_budget = full_detail ? 0 : static_cast<std::size_t>(std::max(0, view.playing_strand_budget));
    if (const std::int64_t carried =
            addCarriedStrands(sim, *frame, view, window_strands, panel, last_carried, m, with_strands);
        carried >= 0) {
      shown_frame = carried;
      input = &with_strands;
    }
    viewer::ViewState& v = view;
    v.settings.light_direction =
        v.light_from_camera ? v.camera.keyLight() : viewer::directionFromAngles(v.light_yaw_deg, v.light_pitch_deg);
    int width = 0, height = 0;
    glfwGetFramebufferSize(window.get(), &width, &height);
    if (width <= 0 || height <= 0) continue;
    w.width = width, w.height = height;
    drawPanel(w, panel, *frame, *input, fps.fps);
    const bool styling = controller.mode() == viewer::Mode::Styling && controller.styling();
    drawHair(renderer, controller, *frame, *input, *bodies, styling_bodies, width, height, m, panel);
    buildOverlay(controller, *frame, hidden, on_top);
    overlay.draw(hidden, on_top, v.camera, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++m.shown;
    std::string record = styling ? std::string() : controller.recordingPath(frame->frame);
    if (v.screenshot || !record.empty() || (done && !o.screenshot.empty()))
      saveFrameImages(controller, v, done ? o.screenshot : std::string(), record, width, height, shots);
    glfwSwapBuffers(window.get());
    m.headMoveShown(w, shown_frame);
    const auto now = std::chrono::steady_clock::now();
    fps.tick(now);
    if (o.seconds && std::chrono::duration<double>(now - started).count() >= *o.seconds) done = true;
  }
  if (o.seconds || script)  // measuring, or a script's report of what it drew
    printMeasures(m, w, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                  sim.latest()->time - started_sim);
  controller.stopRecording();
  const std::shared_ptr<const viewer::PublishedFrame> last = sim.latest();
  std::printf("showed %d frames, simulated %.2f s; state-hash: %016llx\n", m.shown, last->time,
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
