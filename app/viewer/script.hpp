// Scripted runs of the viewer (loosehair-view SCENE --script FILE): a list
// of timed input events, documented in docs/viewer-scripts.md. Each event
// happens at a simulation frame (the simulation runs exactly to it first,
// so a script gives the same bits every time); events of one frame happen
// in order, one a displayed frame. Mouse and key events go through the
// window's own handlers, panel actions through the Controller by name.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <deque>
#include <string>

namespace loosehair::viewer {

struct ScriptEvent {
  std::int64_t frame = 0;
  std::string what;     // "do" of the file, or mouse_down / mouse_move / mouse_up
  nlohmann::json args;  // the event's object
  std::string where;    // "FILE: events[k]" for messages
};

/// The most input events a script may expand to (its drags' steps and its
/// strokes' points each become one), about two hours of one event a frame.
inline constexpr std::size_t kMaxScriptEvents = 200000;

/// Reads and checks a script; mouse drags and brush strokes become
/// mouse_down, mouse_move ... mouse_up events. Throws std::runtime_error
/// naming the file, the event and the field.
std::deque<ScriptEvent> loadScript(const std::string& path);

}  // namespace loosehair::viewer
