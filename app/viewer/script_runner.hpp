// The viewer's scripts (docs/viewer-scripts.md): each timed event played
// as a person's input (the same handlers as the mouse and keyboard,
// window_input.hpp) or as a panel action.
#pragma once

#include "viewer/panel.hpp"
#include "viewer/script.hpp"
#include "viewer/window_input.hpp"

#include <glm/vec3.hpp>

#include <deque>
#include <vector>

namespace loosehair::viewer {

struct ScriptRun {
  std::deque<viewer::ScriptEvent> events;
  std::vector<glm::vec3> start;  // the hair when the script began
  int warmup = 2;                // displayed frames before the first event (the panel lays itself out)
};

/// Plays one script event; false when the script asks to stop.
bool runEvent(const ScriptEvent& e, Window& w, Panel& panel, ScriptRun& run);

}  // namespace loosehair::viewer
