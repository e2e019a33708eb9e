#include "viewer/panel.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <imgui.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <vector>

namespace loosehair::viewer {

const char* const kShortcuts =
    "left drag: orbit the camera, scroll: zoom\n"
    "right drag: turn the head about the neck, Shift + right drag: move it\n"
    "space: play/pause, N or right arrow: one frame, R: restart\n"
    "S: shadows, C: hair colour, D: debug view, L: light from the camera\n"
    "1 2 3 4: front, side, back, three-quarter camera\n"
    "P: screenshot, Tab: hide or show the panel, H: shortcuts, Esc or Q: quit\n";

glm::vec3 lightFromAngles(float yaw_deg, float pitch_deg) {
  const float y = glm::radians(yaw_deg), p = glm::radians(pitch_deg);
  return glm::normalize(glm::vec3(std::cos(p) * std::sin(y), std::sin(p), std::cos(p) * std::cos(y)));
}

void Panel::draw(ViewState& view, const PublishedFrame& frame, double fps) {
  if (frame.frame != last_frame_) {
    last_frame_ = frame.frame;
    frame_ms_.push_back(static_cast<float>(frame.frame_ms));
    while (frame_ms_.size() > 150) frame_ms_.pop_front();
  }
  if (!view.show_panel) return;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("loosehair");
  ImGui::TextUnformatted(sim_.scene().name.c_str());
  if (!view.message.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.8f, 0.1f, 0.1f, 1.0f));
    ImGui::TextWrapped("%s", view.message.c_str());
    ImGui::PopStyleColor();
    if (ImGui::SmallButton("dismiss")) view.message.clear();
  }
  if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen)) simulation(frame, fps);
  if (ImGui::CollapsingHeader("Head", ImGuiTreeNodeFlags_DefaultOpen)) headControls();
  if (ImGui::CollapsingHeader("Rendering")) rendering(view);
  if (ImGui::CollapsingHeader("Capture")) {
    if (ImGui::Button("Screenshot (P)")) view.screenshot = true;
  }
  if (ImGui::CollapsingHeader("Shortcuts")) ImGui::TextUnformatted(kShortcuts);
  ImGui::End();
}

void Panel::simulation(const PublishedFrame& frame, double fps) {
  const bool paused = sim_.paused();
  if (ImGui::Button(paused ? "Play" : "Pause")) sim_.setPaused(!paused);
  ImGui::SameLine();
  if (ImGui::Button("Step")) sim_.stepOnce();
  ImGui::SameLine();
  if (ImGui::Button("Restart")) sim_.restart(sim_.scene());
  bool changed = ImGui::Checkbox("as fast as possible", &fastest_);
  if (!fastest_) {
    changed |= ImGui::SliderFloat("speed", &speed_, 0.1f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("simulated seconds per second of wall time (at most)");
  }
  if (changed) sim_.setSpeed(fastest_ ? 0.0 : static_cast<double>(speed_));
  ImGui::Text("t = %.2f s, frame %" PRId64 "%s", frame.time, frame.frame, frame.paused ? " (paused)" : "");
  ImGui::Text("%.2fx real time, window %.1f frames/s", frame.real_time_factor, fps);
  ImGui::Text("%zu particles, %zu connections", frame.particles, frame.connections);
  ImGui::Text("%zu body contacts, %zu neighbour pairs", frame.contacts, frame.neighbor_pairs);
  ImGui::Text("state hash %016" PRIx64, frame.state_hash);
  if (!frame_ms_.empty()) {
    const std::vector<float> ms(frame_ms_.begin(), frame_ms_.end());
    char label[64];
    std::snprintf(label, sizeof label, "%.1f ms a frame", static_cast<double>(ms.back()));
    ImGui::PlotLines("##frame ms", ms.data(), static_cast<int>(ms.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 50));
  }
  const StageTimes& s = frame.last_step;
  ImGui::Text("last step %.2f ms: neighbours %.2f, density %.2f,", 1e3 * s.total(), 1e3 * s.neighbors, 1e3 * s.density);
  ImGui::Text("  springs %.2f, hair-hair %.2f, strain limit %.2f", 1e3 * s.springs, 1e3 * s.hair_hair,
              1e3 * s.strain_limit);
}

void Panel::headControls() {
  ImGui::TextWrapped("Right drag turns the head about its neck, Shift + right drag moves it.");
  const glm::dvec3 e = head_.eulerDeg();
  ImGui::Text("turned: yaw %.0f, pitch %.0f degrees", e.x, e.y);
  if (ImGui::Button("Centre the head")) {
    head_.reset();
    sim_.setHeadTarget(head_.pose());
  }
  ImGui::SliderFloat("amplitude", &shake_amplitude_deg_, 5.0f, 80.0f, "%.0f deg");
  ImGui::SliderFloat("frequency", &shake_frequency_hz_, 0.2f, 3.0f, "%.1f Hz");
  const bool shake = ImGui::Button("Shake");
  ImGui::SameLine();
  const bool nod = ImGui::Button("Nod");
  if (shake || nod) {
    // two periods from the next frame, smoothly in and out (as the scenes'
    // shake and nod), about the neck, from where the head is
    const double start = sim_.latest()->time;
    const HeadTrajectory wave =
        (shake ? HeadTrajectory::shake : HeadTrajectory::nod)(glm::radians(static_cast<double>(shake_amplitude_deg_)),
                                                               shake_frequency_hz_, 2.0, start);
    const glm::dvec3 pivot = head_.pivot(), base = head_.eulerDeg();
    sim_.setHeadScript([wave, pivot, base](double t) -> std::optional<HeadKeyframe> {
      if (t > wave.endTime()) return std::nullopt;
      return turnAbout(pivot, base + glm::degrees(wave.angles(t)), glm::dvec3(0.0));
    });
  }
}

void Panel::rendering(ViewState& view) {
  static const char* colours[] = {"black", "brown", "blonde", "red"};
  int c = static_cast<int>(view.settings.color);
  if (ImGui::Combo("hair colour", &c, colours, 4)) view.settings.color = static_cast<render::HairColor>(c);
  ImGui::Checkbox("shadows", &view.settings.shadows);
  static const char* views[] = {"hair", "density", "speed", "connections", "directions"};
  int d = static_cast<int>(view.settings.debug);
  if (ImGui::Combo("debug view", &d, views, 5)) view.settings.debug = static_cast<render::DebugView>(d);
  ImGui::Checkbox("light from the camera", &view.light_from_camera);
  if (!view.light_from_camera) {
    ImGui::SliderFloat("light yaw", &view.light_yaw_deg, -180.0f, 180.0f, "%.0f deg");
    ImGui::SliderFloat("light pitch", &view.light_pitch_deg, -10.0f, 90.0f, "%.0f deg");
  }
  ImGui::SliderFloat("billboard width", &view.settings.billboard_width, 0.5f, 8.0f, "%.1f x spacing");
  ImGui::SliderFloat("billboard length", &view.settings.billboard_length, 2.0f, 20.0f, "%.1f x spacing");
  ImGui::SliderFloat("opacity", &view.settings.hair_opacity, 0.05f, 1.0f, "%.2f");
}

}  // namespace loosehair::viewer
