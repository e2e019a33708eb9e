// Reading JSON input files (scenes, styles) field by field: every value is
// checked against its range, unknown fields are errors, and each message
// names the file, the path of the field and the value.
#pragma once

#include "loosehair/json_checks.hpp"
#include "loosehair/scene.hpp"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace loosehair::detail {

using json = nlohmann::json;

[[noreturn]] inline void raiseScene(const std::string& message) { throw SceneError(message); }

// A value for an error message: short values whole, long ones cut (the
// input's nesting is bounded by checkJson, so dumping is safe).
inline std::string num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

inline std::string show(const json& v) {
  if (v.is_string()) return "\"" + clipped(v.get_ref<const std::string&>()) + "\"";
  if (v.is_array() && v.size() > 16) return "an array of " + std::to_string(v.size()) + " values";
  if (v.is_object() && v.size() > 16) return "an object of " + std::to_string(v.size()) + " fields";
  return clipped(v.dump());
}

// A JSON object being read: remembers its path for messages and which keys
// were used, so that misspelt fields are reported instead of ignored.
class Fields {
 public:
  using Raise = void (*)(const std::string& message);  // throws
  Fields(const json& obj, std::string path, const std::string& source, Raise raise_fn = raiseScene)
      : obj_(obj), path_(std::move(path)), source_(source), raise_(raise_fn) {
    if (!obj_.is_object()) fail("", "must be a JSON object, got " + show(obj_));
  }

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    std::string field = path_;
    if (!key.empty()) field += (field.empty() ? "" : ".") + key;
    raise_(source_ + ": " + (field.empty() ? "" : field + ": ") + problem);
    throw SceneError(source_ + ": " + problem);  // raise_ does not return
  }

  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }
  Raise raise() const { return raise_; }
  const json& object() const { return obj_; }

  bool has(const std::string& key) {
    used_.insert(key);
    return obj_.contains(key);
  }
  const json& at(const std::string& key) {
    used_.insert(key);
    return obj_.at(key);
  }

  double number(const std::string& key, double fallback, double lo, double hi, bool lo_open = false) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_number()) fail(key, "must be a number, got " + show(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi || (lo_open && d == lo)) {
      std::ostringstream os;
      os << "must be a number in " << (lo_open ? "(" : "[") << lo << ", " << hi << "], got " << show(v);
      fail(key, os.str());
    }
    return d;
  }
  float real(const std::string& key, float fallback, double lo, double hi, bool lo_open = false) {
    const double d = number(key, fallback, lo, hi, lo_open);
    // a value a float cannot hold (1e-300 rounds to 0) would pass here and
    // fail far from its field
    if (d != 0.0 && std::abs(d) < static_cast<double>(std::numeric_limits<float>::min()))
      fail(key, "must be 0 or at least " + num(std::numeric_limits<float>::min()) + " in magnitude, got " +
                    show(obj_.at(key)));
    return static_cast<float>(d);
  }
  std::int64_t integer(const std::string& key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    // 1e5 is an integer written as a number with an exponent: taken if exact
    std::int64_t i = 0;
    if (v.is_number_integer()) {
      if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
        fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + show(v));
      i = v.get<std::int64_t>();
    } else if (v.is_number_float()) {
      const double d = v.get<double>();
      if (!(std::floor(d) == d) || !(std::abs(d) < 9.2e18)) fail(key, "must be a whole number, got " + show(v));
      if (d < static_cast<double>(lo) || d > static_cast<double>(hi))
        fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + show(v));
      i = static_cast<std::int64_t>(d);
    } else {
      fail(key, "must be an integer, got " + show(v));
    }
    if (i < lo || i > hi)
      fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + show(v));
    return i;
  }
  bool boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_boolean()) fail(key, "must be true or false, got " + show(v));
    return v.get<bool>();
  }
  std::string text(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_string()) fail(key, "must be a string, got " + show(v));
    return v.get<std::string>();
  }
  glm::dvec3 vec3(const std::string& key, glm::dvec3 fallback, double bound = 1e6) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail(key, "must be an array of three numbers, got " + show(v));
    glm::dvec3 out(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(out[a]) || std::abs(out[a]) > bound)
        fail(key, "must hold finite numbers of magnitude at most " + num(bound) + ", got " + show(v));
    return out;
  }
  /// A number, or "auto" (returns nullopt-like: sets is_auto).
  double numberOrAuto(const std::string& key, double fallback, bool& is_auto, double lo, double hi) {
    if (has(key) && obj_.at(key).is_string()) {
      if (obj_.at(key).get<std::string>() != "auto")
        fail(key, "must be a number or \"auto\", got " + show(obj_.at(key)));
      is_auto = true;
      return fallback;
    }
    if (!has(key)) return fallback;
    is_auto = false;
    return number(key, fallback, lo, hi, true);
  }
  Fields child(const std::string& key) {
    used_.insert(key);
    return Fields(obj_.at(key), path_.empty() ? key : path_ + "." + key, source_, raise_);
  }
  /// Fails on any key that was never asked for.
  void finish() const {
    for (auto it = obj_.begin(); it != obj_.end(); ++it)
      if (!used_.count(it.key())) fail(it.key(), "unknown field");
  }

 private:
  const json& obj_;
  std::string path_;
  const std::string& source_;
  Raise raise_;
  std::set<std::string> used_;
};

