// What the viewer can be told to do, by name: the panel's buttons, the
// keyboard shortcuts and scripted runs (--script) all call these, so a
// script does exactly what a user does. Failures become the message shown
// in the panel (and printed); the running simulation is never lost to a
// bad file or value.
#pragma once

#include "loosehair/scene.hpp"
#include "viewer/head_drag.hpp"
#include "viewer/view_state.hpp"
#include "viewer/simulation_thread.hpp"
#include "viewer/styling_session.hpp"

#include <deque>
#include <memory>
#include <optional>
#include <string>

namespace loosehair::viewer {

enum class Mode { Simulate, Styling };

class Controller {
 public:
  Controller(SimulationThread& sim, ViewState& view, HeadDrag& head, std::string scene_path);

  SimulationThread& sim() { return sim_; }
  ViewState& view() { return view_; }
  HeadDrag& head() { return head_; }

  /// Shows `message` in the panel and prints it to stderr.
  void fail(const std::string& message);
  /// Shows `message` in the panel as news, not as an error.
  void note(const std::string& message);
  /// Takes an error message away (an undo took back what caused it).
  void clearError();
  /// Runs `what`, turning what it throws into fail(); true if it did not throw.
  template <class F>
  bool attempt(F&& what) {
    try {
      what();
      return true;
    } catch (const std::exception& e) {
      fail(e.what());
      return false;
    }
  }

  // ---- files ------------------------------------------------------------
  /// Opens a scene, or a style (a file with "wisps") grown on the current
  /// scene's head. The current simulation runs on if it cannot be opened.
  void open(const std::string& path);
  const std::deque<std::string>& recent() const { return recent_; }
  /// The scene the next restart builds (the panel's edits included).
  SceneDesc& pending() { return pending_; }
  /// Restarts from pending() (new particle count, seed, parameters).
  void restart();

  // ---- parameters -------------------------------------------------------
  /// Sets solver parameter `name` (ParamInfo) in pending(); a live one goes
  /// to the running solver at once. Returns false if it waits for a restart.
  /// The value is checked as a scene file's "solver" field is (`source`
  /// names where it came from in the message); a refused one changes nothing.
  bool setParam(const std::string& name, double value, const std::string& source = "the panel");
  /// Wind on (or changed) from now, or off (off applies on restart).
  void setWind(bool on);

  // ---- picture ------------------------------------------------------------
  /// Billboards, or the strands the particles carry (view().strands of
  /// them; bound on the simulation thread the first time, a second or two).
  void setHair(render::HairGeometry hair);

  // ---- head ---------------------------------------------------------------
  void shake(double amplitude_deg, double frequency_hz, bool nod);
  void centreHead();
  /// Writes the head's recorded motion (a drag) as a motion file for
  /// `loosehair simulate --motion`.
  void saveHeadMotion(const std::string& path);

  // ---- capture ---------------------------------------------------------
  void saveSnapshot(const std::string& path);
  void loadSnapshot(const std::string& path);
  /// Records each new simulated frame as DIR/frame_00001.png ... and, if
  /// `video` is given, encodes them to it (ffmpeg, no shell) when stopped.
  /// While recording, the simulation goes a frame per drawn frame (every
  /// frame is written, none skipped).
  void startRecording(const std::string& dir, const std::string& video);
  void stopRecording();
  bool recording() const { return recording_.has_value(); }
  /// The path the frame just drawn should be written to (recording), or "".
  std::string recordingPath(std::int64_t frame);

  // ---- styling ---------------------------------------------------------
  Mode mode() const { return mode_; }
  /// Into styling: the scene's style if it has one (or the one styled
  /// before), else a new style on the scene's head; the simulation pauses.
  void enterStyling();
  /// Simulates the current style (restarting from it); styling again later
  /// goes back to the same style.
  void enterSimulate();
  StylingSession* styling() { return styling_.get(); }
  WispParams new_wisp;  // parameters of the next wisp the brush makes

 private:
  void remember(const std::string& path);

  SimulationThread& sim_;
  ViewState& view_;
  HeadDrag& head_;
  SceneDesc pending_;
  std::deque<std::string> recent_;
  Mode mode_ = Mode::Simulate;
  std::unique_ptr<StylingSession> styling_;
  struct Recording {
    std::string dir, video;
    int written = 0;
    std::int64_t last_frame = -1;
    bool was_paused = false;  // recording steps frame by frame; stopping restores this
  };
  std::optional<Recording> recording_;
};

}  // namespace loosehair::viewer
