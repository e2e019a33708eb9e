#include "viewer/script.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/json_checks.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace loosehair::viewer {
namespace {

using nlohmann::json;

// what each "do" needs besides "frame" (and may have)
struct Kind {
  const char* name;
  std::set<std::string> required, optional;
};

const Kind kKinds[] = {
    {"key", {"key"}, {"ctrl", "shift"}},
    {"drag", {"from", "to"}, {"button", "frames", "shift", "steps", "window", "anchor", "on"}},
    {"hover", {"at"}, {}},
    {"scroll", {"at", "dy"}, {}},
    {"brush", {"path"}, {}},
    {"click", {"at"}, {"button"}},
    {"press", {"name"}, {}},
    {"set", {"name", "value"}, {}},
    {"view", {"name", "value"}, {}},
    {"open", {"path"}, {}},
    {"screenshot", {"path"}, {}},
    {"hash", {}, {"label"}},
    {"save_motion", {"path"}, {}},
    {"save_snapshot", {"path"}, {}},
    {"load_snapshot", {"path"}, {}},
    {"save_style", {"path"}, {}},
    {"record", {"dir"}, {"video"}},
    {"quit", {}, {}},
};

[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw std::runtime_error(where + ": " + what);
}

[[noreturn]] void tooMany(const std::string& where) {
  bad(where, "the script expands to more than " + std::to_string(kMaxScriptEvents) +
                 " input events here (drags become one event a step, strokes one a point); "
                 "use fewer or shorter drags");
}

double number(const json& e, const char* field, const std::string& where, double lo, double hi) {
  const json& v = e.at(field);
  if (!v.is_number()) bad(where, std::string(field) + " must be a number, got " + v.dump());
  const double x = v.get<double>();
  if (!(x >= lo && x <= hi))
    bad(where, std::string(field) + " = " + v.dump() + " must lie in [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]");
  return x;
}

std::pair<double, double> point(const json& v, const std::string& where, const std::string& field) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    bad(where, field + " must be [x, y] in window pixels, got " + v.dump());
  const double x = v[0].get<double>(), y = v[1].get<double>();
  if (!(x >= -1e5 && x <= 1e5 && y >= -1e5 && y <= 1e5)) bad(where, field + " is out of range: " + v.dump());
  return {x, y};
}

bool flag(const json& e, const char* field, const std::string& where) {
  if (!e.contains(field)) return false;
  const json& v = e.at(field);
  if (!v.is_boolean()) bad(where, std::string(field) + " must be true or false, got " + clipped(v.dump()));
  return v.get<bool>();
}

json mouse(const char* button, std::pair<double, double> p, bool shift, bool window = false) {
  return json{{"button", button}, {"x", p.first}, {"y", p.second}, {"shift", shift}, {"window", window}};
}

}  // namespace

