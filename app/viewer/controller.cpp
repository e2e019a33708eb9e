#include "viewer/controller.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/param_table.hpp"
#include "process.hpp"
#include "video.hpp"

#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace loosehair::viewer {

Controller::Controller(SimulationThread& sim, ViewState& view, HeadDrag& head, std::string scene_path)
    : sim_(sim), view_(view), head_(head), pending_(sim.scene()) {
  remember(scene_path);
}

void Controller::note(const std::string& message) {
  view_.message = message;
  view_.message_is_error = false;
}

void Controller::clearError() {
  if (!view_.message_is_error) return;
  view_.message.clear();
  view_.message_is_error = false;
}

void Controller::fail(const std::string& message) {
  view_.message = message;
  view_.message_is_error = true;
  std::fprintf(stderr, "loosehair-view: %s\n", message.c_str());
}

void Controller::remember(const std::string& path) {
  recent_.erase(std::remove(recent_.begin(), recent_.end(), path), recent_.end());
  recent_.push_front(path);
  while (recent_.size() > 8) recent_.pop_back();
}

namespace {

// A style file has wisps; a scene has none (data/styles/README.md,
// data/scenes/README.md).
bool isStyleFile(const std::string& path) {
  const std::string text = readRegularFile(path, kMaxTextFileBytes);
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  return j.is_object() && j.contains("wisps");
}

}  // namespace

void Controller::open(const std::string& path) {
  attempt([&] {
    SceneDesc next;
    if (isStyleFile(path)) {
      next = sim_.scene();
      next.hair.style = path;
      next.hair.style_data.reset();
      (void)loadStyle(path);  // its own errors now, not from the simulation thread
    } else {
      next = loadScene(path);
      next.sim.threads = sim_.scene().sim.threads;
      next.limits = sim_.scene().limits;  // --allow-expensive holds for scenes opened later
    }
    pending_ = next;
    remember(path);
    if (mode_ == Mode::Styling) {
      styling_.reset();
      enterStyling();
    } else {
      sim_.restart(next);  // a scene that cannot be built leaves the current one (takeError)
    }
    view_.message.clear();
  });
}

void Controller::restart() {
  head_.reset();
  sim_.restart(pending_);
}

bool Controller::setParam(const std::string& name, double value_in, const std::string& source) {
  const ParamInfo* info = findParam(name.c_str());
  if (!info) {
    fail(source + ": no solver parameter called \"" + name + "\"");
    return false;
  }
  double value = value_in;
  try {
    // as a scene file's "solver" object checks it; the few that no file
    // holds by that name (the step, the threads, a component of gravity)
    // against the same table's range
    if (info->in_scene) {
      value = checkSceneValue("solver." + name, value_in, source);
    } else if (const std::string why = info->check(value); !why.empty()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%g", value);
      throw std::invalid_argument(source + ": solver." + name + ": " + why + ", got " + buf);
    }
  } catch (const std::exception& e) {
    fail(e.what());
    return false;
  }
  SimParams p = pending_.sim;
  info->set(p, value);
  const std::vector<std::string> problems = validate(p);
  if (!problems.empty()) {
    fail(problems.front());
    return false;
  }
  if (name == "shape_keeping") pending_.shape_keeping_auto = false;
  if (name == "h1") pending_.h1_auto = false;
  if (name == "h2") pending_.h2_auto = false;
  const bool live = info->live && !(name == "shape_keeping" && value > 0 && sim_.latest()->shape_keeping == 0);
  pending_.sim = p;
  if (!live) return false;
  // the running solver's other parameters stay as they run
  sim_.apply([info, value](Solver& s) {
    SimParams q = s.params();
    info->set(q, value);
    s.setParams(q);
  });
  return true;
}

void Controller::setHair(render::HairGeometry hair) {
  view_.settings.hair = hair;
  sim_.setPublishStrands(hair == render::HairGeometry::Strands ? static_cast<std::size_t>(std::max(1, view_.strands))
                                                               : 0);
}

void Controller::setWind(bool on) {
  pending_.has_wind = on;
  if (!on) return;  // the air goes with a restart
  const WindParams w = pending_.wind;
  attempt([&] {
    const auto problems = validate(w);
    if (!problems.empty()) throw std::invalid_argument(problems.front());
    sim_.apply([w](Solver& s) { s.setWind(w); });
  });
}