inline std::string resolvePath(const std::string& source, const std::string& file) {
  const std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  return (std::filesystem::path(source).parent_path() / p).lexically_normal().string();
}

// The mesh fields shared by "head" (type "mesh") and "torso".
inline void readMeshSpec(Fields& f, MeshSpec& m) {
  if (!f.has("mesh")) f.fail("mesh", "is required (the mesh file, relative to the scene file)");
  const std::string file = f.text("mesh", "");
  if (file.empty()) f.fail("mesh", "must name a mesh file");
  m.path = resolvePath(f.source(), file);
  m.load.scale = f.real("scale", 1.0f, 0.0, 1e6, true);
  try {
    m.load.up = parseAxis(f.text("up", "+y"));
  } catch (const std::invalid_argument& e) {
    f.fail("up", e.what());
  }
  try {
    m.load.front = parseAxis(f.text("front", "+z"));
  } catch (const std::invalid_argument& e) {
    f.fail("front", e.what());
  }
  if (std::abs(glm::dot(axisVector(m.load.up), axisVector(m.load.front))) > 0.5f)
    f.fail("front", "must be a different axis from up");
  // as far as the mesh may lie (a scan or a scene export kilometres out)
  m.load.offset = glm::vec3(f.vec3("offset", glm::dvec3(0.0), 1e6));
  bool voxel_auto = true;
  m.sdf_voxel = static_cast<float>(f.numberOrAuto("sdf_voxel", 0.0, voxel_auto, 0.0, 1.0));
  if (voxel_auto) m.sdf_voxel = 0.0f;
}

inline std::vector<glm::vec3> readPoints(Fields& f, const std::string& key, std::size_t at_least,
                                         double max_distance = 100.0) {
  const json& v = f.at(key);
  if (!v.is_array() || v.size() < at_least)
    f.fail(key, "must be an array of at least " + std::to_string(at_least) + " points [x, y, z]");
  std::vector<glm::vec3> out;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const json& q = v[k];
    if (!q.is_array() || q.size() != 3 || !q[0].is_number() || !q[1].is_number() || !q[2].is_number())
      f.fail(key + "[" + std::to_string(k) + "]", "must be a point [x, y, z], got " + show(q));
    const glm::dvec3 d(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || glm::length(d) > max_distance)
      f.fail(key + "[" + std::to_string(k) + "]",
             "must hold finite coordinates within " + show(max_distance) + " m, got " + show(q));
    out.emplace_back(d);
  }
  return out;
}

/// The head, torso and scalp fields of `top` (scenes and styles share them).
void readHeadParts(Fields& top, HeadDesc& h);
/// The same fields written back (paths relative to `folder`).
json writeHeadParts(const HeadDesc& h, const std::string& folder);

}  // namespace loosehair::detail
