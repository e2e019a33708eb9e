// The values a person types into the viewer's panel or a script sets by
// name ({"do": "set", "name": ..., "value": ...}): each is checked as the
// file that holds it checks it (a scene's field, a style's wisp parameter),
// or, for the viewer's own settings, against the range named here.
#pragma once

#include <string>

namespace loosehair::viewer {

/// `value` for the viewer value `name`, checked: "speed" (simulated seconds
/// a second, 0 for as fast as possible), "particles", "seed", "wind.speed",
/// "shake.amplitude_deg", "shake.frequency_hz", "styling.brush_radius" (m),
/// "styling.step_mm", "styling.drag_falloff" (m), "styling.wisp_length" (m,
/// a new wisp's), "styling.settle_seconds", "styling.brush_pixels",
/// "styling.brush_strength", "styling.curl_radius", "styling.curl_period"
/// (the curl brush's, checked as a wisp's), "styling.density", "styling.offset_radius",
/// "styling.length_variation", "styling.blend", "styling.edge_ramp". Solver parameters go through
/// Controller::setParam. Throws std::runtime_error naming `source`, the
/// value's name and the value (std::invalid_argument for an unknown name).
double checkViewerValue(const std::string& name, double value, const std::string& source);

/// Whether `name` is one of those.
bool isViewerValue(const std::string& name);

}  // namespace loosehair::viewer
