#include "viewer/panel.hpp"

#include "loosehair/render/gl_loader.hpp"
#include "viewer/viewer_values.hpp"

#include "loosehair/param_table.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace loosehair::viewer {

// A value typed into a slider (Ctrl+click) stays within the slider's range,
// which lies within what the scene and style files allow.
constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;

const char* const kShortcuts =
    "left drag: orbit the camera (styling: on the scalp, brush), scroll: zoom\n"
    "right drag: turn the head about the neck, Shift + right drag: move it\n"
    "space: play/pause, N or right arrow: one frame, R: restart\n"
    "S: shadows, C: hair colour, D: debug view, L: light turns with the camera\n"
    "1 2 3 4: front, side, back, three-quarter camera\n"
    "F2: styling mode or back to simulating\n"
    "styling: click a control point to select it, T/G/B: tangent, normal or\n"
    "  binormal direction, Up/Down: move along it, Ctrl+Z / Ctrl+Shift+Z: undo/redo\n"
    "P: screenshot, Tab: hide or show the panel, H: shortcuts, Esc or Q: quit\n";

glm::vec3 directionFromAngles(float yaw_deg, float pitch_deg) {
  const float y = glm::radians(yaw_deg), p = glm::radians(pitch_deg);
  return glm::normalize(glm::vec3(std::cos(p) * std::sin(y), std::sin(p), std::cos(p) * std::cos(y)));
}

namespace {

void tooltip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

}  // namespace

void Panel::draw(const PublishedFrame& frame, double fps) {
  ViewState& view = c_.view();
  if (frame.frame != last_frame_) {
    last_frame_ = frame.frame;
    stage_ms_.emplace_back(frame.frame_ms, frame.last_step);
    while (stage_ms_.size() > 150) stage_ms_.pop_front();  // five seconds at 30 frames/s
  }
  view.ui_rects.clear();
  view.panel_width = 0;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  statusWindow(view, display);
  helpWindow(view, display);
  legendWindow(view, display);
  if (!view.show_panel) return;
  // the panel stands at the left, as tall as the window; its width is the
  // user's (dragging its right edge)
  ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(450, display.y), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSizeConstraints(ImVec2(300, display.y), ImVec2(600, display.y));
  ImGui::Begin("loosehair", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse);
  remember(view);
  view.panel_width = ImGui::GetWindowSize().x;
  ImGui::Text("%s  [%s]", c_.sim().scene().name.c_str(), c_.mode() == Mode::Styling ? "styling" : "simulating");
  if (ImGui::Button(c_.mode() == Mode::Styling ? "Simulate this style (F2)" : "Style the hair (F2)")) {
    if (c_.mode() == Mode::Styling)
      c_.enterSimulate();
    else
      c_.enterStyling();
  }
  auto section = [&](const char* name, bool open_by_default) {
    if (view.open_section == name) ImGui::SetNextItemOpen(true);
    return ImGui::CollapsingHeader(name, open_by_default ? ImGuiTreeNodeFlags_DefaultOpen : 0);
  };
  if (c_.mode() == Mode::Styling) {
    if (section("Styling", true)) styling();
  } else {
    if (section("Simulation", true)) simulation(frame, fps);
    if (section("Solver parameters", false)) parameters();
    if (section("Head", true)) headControls();
    if (section("Wind", false)) wind();
  }
  if (section("Scene and style files", false)) files();
  if (section("Rendering", false)) rendering();
  if (section("Capture", false)) capture();
  if (section("Shortcuts", false)) ImGui::TextUnformatted(kShortcuts);
  view.open_section.clear();
  last_panel_width_ = view.panel_width;
  ImGui::End();
}

void Panel::remember(ViewState& view) {
  const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
  view.ui_rects.emplace_back(at.x, at.y, at.x + size.x, at.y + size.y);
}

