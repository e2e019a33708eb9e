#include "viewer/viewer_values.hpp"

#include "loosehair/scene.hpp"
#include "loosehair/style.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace loosehair::viewer {
namespace {

// A viewer value and where its check comes from: a scene field, a wisp
// parameter, or a range of the viewer's own.
struct ValueRule {
  const char* name;
  const char* scene_field;  // checked by checkSceneValue
  const char* wisp_field;   // checked by checkWispValue
  double lo, hi;            // otherwise: within [lo, hi]
  const char* unit;
};

const ValueRule kRules[] = {
    {"speed", nullptr, nullptr, 0.0, 100.0, "x real time (0: as fast as possible)"},
    {"particles", "hair.particles", nullptr, 0, 0, ""},
    {"seed", "seed", nullptr, 0, 0, ""},
    {"wind.speed", "wind.speed", nullptr, 0, 0, ""},
    {"shake.amplitude_deg", "motion.amplitude_deg", nullptr, 0, 0, ""},
    {"shake.frequency_hz", "motion.frequency_hz", nullptr, 0, 0, ""},
    {"styling.brush_radius", nullptr, nullptr, 0.001, 0.2, "m"},
    {"styling.step_mm", nullptr, nullptr, 0.01, 100.0, "mm"},
    {"styling.drag_falloff", nullptr, nullptr, 0.0, 1.0, "m"},
    {"styling.wisp_length", nullptr, nullptr, 0.01, 2.0, "m"},
    {"styling.settle_seconds", nullptr, nullptr, 0.05, 10.0, "s"},
    {"styling.brush_pixels", nullptr, nullptr, 2.0, 2000.0, "pixels"},
    {"styling.brush_strength", nullptr, nullptr, 0.0, 1.0, ""},
    {"styling.curl_radius", nullptr, "curl_radius", 0, 0, ""},
    {"styling.curl_period", nullptr, "curl_period", 0, 0, ""},
    {"styling.density", nullptr, "density", 0, 0, ""},
    {"styling.offset_radius", nullptr, "offset_radius", 0, 0, ""},
    {"styling.length_variation", nullptr, "length_variation", 0, 0, ""},
    {"styling.blend", nullptr, "blend", 0, 0, ""},
    {"styling.edge_ramp", nullptr, "edge_ramp", 0, 0, ""},
};

const ValueRule* find(const std::string& name) {
  for (const ValueRule& r : kRules)
    if (name == r.name) return &r;
  return nullptr;
}

}  // namespace

bool isViewerValue(const std::string& name) { return find(name) != nullptr; }

double checkViewerValue(const std::string& name, double value, const std::string& source) {
  const ValueRule* r = find(name);
  if (!r) throw std::invalid_argument(source + ": no viewer value called \"" + name + "\"");
  if (r->scene_field) return checkSceneValue(r->scene_field, value, source + " (" + name + ")");
  if (r->wisp_field) return checkWispValue(r->wisp_field, value, source + " (" + name + ")");
  if (!(std::isfinite(value) && value >= r->lo && value <= r->hi)) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s: %s must be a number in [%g, %g] %s, got %g", source.c_str(), name.c_str(),
                  r->lo, r->hi, r->unit, value);
    throw std::runtime_error(buf);
  }
  return value;
}

}  // namespace loosehair::viewer
