// The viewer's mouse and keyboard on the 3-D view: orbit, zoom, drag the
// head, pick and drag the styling handles, brush; the GLFW callbacks hand
// the panel (Dear ImGui) what is its own. Scripts (script_runner.hpp) call
// the same handlers.
#pragma once

#include "viewer/controller.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/vec2.hpp>

#include <chrono>
#include <cstdint>
#include <optional>

namespace loosehair::viewer {

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

/// A key on the 3-D view (`scripted`: from a script, never the panel's).
void key(Window& w, int key, int mods, bool scripted);
/// A mouse button pressed or released at (x, y) framebuffer pixels.
void mouseButton(Window& w, int button, bool press, bool shift, double x, double y);
/// The pointer moved to (x, y) framebuffer pixels.
void cursor(Window& w, double x, double y);

// The GLFW callbacks (the window's user pointer is its Window).
void onMouseButton(GLFWwindow* window, int button, int action, int mods);
void onCursor(GLFWwindow* window, double x, double y);
void onScroll(GLFWwindow* window, double dx, double dy);
void onKey(GLFWwindow* window, int k, int scancode, int action, int mods);
/// The panel does not see the presses the 3-D view holds.
void hideViewPressesFromInterface(const Window& w);

}  // namespace loosehair::viewer