// Messages (what was saved, what went wrong) in a window of their own at the
// foot of the 3-D view: nothing in the panel moves when one appears, and a
// scrolled panel does not hide it.
void Panel::statusWindow(ViewState& view, ImVec2 display) {
  if (view.message.empty()) return;
  const float left = view.show_panel ? last_panel_width_ : 0.0f;
  ImGui::SetNextWindowPos(ImVec2(left + 8, display.y - 8), ImGuiCond_Always, ImVec2(0, 1));
  ImGui::SetNextWindowSizeConstraints(ImVec2(200, 0), ImVec2(std::max(200.0f, display.x - left - 16), display.y / 3));
  ImGui::Begin("##status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove);
  remember(view);
  ImGui::PushStyleColor(ImGuiCol_Text,
                        view.message_is_error ? ImVec4(0.75f, 0.1f, 0.1f, 1.0f) : ImVec4(0.1f, 0.4f, 0.15f, 1.0f));
  ImGui::PushTextWrapPos(std::max(200.0f, std::min(900.0f, display.x - left - 40)));
  ImGui::TextUnformatted(view.message.c_str());
  ImGui::PopTextWrapPos();
  ImGui::PopStyleColor();
  if (ImGui::SmallButton("dismiss")) view.message.clear();
  ImGui::End();
}

// What the density and speed views' colours mean: the ramp from the
// frame's least to its greatest value, with the unit, at the view's top
// right.
void Panel::legendWindow(ViewState& view, ImVec2 display) {
  if (!legend.shown || view.settings.debug != legend.view) return;
  ImGui::SetNextWindowPos(ImVec2(display.x - 8, 8), ImGuiCond_Always, ImVec2(1, 0));
  ImGui::Begin("##legend", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove);
  remember(view);
  ImGui::Text("%s (%s)", legend.view == render::DebugView::Density ? "density" : "speed", legend.unit);
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float w = 220.0f, h = 14.0f;
  constexpr int kSteps = 32;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  for (int k = 0; k < kSteps; ++k) {
    const float t0 = static_cast<float>(k) / kSteps, t1 = static_cast<float>(k + 1) / kSteps;
    const glm::vec3 a = render::debugRamp(t0), b = render::debugRamp(t1);
    const ImU32 ca = ImGui::GetColorU32(ImVec4(a.r, a.g, a.b, 1.0f)),
                cb = ImGui::GetColorU32(ImVec4(b.r, b.g, b.b, 1.0f));
    draw->AddRectFilledMultiColor(ImVec2(at.x + w * t0, at.y), ImVec2(at.x + w * t1, at.y + h), ca, cb, cb, ca);
  }
  ImGui::Dummy(ImVec2(w, h));
  ImGui::Text("%-10.3g", static_cast<double>(legend.low));
  ImGui::SameLine(w - ImGui::CalcTextSize("0000000000").x + 8);
  ImGui::Text("%10.3g", static_cast<double>(legend.high));
  ImGui::End();
}

// The shortcuts (H), over the middle of the 3-D view.
void Panel::helpWindow(ViewState& view, ImVec2 display) {
  if (!view.show_help) return;
  const float left = view.show_panel ? last_panel_width_ : 0.0f;
  ImGui::SetNextWindowPos(ImVec2(left + 0.5f * (display.x - left), 0.5f * display.y), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::Begin("Shortcuts (H to close)", &view.show_help,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoMove);
  remember(view);
  ImGui::TextUnformatted(kShortcuts);
  ImGui::End();
}

void Panel::files() {
  ImGui::InputText("file", path_, sizeof path_);
  tooltip("a scene (.json) or a style (a .json with wisps; grown on this scene's head)");
  if (ImGui::Button("Open")) c_.open(path_);
  // a small browser: the folders and .json files of browse_dir_
  namespace fs = std::filesystem;
  ImGui::Text("in %s:", browse_dir_.c_str());
  ImGui::BeginChild("browse", ImVec2(0, 110), true);
  std::error_code ec;
  std::vector<fs::path> entries;
  for (fs::directory_iterator it(browse_dir_, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) || it->path().extension() == ".json") entries.push_back(it->path());
  std::sort(entries.begin(), entries.end());
  if (ImGui::Selectable("..")) browse_dir_ = fs::absolute(browse_dir_, ec).parent_path().string();
  for (const fs::path& e : entries) {
    const bool dir = fs::is_directory(e, ec);
    const std::string label = e.filename().string() + (dir ? "/" : "");
    if (ImGui::Selectable(label.c_str())) {
      if (dir)
        browse_dir_ = e.string();
      else
        std::snprintf(path_, sizeof path_, "%s", e.string().c_str());
    }
  }
  if (ec) ImGui::TextDisabled("%s", ec.message().c_str());
  ImGui::EndChild();
  ImGui::TextDisabled("recent:");
  for (const std::string& r : c_.recent()) {
    if (ImGui::Selectable(r.c_str())) {
      std::snprintf(path_, sizeof path_, "%s", r.c_str());
      c_.open(r);
    }
  }
  SceneDesc& p = c_.pending();
  if (particles_ == 0) particles_ = p.hair.particles, seed_ = static_cast<int>(p.seed);
  ImGui::InputInt("particles", &particles_, 500, 5000);
  tooltip("target particle count of the cantilever hair (applies on restart)");
  ImGui::InputInt("seed", &seed_);
  tooltip("random seed of the hair sampling (applies on restart)");
  if (ImGui::Button("Re-initialise")) {
    c_.attempt([&] {
      // as a scene file's hair.particles and seed are checked
      const double n = checkViewerValue("particles", particles_, "the panel");
      const double seed = checkViewerValue("seed", seed_, "the panel");
      p.hair.particles = static_cast<int>(n);
      p.seed = static_cast<std::uint64_t>(seed);
      c_.restart();
    });
  }
}

void Panel::simulation(const PublishedFrame& frame, double fps) {
  SimulationThread& sim = c_.sim();
  const bool paused = sim.paused();
  if (ImGui::Button(paused ? "Play" : "Pause")) sim.setPaused(!paused);
  ImGui::SameLine();
  if (ImGui::Button("Step")) sim.stepOnce();
  ImGui::SameLine();
  if (ImGui::Button("Restart")) c_.restart();
  // as the simulation runs now (a script or a shortcut may have set it)
  fastest_ = sim.speed() == 0.0;
  if (!fastest_) speed_ = static_cast<float>(sim.speed());
  bool changed = ImGui::Checkbox("as fast as possible", &fastest_);
  if (!fastest_) {
    changed |= ImGui::SliderFloat("speed", &speed_, 0.1f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic | kClamp);
    tooltip("simulated seconds per second of wall time (at most)");
  }
  if (changed) sim.setSpeed(fastest_ ? 0.0 : static_cast<double>(speed_));
  ImGui::Text("t = %.2f s, frame %" PRId64 "%s", frame.time, frame.frame, frame.paused ? " (paused)" : "");
  ImGui::Text("%.2fx real time, window %.1f frames/s", frame.real_time_factor, fps);
  {
    // software rasterisers by name (Mesa's llvmpipe, softpipe, swrast)
    const std::string& r = gl_renderer;
    ImGui::TextWrapped("drawn by %s: %s", render::softwareRenderer(r) ? "the CPU (software OpenGL)" : "the GPU",
                       r.empty() ? "unknown" : r.c_str());
  }
  if (const auto strands = c_.sim().latestStrands()) {
    const bool gpu = strands->field != nullptr;
    ImGui::TextWrapped("strands of frame %" PRId64 ", carried %s (%.1f ms a carry)", strands->frame,
                       gpu ? "by a compute shader" : "on the CPU", gpu ? gpu_carry_ms : strands->carry_ms);
    if (strands_bound > 0 && strands_drawn < strands_bound)
      ImGui::Text("%zu of %zu strands drawn (%s)", strands_drawn, strands_bound,
                  c_.view().settings.strand_budget > 0 ? "while playing" : "level of detail");
  }
  ImGui::Text("%zu particles, %zu connections", frame.particles, frame.connections);
  ImGui::Text("%zu body contacts, %zu neighbour pairs", frame.contacts, frame.neighbor_pairs);
  ImGui::Text("state hash %016" PRIx64, frame.state_hash);
  static const char* stages[] = {"whole frame",   "step: all stages", "neighbours", "density",      "springs",
                                 "hair-hair",     "external",         "integrate",  "strain limit", "tethers",
                                 "body contacts", "directions",       "air"};
  ImGui::Combo("plot", &plot_stage_, stages, IM_ARRAYSIZE(stages));
  tooltip("the last five seconds of one stage's time (ms)");
  if (!stage_ms_.empty()) {
    std::vector<float> ms;
    for (const auto& [frame_ms, st] : stage_ms_) {
      const double v[] = {frame_ms,          1e3 * st.total(),       1e3 * st.neighbors,
                          1e3 * st.density,  1e3 * st.springs,       1e3 * st.hair_hair,
                          1e3 * st.external, 1e3 * st.integrate,     1e3 * st.strain_limit,
                          1e3 * st.tethers,  1e3 * st.body_contacts, 1e3 * st.directions,
                          1e3 * st.air};
      ms.push_back(static_cast<float>(v[plot_stage_]));
    }
    char label[64];
    std::snprintf(label, sizeof label, "%.2f ms", static_cast<double>(ms.back()));
    ImGui::PlotLines("##stage ms", ms.data(), static_cast<int>(ms.size()), 0, label, 0.0f, FLT_MAX, ImVec2(0, 50));
  }
  const StageTimes& s = frame.last_step;
  ImGui::Text("last step %.2f ms: neighbours %.2f, density %.2f,", 1e3 * s.total(), 1e3 * s.neighbors, 1e3 * s.density);
  ImGui::Text("  springs %.2f, hair-hair %.2f, external %.2f,", 1e3 * s.springs, 1e3 * s.hair_hair, 1e3 * s.external);
  ImGui::Text("  integrate %.2f, strain limit %.2f, tethers %.2f,", 1e3 * s.integrate, 1e3 * s.strain_limit,
              1e3 * s.tethers);
  ImGui::Text("  body contacts %.2f, directions %.2f, air %.2f", 1e3 * s.body_contacts, 1e3 * s.directions,
              1e3 * s.air);
  SimParams& p = c_.pending().sim;
  bool hh = p.hair_hair;
  if (ImGui::Checkbox("hair-hair interactions", &hh)) c_.setParam("hair_hair", hh ? 1.0 : 0.0);
  bool keep = frame.shape_keeping > 0;
  if (ImGui::Checkbox("shape keeping", &keep)) c_.setParam("shape_keeping", keep ? 1.0 : 0.0);
  tooltip("hold a style's shape; turning it on applies on restart");
  if (frame.shape_keeping > 0) {
    ImGui::SameLine();
    ImGui::Text("%.2g Hz", frame.shape_keeping);
  }
}

void Panel::parameters() {
  ImGui::TextWrapped("Live changes apply at the next frame; (restart) marks those that apply on restart.");
  SimParams& p = c_.pending().sim;
  ImGui::PushItemWidth(ImGui::GetFontSize() * 10);
  for (const ParamInfo& info : paramTable()) {
    ImGui::PushID(info.name);
    char label[96];
    std::snprintf(label, sizeof label, "%s%s%s%s", info.name, *info.unit ? " (" : "", info.unit, *info.unit ? ")" : "");
    const double before = info.get(p);
    double v = before;
    bool changed = false;
    if (info.kind == ParamInfo::Kind::Switch) {
      bool b = v != 0;
      changed = ImGui::Checkbox(label, &b);
      v = b ? 1 : 0;
    } else {
      // the parameter's one range (param_table.cpp), dragged in ratios
      // where it spans decades; Ctrl+click types a value
      const double lo = info.lo_open ? std::nextafter(info.lo, info.hi) : info.lo, hi = info.hi;
      const ImGuiSliderFlags flags = (info.logarithmic ? ImGuiSliderFlags_Logarithmic : 0) | kClamp;
      // a logarithmic drag moves through [0, 1] of the range's log: 500 px
      // cross it; a linear one moves by 0.5 % of the value (or of the range)
      // a pixel
      const double log_speed = 0.002 * (hi - lo);
      if (info.kind == ParamInfo::Kind::Integer) {
        int i = static_cast<int>(v);
        const float speed = static_cast<float>(info.logarithmic ? log_speed : 0.2);
        changed = ImGui::DragInt(label, &i, speed, static_cast<int>(lo), static_cast<int>(hi), "%d", flags);
        v = i;
      } else {
        const double linear_speed = 0.005 * std::max(std::abs(v), 0.01 * (hi - lo));
        const float speed = static_cast<float>(info.logarithmic ? log_speed : linear_speed);
        changed = ImGui::DragScalar(label, ImGuiDataType_Double, &v, speed, &lo, &hi, "%.4g", flags);
      }
    }
    char help[320];
    std::snprintf(help, sizeof help, "%s\nvalues %s%g to %g%s", info.help, info.lo_open ? "above " : "", info.lo,
                  info.hi, info.live ? "" : "\napplies on restart");
    tooltip(help);
    if (!info.live) {
      ImGui::SameLine();
      ImGui::TextDisabled("(restart)");
    }
    if (changed) c_.setParam(info.name, v);
    ImGui::PopID();
  }
  ImGui::PopItemWidth();
}

void Panel::headControls() {
  ImGui::TextWrapped("Right drag turns the head about its neck, Shift + right drag moves it.");
  const glm::dvec3 e = c_.head().eulerDeg();
  ImGui::Text("turned: yaw %.0f, pitch %.0f degrees", e.x, e.y);
  if (ImGui::Button("Centre the head")) c_.centreHead();
  ImGui::SliderFloat("amplitude", &shake_amplitude_deg, 5.0f, 80.0f, "%.0f deg", kClamp);
  ImGui::SliderFloat("frequency", &shake_frequency_hz, 0.2f, 3.0f, "%.1f Hz", kClamp);
  if (ImGui::Button("Shake")) c_.shake(shake_amplitude_deg, shake_frequency_hz, false);
  ImGui::SameLine();
  if (ImGui::Button("Nod")) c_.shake(shake_amplitude_deg, shake_frequency_hz, true);
  ImGui::InputText("##motion", motion_path_, sizeof motion_path_);
  ImGui::SameLine();
  if (ImGui::Button("Save head motion")) c_.saveHeadMotion(motion_path_);
  tooltip("the head as moved by hand, for loosehair simulate SCENE --motion FILE");
}

void Panel::wind() {
  SceneDesc& p = c_.pending();
  ViewState& v = c_.view();
  bool on = p.has_wind;
  bool changed = ImGui::Checkbox("wind", &on);
  tooltip(
      "air blown through the hair (a grid, or SPH particles with wind.model \"particles\"); off applies on restart");
  glm::vec3 d = glm::normalize(p.wind.direction);
  float yaw = glm::degrees(std::atan2(d.x, d.z)), pitch = glm::degrees(std::asin(std::clamp(d.y, -1.0f, 1.0f)));
  changed |= ImGui::SliderFloat("towards, yaw", &yaw, -180.0f, 180.0f, "%.0f deg", kClamp);
  changed |= ImGui::SliderFloat("towards, pitch", &pitch, -60.0f, 60.0f, "%.0f deg", kClamp);
  changed |= ImGui::SliderFloat("speed##wind", &p.wind.speed, 0.0f, 10.0f, "%.1f m/s", kClamp);
  changed |= ImGui::SliderFloat("gusts", &gust_, 0.0f, 1.0f, "%.2f", kClamp);
  tooltip("the wind speed varies by this fraction up and down");
  changed |= ImGui::SliderFloat("gust period", &gust_period_, 0.5f, 10.0f, "%.1f s", kClamp);
  ImGui::Checkbox("wind arrow", &v.show_wind_arrow);
  if (changed) {
    p.wind.direction = directionFromAngles(yaw, pitch);
    p.wind.profile.clear();
    if (gust_ > 0) {  // rising and falling every half period for the next minute (then held)
      const double t0 = c_.sim().latest()->time;
      for (int k = 0; k <= static_cast<int>(120.0f / gust_period_); ++k)
        p.wind.profile.emplace_back(t0 + 0.5 * gust_period_ * k, k % 2 ? 1.0f + gust_ : 1.0f - gust_);
    }
    c_.setWind(on);
  }
}

void Panel::rendering() {
  ViewState& view = c_.view();
  static const char* colours[] = {"black", "brown", "blonde", "red"};
  int c = static_cast<int>(view.settings.color);
  if (ImGui::Combo("hair colour", &c, colours, 4)) {
    view.settings.color = static_cast<render::HairColor>(c);
    view.settings.custom_color.reset();
  }
  bool own = view.settings.custom_color.has_value();
  if (ImGui::Checkbox("own colour", &own))
    view.settings.custom_color = own ? std::optional<glm::vec3>(glm::vec3(0.3f, 0.18f, 0.1f)) : std::nullopt;
  if (view.settings.custom_color) ImGui::ColorEdit3("colour", &view.settings.custom_color->x);
  ImGui::Checkbox("shadows", &view.settings.shadows);
  static const char* views[] = {"hair", "density", "speed", "connections", "directions"};
  int d = static_cast<int>(view.settings.debug);
  if (ImGui::Combo("debug view", &d, views, 5)) view.settings.debug = static_cast<render::DebugView>(d);
  if (ImGui::Checkbox("neighbour grid cells", &view.show_grid)) c_.sim().setPublishGrid(view.show_grid);
  if (ImGui::Checkbox("air particles", &view.show_air)) c_.sim().setPublishAir(view.show_air);
  ImGui::Checkbox("light turns with the camera", &view.light_from_camera);
  if (!view.light_from_camera) {
    ImGui::SliderFloat("light yaw", &view.light_yaw_deg, -180.0f, 180.0f, "%.0f deg", kClamp);
    ImGui::SliderFloat("light pitch", &view.light_pitch_deg, -10.0f, 90.0f, "%.0f deg", kClamp);
    ImGui::Checkbox("light arrow", &view.show_light_arrow);
  }
  static const char* hairs[] = {"billboards", "strands"};
  int hair = view.settings.hair == render::HairGeometry::Strands ? 1 : 0;
  if (ImGui::Combo("hair", &hair, hairs, 2))
    c_.setHair(hair == 1 ? render::HairGeometry::Strands : render::HairGeometry::Billboards);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("billboards: one a particle (the LCP paper); strands: thin strands the particles carry");
  if (view.settings.hair == render::HairGeometry::Strands) {
    ImGui::SliderInt("strands", &view.strands, 1000, 100000, "%d", kClamp);
    if (ImGui::IsItemDeactivatedAfterEdit()) c_.setHair(render::HairGeometry::Strands);
    static const char* shadings[] = {"Kajiya-Kay", "Marschner"};
    int sh = view.settings.shading == render::HairShading::Marschner ? 1 : 0;
    if (ImGui::Combo("shading", &sh, shadings, 2))
      view.settings.shading = sh == 1 ? render::HairShading::Marschner : render::HairShading::KajiyaKay;
    ImGui::SliderInt("supersampling", &view.settings.supersample, 1, 3, "%dx", kClamp);
    ImGui::Checkbox("fewer strands when the hair is small", &view.settings.strand_lod);
    tooltip("level of detail: every k-th strand, k times as opaque, where they overlap more than 8 deep");
    ImGui::SliderInt("strands while playing", &view.playing_strand_budget, 0, 100000,
                     view.playing_strand_budget == 0 ? "all" : "%d", kClamp);
    tooltip(
        "at most this many strands drawn while the hair moves, each standing for several (0: all); "
        "all of them when paused or recording");
  }
  ImGui::SliderFloat("billboard width", &view.settings.billboard_width, 0.5f, 8.0f, "%.1f x spacing", kClamp);
  ImGui::SliderFloat("billboard length", &view.settings.billboard_length, 2.0f, 20.0f, "%.1f x spacing", kClamp);
  ImGui::SliderFloat("opacity", &view.settings.hair_opacity, 0.05f, 1.0f, "%.2f", kClamp);
}

void Panel::capture() {
  ViewState& view = c_.view();
  ImGui::InputText("##shot", shot_path_, sizeof shot_path_);
  ImGui::SameLine();
  if (ImGui::Button("Screenshot")) {
    view.screenshot = true;
    view.screenshot_path = shot_path_;
  }
  ImGui::InputText("##record", record_dir_, sizeof record_dir_);
  ImGui::SameLine();
  if (!c_.recording()) {
    if (ImGui::Button("Record")) {
      const std::string dir = record_dir_;
      c_.startRecording(dir, record_mp4_ ? dir + ".mp4" : "");
    }
  } else if (ImGui::Button("Stop recording")) {
    c_.stopRecording();
  }
  ImGui::Checkbox("and encode an MP4 when stopped (ffmpeg)", &record_mp4_);
  ImGui::InputText("##snapshot", snapshot_path_, sizeof snapshot_path_);
  if (ImGui::Button("Save state")) c_.saveSnapshot(snapshot_path_);
  ImGui::SameLine();
  if (ImGui::Button("Load state")) c_.loadSnapshot(snapshot_path_);
  tooltip("a snapshot of this scene resumes bit-identically");
}

void Panel::styling() {
  StylingSession* s = c_.styling();
  if (!s) {
    ImGui::TextWrapped("The style could not be opened.");
    return;
  }
  const Style& st = s->style();
  ImGui::Text("%zu wisps, %zu ties, preview %zu strands", st.wisps.size(), st.ties.size(), s->previewStrands());
  ImGui::Checkbox("coverage view", &s->show_coverage);
  tooltip("marks in red the scalp with no strand root within 5 mm");
  if (s->show_coverage && s->covered() >= 0.0) {
    ImGui::SameLine();
    ImGui::Text("%.1f %% of the scalp covered", 100.0 * s->covered());
  }
  // the preview's error goes to the status window over the view (a line
  // here would move the buttons under the mouse), once a change
  if (s->preview_error != shown_preview_error_) {
    shown_preview_error_ = s->preview_error;
    if (!shown_preview_error_.empty()) c_.fail("the preview cannot be grown: " + shown_preview_error_);
  }
  ImGui::TextWrapped(
      "Left drag on the scalp brushes a region. Drag a control point to move it (the points "
      "after it follow), an arrow of the selected point to move along it, or a key strand "
      "between its points to move it whole; each drag is one undo.");
  ImGui::SliderFloat("drag falloff", &s->drag_falloff, 0.0f, 0.3f, "%.2f m", kClamp);
  tooltip("how far along the strand the points after a dragged one follow it (0: the point alone)");
  {
    static const char* tools[] = {"select and drag", "comb", "length", "puff", "smooth", "curl", "tie"};
    int t = static_cast<int>(s->tool);
    if (ImGui::Combo("tool", &t, tools, 7)) s->tool = static_cast<StylingSession::Tool>(t);
    tooltip(
        "what a left drag does: select and drag points (on the scalp: paint a region), or brush the key "
        "strands: comb (pull along the drag, tips most), length (grow; with Shift: cut), puff (lift from the "
        "scalp), smooth, curl (the curl below to the wisps touched), tie (click where key strands pass: "
        "the key strands within the brush gathered into a ring off the head)");
    if (s->tool != StylingSession::Tool::Select) {
      ImGui::SliderFloat("brush size", &s->brush_pixels, 5.0f, 300.0f, "%.0f px", kClamp);
      if (s->tool != StylingSession::Tool::Tie)
        ImGui::SliderFloat("strength", &s->brush_strength, 0.0f, 1.0f, "%.2f", kClamp);
    }
    if (s->tool == StylingSession::Tool::Curl) {
      ImGui::SliderFloat("curl radius", &s->curl_radius, 0.0f, 0.05f, "%.3f m", kClamp);
      ImGui::SliderFloat("curl period", &s->curl_period, 0.005f, 0.2f, "%.3f m", kClamp);
    }
    ImGui::Checkbox("mirror editing", &s->mirror_editing);
    tooltip("every edit of a key strand also shapes the wisp rooted at its mirror image across the head");
  }
  ImGui::SliderFloat("brush radius", &s->brush_radius, 0.004f, 0.05f, "%.3f m", kClamp);
  ImGui::Text("brushed: %zu triangles", s->brushed().size());
  ImGui::SameLine();
  if (ImGui::SmallButton("clear")) s->clearBrush();
  ImGui::SliderFloat("density", &c_.new_wisp.density, 1.0f, 100.0f, "%.0f strands/cm^2", kClamp);
  ImGui::SliderFloat("offset radius", &c_.new_wisp.offset_radius, 0.0f, 0.05f, "%.3f m", kClamp);
  tooltip("smooth (small) to fuzzy (large) wisps");
  ImGui::SliderFloat("length variation", &c_.new_wisp.length_variation, 0.0f, 0.9f, "%.2f", kClamp);
  ImGui::SliderFloat("blend", &c_.new_wisp.blend, 0.0f, 1.0f, "%.2f", kClamp);
  tooltip(
      "members near a wisp's border take the neighbouring wisps' shapes, so adjacent wisps meet without "
      "a gap (0: translated copies of the own key strand; never across a parting)");
  ImGui::SliderFloat("hairline ramp", &c_.new_wisp.edge_ramp, 0.0f, 0.05f, "%.3f m", kClamp);
  tooltip(
      "members within this distance of the edge of the hair thin out towards it, so the hairline is not "
      "a row of bristles (0: none)");
  ImGui::SliderFloat("new wisp length", &s->new_wisp_length, 0.02f, 1.0f, "%.2f m", kClamp);
  tooltip("a new wisp's key strand hangs from the scalp under gravity, this long");
  if (ImGui::Button("Create wisp")) c_.attempt([&] { s->createWispFromBrush(c_.new_wisp); });
  ImGui::SameLine();
  if (ImGui::Button("Set region")) c_.attempt([&] { s->setRegionFromBrush(); });
  if (s->wisp) {
    ImGui::Separator();
    const std::string point = s->point ? std::to_string(*s->point) : std::string("none");
    ImGui::Text("wisp %zu (%s), control point %s", *s->wisp, st.wisps[*s->wisp].name.c_str(), point.c_str());
    if (ImGui::Button("Apply density etc. to it")) c_.attempt([&] { s->editor().setParams(*s->wisp, c_.new_wisp); });
    static const char* axes[] = {"tangent", "normal", "binormal"};
    int a = static_cast<int>(s->axis);
    if (ImGui::Combo("direction", &a, axes, 3)) s->axis = static_cast<StylingAxis>(a);
    ImGui::SliderFloat("step", &move_step_mm, 1.0f, 50.0f, "%.0f mm", kClamp);
    if (ImGui::Button("Move -")) c_.attempt([&] { s->moveSelected(-1e-3f * move_step_mm); });
    ImGui::SameLine();
    if (ImGui::Button("Move +")) c_.attempt([&] { s->moveSelected(1e-3f * move_step_mm); });
    if (ImGui::Button("Add point")) c_.attempt([&] { s->addPointAfterSelected(); });
    ImGui::SameLine();
    if (ImGui::Button("Delete point")) c_.attempt([&] { s->deleteSelectedPoint(); });
    ImGui::SameLine();
    if (ImGui::Button("Delete wisp")) c_.attempt([&] { s->deleteSelectedWisp(); });
    if (ImGui::Button("Copy strand")) c_.attempt([&] { s->copySelected(); });
    ImGui::SameLine();
    if (ImGui::Button("Paste strand")) c_.attempt([&] { s->pasteOnSelected(); });
    ImGui::SameLine();
    if (ImGui::Button("Mirror")) c_.attempt([&] { s->mirrorSelected(); });
    if (ImGui::Button("Tie here")) c_.attempt([&] { s->tieAtSelected(0.015f); });
  }
  ImGui::Separator();
  ImGui::SliderFloat("settle time", &s->settle_seconds, 0.2f, 5.0f, "%.1f s", kClamp);
  tooltip(
      "Settle simulates the style on a still head for this long (gravity, the head, the other hair) and "
      "puts the key strands where the hair came to rest; one undo step");
  if (s->settling()) {
    ImGui::Text("settling ...");
  } else if (ImGui::Button("Settle")) {
    c_.attempt([&] { s->startSettle(); });
  }
  if (ImGui::Button("Undo")) s->undo(), c_.clearError();
  ImGui::SameLine();
  if (ImGui::Button("Redo")) s->redo(), c_.clearError();
  ImGui::InputText("##style", style_path_, sizeof style_path_);
  ImGui::SameLine();
  if (ImGui::Button("Save style"))
    c_.attempt([&] {
      s->save(style_path_);
      c_.note(std::string("saved the style to ") + style_path_);
    });
}

}  // namespace loosehair::viewer
