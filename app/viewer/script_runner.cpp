// The viewer's scripts: one event at a time (script_runner.hpp).
#include "viewer/script_runner.hpp"

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

namespace loosehair::viewer {
namespace {

int glfwKeyNamed(const std::string& name, const std::string& where) {
  static const std::pair<const char*, int> named[] = {
      {"space", GLFW_KEY_SPACE},   {"right", GLFW_KEY_RIGHT},   {"left", GLFW_KEY_LEFT},
      {"up", GLFW_KEY_UP},         {"down", GLFW_KEY_DOWN},     {"tab", GLFW_KEY_TAB},
      {"escape", GLFW_KEY_ESCAPE}, {"delete", GLFW_KEY_DELETE}, {"f2", GLFW_KEY_F2}};
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

// As a person's input: the pointer moves there and the window's own
// handlers decide whether the panel or the view gets it.
void runWindowEvent(const ScriptEvent& e, Window& w) {
  const nlohmann::json& a = e.args;
  const std::string& what = e.what;
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
}

// Input on the 3-D view in framebuffer pixels, or (with "anchor") in pixels
// from a styling handle as seen at the press.
void runViewPointerEvent(const ScriptEvent& e, Window& w) {
  Controller& c = *w.c;
  const nlohmann::json& a = e.args;
  const std::string& what = e.what;
  const int button = a["button"] == "left" ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT;
  double x = a["x"].get<double>(), y = a["y"].get<double>();
  if (a.contains("anchor")) {  // pixels from a control point, arrow or key strand, as seen at the press
    if (what == "mouse_down") {
      StylingSession* st = c.mode() == Mode::Styling ? c.styling() : nullptr;
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
          p = st->handlePoint(wi, k,
                              on == "tangent"  ? StylingAxis::Tangent
                              : on == "normal" ? StylingAxis::Normal
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
}

// "set": a solver parameter (checked as the scene file's) or a value of
// the viewer (viewer_values.hpp).
void runSetEvent(const ScriptEvent& e, Controller& c, Panel& panel) {
  const nlohmann::json& a = e.args;
  auto text = [&](const char* f) { return a.at(f).get<std::string>(); };
  const std::string name = text("name");
  if (!a["value"].is_number() && !a["value"].is_boolean())
    throw std::runtime_error(e.where + ": value must be a number");
  const double raw = a["value"].is_boolean() ? (a["value"].get<bool>() ? 1.0 : 0.0) : a["value"].get<double>();
  if (!isViewerValue(name)) {
    c.setParam(name, raw, e.where);  // a solver parameter, checked as the scene file's
  } else {
    // values of the styling session (only in the styling mode) and of the
    // wisps the brush creates, by their script names
    using Session = StylingSession;
    static const std::pair<const char*, float Session::*> session[] = {
        {"styling.brush_radius", &Session::brush_radius},   {"styling.drag_falloff", &Session::drag_falloff},
        {"styling.wisp_length", &Session::new_wisp_length}, {"styling.settle_seconds", &Session::settle_seconds},
        {"styling.brush_pixels", &Session::brush_pixels},   {"styling.brush_strength", &Session::brush_strength},
        {"styling.curl_radius", &Session::curl_radius},     {"styling.curl_period", &Session::curl_period}};
    static const std::pair<const char*, float WispParams::*> new_wisp[] = {
        {"styling.density", &WispParams::density},
        {"styling.offset_radius", &WispParams::offset_radius},
        {"styling.blend", &WispParams::blend},
        {"styling.edge_ramp", &WispParams::edge_ramp},
        {"styling.length_variation", &WispParams::length_variation}};
    const auto* in_session =
        std::find_if(std::begin(session), std::end(session), [&](const auto& f) { return name == f.first; });
    const auto* in_wisp =
        std::find_if(std::begin(new_wisp), std::end(new_wisp), [&](const auto& f) { return name == f.first; });
    if (in_session != std::end(session) && !c.styling())
      throw std::runtime_error(e.where + ": " + name + " is set in styling mode");
    const double value = checkViewerValue(name, raw, e.where);
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
}

// "view": the picture's and the styling mode's settings.
void runViewEvent(const ScriptEvent& e, Controller& c) {
  ViewState& v = c.view();
  const nlohmann::json& a = e.args;
  auto text = [&](const char* f) { return a.at(f).get<std::string>(); };
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
    StylingSession& st = *c.styling();
    st.wisp = val[0].get<std::size_t>();
    st.point = val[1].get<std::size_t>();
    st.clampSelection();
  } else if (name == "axis" && c.styling()) {
    const std::string ax = val.get<std::string>();
    if (ax != "tangent" && ax != "normal" && ax != "binormal")
      throw std::runtime_error(e.where + ": axis must be tangent, normal or binormal");
    c.styling()->axis = ax == "tangent"  ? StylingAxis::Tangent
                        : ax == "normal" ? StylingAxis::Normal
                                         : StylingAxis::Binormal;
  } else if (name == "tool" && c.styling()) {
    using Tool = StylingSession::Tool;
    const std::string t = val.is_string() ? val.get<std::string>() : std::string();
    static const std::pair<const char*, Tool> tools[] = {
        {"select", Tool::Select}, {"comb", Tool::Comb}, {"length", Tool::Length}, {"puff", Tool::Puff},
        {"smooth", Tool::Smooth}, {"curl", Tool::Curl}, {"tie", Tool::Tie}};
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
}

// "press": a panel button by its name.
void runPressEvent(const ScriptEvent& e, Controller& c, Panel& panel) {
  const nlohmann::json& a = e.args;
  auto text = [&](const char* f) { return a.at(f).get<std::string>(); };
  const std::string name = text("name");
  StylingSession* st = c.styling();
  auto need = [&]() -> StylingSession& {
    if (!st || c.mode() != Mode::Styling)
      throw std::runtime_error(e.where + ": \"" + name + "\" needs the styling mode");
    return *st;
  };
  const float step = 1e-3f * panel.move_step_mm;
  if (name == "play")
    c.sim().setPaused(false);
  else if (name == "pause")
    c.sim().setPaused(true);
  else if (name == "step")
    c.sim().stepOnce();
  else if (name == "restart")
    c.restart();
  else if (name == "shake" || name == "nod")
    c.shake(panel.shake_amplitude_deg, panel.shake_frequency_hz, name == "nod");
  else if (name == "centre_head")
    c.centreHead();
  else if (name == "wind_on" || name == "wind_off")
    c.setWind(name == "wind_on");
  else if (name == "stop_recording")
    c.stopRecording();
  else if (name == "styling")
    c.enterStyling();
  else if (name == "simulate")
    c.enterSimulate();
  else if (name == "create_wisp")
    c.attempt([&] { need().createWispFromBrush(c.new_wisp); });
  else if (name == "set_region")
    c.attempt([&] { need().setRegionFromBrush(); });
  else if (name == "clear_brush")
    need().clearBrush();
  else if (name == "move_plus")
    c.attempt([&] { need().moveSelected(step); });
  else if (name == "move_minus")
    c.attempt([&] { need().moveSelected(-step); });
  else if (name == "add_point")
    c.attempt([&] { need().addPointAfterSelected(); });
  else if (name == "delete_point")
    c.attempt([&] { need().deleteSelectedPoint(); });
  else if (name == "delete_wisp")
    c.attempt([&] { need().deleteSelectedWisp(); });
  else if (name == "copy")
    c.attempt([&] { need().copySelected(); });
  else if (name == "paste")
    c.attempt([&] { need().pasteOnSelected(); });
  else if (name == "mirror")
    c.attempt([&] { need().mirrorSelected(); });
  else if (name == "tie")
    c.attempt([&] { need().tieAtSelected(0.015f); });
  else if (name == "apply_params")
    c.attempt([&] {
      StylingSession& ss = need();
      if (!ss.wisp) throw StyleError("select a wisp first to set its parameters");
      ss.editor().setParams(*ss.wisp, c.new_wisp);
    });
  else if (name == "undo")
    need().undo(), c.clearError();
  else if (name == "redo")
    need().redo(), c.clearError();
  else if (name == "settle")
    c.attempt([&] {  // a script waits for it: the next event sees the settled style
      StylingSession& ss = need();
      ss.startSettle();
      if (ss.finishSettle(true)) c.note("settled the style: the key strands lie where the hair came to rest");
    });
  else
    throw std::runtime_error(e.where + ": no panel action called \"" + name + "\"");
}

}  // namespace

bool runEvent(const ScriptEvent& e, Window& w, Panel& panel, ScriptRun& run) {
  Controller& c = *w.c;
  ViewState& v = c.view();
  const nlohmann::json& a = e.args;
  const std::string& what = e.what;
  auto text = [&](const char* f) { return a.at(f).get<std::string>(); };
  if (a.value("window", false) || what == "hover" || what == "scroll") {
    runWindowEvent(e, w);
  } else if (what == "mouse_down" || what == "mouse_up" || what == "mouse_move") {
    runViewPointerEvent(e, w);
  } else if (what == "key") {
    key(w, glfwKeyNamed(text("key"), e.where),
        (a.value("ctrl", false) ? GLFW_MOD_CONTROL : 0) | (a.value("shift", false) ? GLFW_MOD_SHIFT : 0), true);
  } else if (what == "set") {
    runSetEvent(e, c, panel);
  } else if (what == "view") {
    runViewEvent(e, c);
  } else if (what == "press") {
    runPressEvent(e, c, panel);
  } else if (what == "open") {
    c.open(text("path"));
  } else if (what == "screenshot") {
    v.screenshot = true;
    v.screenshot_path = text("path");
  } else if (what == "hash") {
    const std::shared_ptr<const PublishedFrame> f = c.sim().latest();
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

}  // namespace loosehair::viewer