std::deque<ScriptEvent> loadScript(const std::string& path) {
  const std::string text = readRegularFile(path, kMaxTextFileBytes);
  // nesting, repeated keys and syntax first: a tree 100,000 levels deep
  // overflowed the stack when it was copied or printed
  checkJson(text, path, [](const std::string& m) -> void { throw std::runtime_error(m); });
  json root = json::parse(text, nullptr, false);
  if (root.is_discarded()) bad(path, "not valid JSON");
  if (!root.is_object() || !root.contains("events") || !root["events"].is_array())
    bad(path, "must be {\"events\": [...]}");
  for (const auto& [k, v] : root.items())
    if (k != "events" && k != "comment") bad(path, "unknown field \"" + k + "\"");
  std::deque<ScriptEvent> out;
  std::int64_t last = 0;
  const json& events = root["events"];
  for (std::size_t i = 0; i < events.size(); ++i) {
    const std::string where = path + ": events[" + std::to_string(i) + "]";
    const json& e = events[i];
    if (!e.is_object() || !e.contains("do") || !e["do"].is_string()) bad(where, "must be an object with \"do\"");
    const std::string what = e["do"].get<std::string>();
    const Kind* kind = nullptr;
    for (const Kind& k : kKinds)
      if (what == k.name) kind = &k;
    if (!kind) bad(where, "unknown \"do\": \"" + what + "\" (docs/viewer-scripts.md lists them)");
    for (const std::string& f : kind->required)
      if (!e.contains(f)) bad(where, "\"" + what + "\" needs \"" + f + "\"");
    for (const auto& [k, v] : e.items())
      if (k != "do" && k != "frame" && k != "comment" && !kind->required.count(k) && !kind->optional.count(k))
        bad(where, "unknown field \"" + k + "\" for \"" + what + "\"");
    const std::int64_t frame =
        e.contains("frame") ? static_cast<std::int64_t>(number(e, "frame", where, 0, 1e7)) : last;
    if (frame < last)
      bad(where, "frame " + std::to_string(frame) + " comes before the previous event's " + std::to_string(last));
    last = frame;
    for (const char* f : {"path", "dir", "video", "name", "key", "label", "button"})  // a brush's path is points
      if (e.contains(f) && !(what == "brush" && f == std::string("path")) && !e[f].is_string())
        bad(where, std::string(f) + " must be a string, got " + clipped(e[f].dump()));
    for (const char* f : {"shift", "ctrl"}) (void)flag(e, f, where);
    if (what == "drag") {
      const auto a = point(e["from"], where, "from"), b = point(e["to"], where, "to");
      const std::string button = e.value("button", "right");
      if (button != "left" && button != "right") bad(where, "button must be \"left\" or \"right\"");
      const int frames = e.contains("frames") ? static_cast<int>(number(e, "frames", where, 0, 1e5)) : 0;
      const int steps = e.contains("steps") ? static_cast<int>(number(e, "steps", where, 1, 1e4)) : std::max(frames, 1);
      const bool shift = flag(e, "shift", where);
      const bool window = flag(e, "window", where);
      // anchored: from and to are pixels from where a style's control point
      // (or its arrow, or its key strand after it) is seen at the press
      json anchor;
      if (e.contains("anchor")) {
        const json& an = e["anchor"];
        if (!an.is_array() || an.size() != 2 || !an[0].is_number_unsigned() || !an[1].is_number_unsigned() ||
            an[0].get<double>() > 1e6 || an[1].get<double>() > 1e6)
          bad(where, "anchor must be [wisp, control point] (two whole numbers), got " + clipped(an.dump()));
        const std::string on = e.value("on", "point");
        if (on != "point" && on != "strand" && on != "tangent" && on != "normal" && on != "binormal")
          bad(where, "on must be \"point\", \"strand\", \"tangent\", \"normal\" or \"binormal\", got \"" + on + "\"");
        if (window) bad(where, "an anchored drag does not go through the window (window: false)");
        anchor = json{{"anchor", an}, {"on", on}};
      } else if (e.contains("on")) {
        bad(where, "on needs an anchor");
      }
      auto event = [&](std::pair<double, double> at) {
        json m = mouse(button.c_str(), at, shift, window);
        if (!anchor.is_null()) m.update(anchor);
        return m;
      };
      if (out.size() + static_cast<std::size_t>(steps) + 2 > kMaxScriptEvents) tooMany(where);
      out.push_back({frame, "mouse_down", event(a), where});
      for (int k = 1; k <= steps; ++k) {
        const double t = static_cast<double>(k) / steps;
        const std::int64_t f = frame + (frames * k) / steps;
        out.push_back(
            {f, "mouse_move", event({a.first + t * (b.first - a.first), a.second + t * (b.second - a.second)}), where});
      }
      out.push_back({frame + frames, "mouse_up", event(b), where});
    } else if (what == "brush" || what == "click") {
      std::vector<std::pair<double, double>> pts;
      if (what == "click") {
        pts.push_back(point(e["at"], where, "at"));
      } else {
        if (!e["path"].is_array() || e["path"].empty()) bad(where, "path must be a list of [x, y]");
        if (out.size() + e["path"].size() + 2 > kMaxScriptEvents) tooMany(where);
        for (const json& p : e["path"]) pts.push_back(point(p, where, "path"));
      }
      const std::string button = what == "click" ? e.value("button", "left") : "left";
      out.push_back({frame, "mouse_down", mouse(button.c_str(), pts.front(), false), where});
      for (std::size_t k = 1; k < pts.size(); ++k)
        out.push_back({frame, "mouse_move", mouse(button.c_str(), pts[k], false), where});
      out.push_back({frame, "mouse_up", mouse(button.c_str(), pts.back(), false), where});
    } else {
      if (what == "hover" || what == "scroll") (void)point(e["at"], where, "at");
      if (what == "scroll") (void)number(e, "dy", where, -100, 100);
      if (out.size() + 1 > kMaxScriptEvents) tooMany(where);
      out.push_back({frame, what, e, where});
    }
  }
  // a drag goes on over frames while later events happen: in frame order,
  // events of one frame in the order written
  std::stable_sort(out.begin(), out.end(),
                   [](const ScriptEvent& a, const ScriptEvent& b) { return a.frame < b.frame; });
  return out;
}

}  // namespace loosehair::viewer
