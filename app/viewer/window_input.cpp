// The viewer's mouse and keyboard on the 3-D view (window_input.hpp).
#include "viewer/window_input.hpp"

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

static Window& of(GLFWwindow* w) { return *static_cast<Window*>(glfwGetWindowUserPointer(w)); }

template <class E>
static E next(E value, E last) {
  return static_cast<E>((static_cast<int>(value) + 1) % (static_cast<int>(last) + 1));
}

static render::Ray rayAt(const Window& w, double x, double y) {
  return w.c->view().camera.ray(x, y, w.width, w.height);
}

void key(Window& w, int key, int mods, bool scripted) {
  if (!scripted && ImGui::GetIO().WantCaptureKeyboard) return;
  Controller& c = *w.c;
  ViewState& v = c.view();
  StylingSession* st = c.mode() == Mode::Styling ? c.styling() : nullptr;
  const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0, shift = (mods & GLFW_MOD_SHIFT) != 0;
  if (st) {
    switch (key) {
      case GLFW_KEY_Z:
        if (ctrl) {
          (shift ? st->redo() : st->undo());
          c.clearError();
        }
        return;
      case GLFW_KEY_T:
        st->axis = StylingAxis::Tangent;
        return;
      case GLFW_KEY_G:
        st->axis = StylingAxis::Normal;
        return;
      case GLFW_KEY_B:
        st->axis = StylingAxis::Binormal;
        return;
      case GLFW_KEY_UP:
        c.attempt([&] { st->moveSelected(0.005f); });
        return;
      case GLFW_KEY_DOWN:
        c.attempt([&] { st->moveSelected(-0.005f); });
        return;
      case GLFW_KEY_DELETE:
        c.attempt([&] { st->deleteSelectedPoint(); });
        return;
      default:
        break;
    }
  }
  switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
      v.quit = true;
      break;
    case GLFW_KEY_SPACE:
      c.sim().setPaused(!c.sim().paused());
      break;
    case GLFW_KEY_N:
    case GLFW_KEY_RIGHT:
      c.sim().stepOnce();
      break;
    case GLFW_KEY_R:
      c.restart();
      break;
    case GLFW_KEY_S:
      v.settings.shadows = !v.settings.shadows;
      break;
    case GLFW_KEY_C:
      v.settings.color = next(v.settings.color, render::HairColor::Red);
      v.settings.custom_color.reset();
      break;
    case GLFW_KEY_D:
      v.settings.debug = next(v.settings.debug, render::DebugView::Directions);
      break;
    case GLFW_KEY_L:
      v.light_from_camera = !v.light_from_camera;
      break;
    case GLFW_KEY_P:
      v.screenshot = true;
      break;
    case GLFW_KEY_TAB:
      v.show_panel = !v.show_panel;
      break;
    case GLFW_KEY_H:
      v.show_help = !v.show_help;
      break;
    case GLFW_KEY_F2:
      if (c.mode() == Mode::Styling)
        c.enterSimulate();
      else
        c.enterStyling();
      break;
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3:
    case GLFW_KEY_4: {
      static const char* presets[] = {"front", "side", "back", "three-quarter"};
      const render::Camera p = render::Camera::preset(presets[key - GLFW_KEY_1]);
      v.camera.yaw_deg = p.yaw_deg;
      v.camera.pitch_deg = p.pitch_deg;
      break;
    }
    default:
      break;
  }
}

// How near (m, at the depth of what is picked) the pointer must be to a
// control point, an arrow or a key strand: about 8 pixels at 720 rows.
static float pickTolerance(Controller& c) { return 0.01f * c.view().camera.distance; }

void mouseButton(Window& w, int button, bool press, bool shift, double x, double y) {
  w.last_x = x, w.last_y = y;
  w.shift = shift;
  Controller& c = *w.c;
  StylingSession* st = c.mode() == Mode::Styling ? c.styling() : nullptr;
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    if (press && st && st->tool == StylingSession::Tool::Tie) {  // a tie where the wisps pass
      const render::Ray r = rayAt(w, x, y);
      // the key strands within the brush circle (its radius in metres at
      // the camera's distance), or at least those picked at the click
      const render::Camera& cam = c.view().camera;
      const float brush = st->brush_pixels * 2.0f * cam.distance * std::tan(0.5f * glm::radians(cam.fov_deg)) /
                          static_cast<float>(std::max(1, w.height));
      c.attempt([&] {
        st->tieAt(r, std::max(3.0f * pickTolerance(c), brush));
        c.note("tied: the ring goes round the key strands there");
      });
      return;
    }
    if (press && st && st->tool != StylingSession::Tool::Select) {  // a strand brush stroke
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
  Controller& c = *w.c;
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
  if (c.mode() == Mode::Styling && c.styling() && !w.styling_drag && !w.brushing && !w.orbiting && !w.stroking)
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
static bool onInterface(const Window& w, double x, double y) {
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
  w.shift =
      glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
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

}  // namespace loosehair::viewer
