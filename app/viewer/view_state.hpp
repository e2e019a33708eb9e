// What the window shows and how; the panel, the shortcuts and scripts change it.
#pragma once

#include "loosehair/render/renderer.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <string>
#include <vector>

namespace loosehair::viewer {

/// What the window shows and how; the panel and the shortcuts change it.
struct ViewState {
  render::Camera camera;
  render::RenderSettings settings;
  /// The light turns with the camera (Camera::keyLight), or stays where
  /// light_yaw_deg and light_pitch_deg put it.
  bool light_from_camera = true;
  float light_yaw_deg = 35.0f, light_pitch_deg = 50.0f;  // the fixed light
  bool show_panel = true;
  bool show_help = false;  // the shortcuts, in a window of their own (H)
  /// The panel's and other windows' rectangles as last drawn (x0, y0, x1,
  /// y1 in window coordinates): a press or a scroll over one belongs to it,
  /// anywhere else to the 3-D view, decided when it happens.
  std::vector<glm::vec4> ui_rects;
  float panel_width = 0;  // the panel's width when shown (window coordinates)
  bool screenshot = false, quit = false;
  std::string message;  // shown in the status window (errors, what was saved)
  bool message_is_error = false;
  std::string open_section;     // a panel section to open at the next frame (scripts)
  std::string screenshot_path;  // where the next screenshot goes ("" = a numbered file)
  // debug views the renderer does not draw itself (overlay lines)
  bool show_grid = false, show_air = false;
  bool show_wind_arrow = true, show_light_arrow = true;
  /// Render strands drawn when settings.hair is Strands (Controller::setHair).
  int strands = 12000;
  /// Strands drawn (and carried, on the GPU) at most while the simulation
  /// plays, 0 for all; all of them are drawn while it is paused. Set for
  /// software OpenGL, where 12,000 strands draw at a few frames a second.
  int playing_strand_budget = 0;
};

}  // namespace loosehair::viewer
