// The viewer's panel (Dear ImGui): scene and style files, the simulation
// and every solver parameter, the head, wind, rendering, capture, the
// styling mode and the shortcuts. Everything it does goes through the
// Controller, as shortcuts and scripts do.
#pragma once

#include "viewer/controller.hpp"

#include <imgui.h>

#include <cstddef>
#include <deque>
#include <string>

namespace loosehair::viewer {

/// The keyboard shortcuts, for the panel and --help.
extern const char* const kShortcuts;

class Panel {
 public:
  explicit Panel(Controller& c) : c_(c) {}
  /// Draws the panel for this displayed frame (between ImGui::NewFrame and
  /// ImGui::Render). `fps` is the window's frames per second.
  void draw(const PublishedFrame& frame, double fps);

  float shake_amplitude_deg = 35.0f, shake_frequency_hz = 1.0f;
  float move_step_mm = 10.0f;  // styling: one press of a move button
  /// What draws the window (GL_RENDERER), shown with the frame rate.
  std::string gl_renderer;
  double gpu_carry_ms = 0.0;                         // the window's last carry of the strands on the GPU (CPU side)
  std::size_t strands_drawn = 0, strands_bound = 0;  // in the last frame drawn

 private:
  std::string shown_preview_error_;  // the styling preview's error last shown

 public:
  /// The last drawn frame's debug-view colours, for the legend.
  render::DebugLegend legend;

 private:
  void files();
  void simulation(const PublishedFrame& frame, double fps);
  void parameters();
  void headControls();
  void wind();
  void rendering();
  void capture();
  void styling();
  void statusWindow(ViewState& view, ImVec2 display);
  void helpWindow(ViewState& view, ImVec2 display);
  void legendWindow(ViewState& view, ImVec2 display);
  static void remember(ViewState& view);

  Controller& c_;
  std::deque<std::pair<double, StageTimes>> stage_ms_;  // recent frames: wall ms, last step's stages
  int plot_stage_ = 0;
  std::int64_t last_frame_ = -1;
  float speed_ = 1.0f;
  bool fastest_ = false;
  char path_[512] = "";
  std::string browse_dir_ = ".";
  char record_dir_[512] = "loosehair-recording";
  char shot_path_[512] = "loosehair-screenshot.png";
  char snapshot_path_[512] = "loosehair-state.lhsnap";
  char style_path_[512] = "my-style.json";
  char motion_path_[512] = "head-motion.json";
  float gust_ = 0.0f, gust_period_ = 2.0f;  // wind: fraction up and down, period (s)
  bool record_mp4_ = true;
  int particles_ = 0;
  int seed_ = 0;
  float last_panel_width_ = 450.0f;  // the status and help windows stand right of it
};

/// The unit direction of the panel's two angles (the light's, towards the
/// light; the wind's, where it blows): yaw about +Y from +Z, pitch above
/// the horizontal.
glm::vec3 directionFromAngles(float yaw_deg, float pitch_deg);

}  // namespace loosehair::viewer
