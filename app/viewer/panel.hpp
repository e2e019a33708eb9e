// The viewer's panel (Dear ImGui): simulation controls and figures, the
// head, rendering and capture. It reads and changes the view's state and
// sends everything for the simulation through SimulationThread.
#pragma once

#include "viewer/head_drag.hpp"
#include "viewer/simulation_thread.hpp"

#include <deque>
#include <string>

namespace loosehair::viewer {

/// What the window shows and how; the panel and the shortcuts change it.
struct ViewState {
  render::Camera camera;
  render::RenderSettings settings;
  bool light_from_camera = false;
  float light_yaw_deg = 35.0f, light_pitch_deg = 50.0f;  // the fixed light
  bool show_panel = true;
  bool screenshot = false, quit = false;
  std::string message;  // shown in the panel (errors, what was saved)
};

/// The keyboard shortcuts, for the panel and --help.
extern const char* const kShortcuts;

class Panel {
 public:
  Panel(SimulationThread& sim, HeadDrag& head) : sim_(sim), head_(head) {}
  /// Draws the panel for this displayed frame (between ImGui::NewFrame and
  /// ImGui::Render). `fps` is the window's frames per second.
  void draw(ViewState& view, const PublishedFrame& frame, double fps);

 private:
  void simulation(const PublishedFrame& frame, double fps);
  void headControls();
  void rendering(ViewState& view);

  SimulationThread& sim_;
  HeadDrag& head_;
  std::deque<float> frame_ms_;  // the simulation's recent frame times
  std::int64_t last_frame_ = -1;
  float shake_amplitude_deg_ = 35.0f, shake_frequency_hz_ = 1.0f;
  float speed_ = 1.0f;
  bool fastest_ = false;
};

/// The light direction of the panel's two angles (towards the light).
glm::vec3 lightFromAngles(float yaw_deg, float pitch_deg);

}  // namespace loosehair::viewer