void Controller::shake(double amplitude_deg, double frequency_hz, bool nod) {
  // two periods from the next frame, smoothly in and out (as the scenes'
  // shake and nod), about the neck, from where the head is
  const double start = sim_.latest()->time;
  const HeadTrajectory wave =
      (nod ? HeadTrajectory::nod : HeadTrajectory::shake)(glm::radians(amplitude_deg), frequency_hz, 2.0, start);
  const glm::dvec3 pivot = head_.pivot(), base = head_.eulerDeg();
  sim_.setHeadScript([wave, pivot, base](double t) -> std::optional<HeadKeyframe> {
    if (t > wave.endTime()) return std::nullopt;
    return turnAbout(pivot, base + glm::degrees(wave.angles(t)), glm::dvec3(0.0));
  });
}

void Controller::centreHead() {
  head_.reset();
  sim_.setHeadTarget(head_.pose());
}

void Controller::saveHeadMotion(const std::string& path) {
  attempt([&] {
    const std::vector<HeadKeyframe> keys = sim_.headKeys();
    if (keys.size() < 2) throw std::runtime_error("the head has not been moved by hand yet: no motion to save");
    const std::string text = keyframesJson(keys);
    writeFileAtomically(path, {text});
    note("saved the head motion (" + std::to_string(keys.size()) + " keys) to " + path);
  });
}

void Controller::saveSnapshot(const std::string& path) {
  sim_.saveSnapshot(path);
  if (const std::string e = sim_.takeError(); !e.empty())
    fail(e);
  else
    note("saved the state to " + path);
}

void Controller::loadSnapshot(const std::string& path) {
  sim_.loadSnapshot(path);
  if (const std::string e = sim_.takeError(); !e.empty()) {
    fail(e);
    return;
  }
  head_.reset();
  note("resumed from " + path);
}

void Controller::startRecording(const std::string& dir, const std::string& video) {
  attempt([&] {
    namespace fs = std::filesystem;
    if (!video.empty()) (void)app::checkVideoName(video, "the recording's video");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(dir + ": cannot create the directory: " + ec.message());
    if (!fs::is_empty(dir, ec)) throw std::runtime_error(dir + ": the recording folder must be empty or new");
    if (!video.empty() && !app::findProgram("ffmpeg"))
      throw std::runtime_error("recording to MP4 needs ffmpeg, which is not installed");
    recording_ = Recording{dir, video, 0, -1, sim_.paused()};
    note("recording to " + dir);
  });
}

std::string Controller::recordingPath(std::int64_t frame) {
  if (!recording_ || frame == recording_->last_frame) return "";
  recording_->last_frame = frame;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", ++recording_->written);
  return (std::filesystem::path(recording_->dir) / name).string();
}

void Controller::stopRecording() {
  if (!recording_) return;
  const Recording r = *recording_;
  recording_.reset();
  sim_.setPaused(r.was_paused);
  if (r.video.empty() || r.written == 0) {
    note("recorded " + std::to_string(r.written) + " frames to " + r.dir);
    return;
  }
  attempt([&] {
    app::encodeVideo(*app::findProgram("ffmpeg"), r.dir, r.video, sim_.scene().frame_rate);
    note("recorded " + std::to_string(r.written) + " frames to " + r.dir + " and " + r.video);
  });
}

void Controller::enterStyling() {
  if (mode_ == Mode::Styling && styling_) return;
  attempt([&] {
    if (!styling_) {
      const SceneDesc& scene = pending_;
      Style style;
      if (scene.hair.style_data) {
        style = *scene.hair.style_data;
      } else if (!scene.hair.style.empty()) {
        style = loadStyle(scene.hair.style);
      } else {
        style.head = scene;  // the scene's head, no wisps yet
        style.source = scene.source;
        style.name = scene.name + "-style";
      }
      styling_ = std::make_unique<StylingSession>(std::move(style));
    }
    sim_.setPaused(true);
    mode_ = Mode::Styling;
    head_.reset();
  });
}

void Controller::enterSimulate() {
  if (mode_ != Mode::Styling) return;
  mode_ = Mode::Simulate;
  if (!styling_) return;
  if (styling_->style().wisps.empty()) {
    fail("the style has no wisps yet: the scene's own hair simulates");
    sim_.setPaused(false);
    return;
  }
  attempt([&] {
    try {
      checkStyle(styling_->style(), styling_->head());
    } catch (const StyleError& e) {
      // its source is the scene it was started from: say which style it is
      std::string m = e.what();
      const std::string from = styling_->style().source + ": ";
      if (m.rfind(from, 0) == 0) m = m.substr(from.size());
      throw StyleError("the style being edited: " + m);
    }
    SceneDesc next = pending_;
    static_cast<HeadDesc&>(next) = styling_->style().head;
    next.hair.style_data = std::make_shared<const Style>(styling_->style());
    next.hair.style = styling_->style().source;
    pending_ = next;
    sim_.restart(next);
    sim_.setPaused(false);
  });
}

}  // namespace loosehair::viewer
