#include "loosehair/scene.hpp"
#include "loosehair/param_table.hpp"

#include "init/cantilever.hpp"
#include "init/hanging_hair.hpp"
#include "init/poisson_pillar.hpp"
#include "init/length_map.hpp"
#include "init/mesh_scalp.hpp"
#include "init/scalp_surface.hpp"
#include "bodies/head_orientation.hpp"
#include "loosehair/json_checks.hpp"
#include "solver/neighbor_grid.hpp"
#include "util/parallel.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/head_model.hpp"
#include "files/json_fields.hpp"
#include "loosehair/style.hpp"
#include "style/hair_tie.hpp"
#include "style/style_seeding.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <chrono>
#include <optional>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <unordered_map>
#include <set>
#include <sstream>

namespace loosehair {
namespace {

using namespace detail;

// The "solver" object: every parameter the table marks in_scene, checked
// against its one range (param_table.cpp); h1 and h2 may be "auto",
// gravity is one vector, and a shape_keeping given is no longer automatic.
void readSolver(Fields f, SceneDesc& s) {
  SimParams& p = s.sim;
  for (const ParamInfo& info : paramTable()) {
    if (!info.in_scene) continue;
    const std::string name = info.name;
    const double fallback = info.get(p);
    double v = fallback;
    if (name == "h1" || name == "h2") {
      v = f.numberOrAuto(name, fallback, name == "h1" ? s.h1_auto : s.h2_auto, info.lo, info.hi);
    } else if (info.kind == ParamInfo::Kind::Switch) {
      v = f.boolean(name, fallback != 0.0) ? 1.0 : 0.0;
    } else if (info.kind == ParamInfo::Kind::Integer) {
      v = static_cast<double>(f.integer(name, static_cast<std::int64_t>(fallback), static_cast<std::int64_t>(info.lo),
                                        static_cast<std::int64_t>(info.hi)));
    } else {
      if (name == "shape_keeping" && f.has(name)) s.shape_keeping_auto = false;
      v = f.real(name, static_cast<float>(fallback), info.lo, info.hi, info.lo_open);
    }
    info.set(p, v);
  }
  const ParamInfo& g = *findParam("gravity.y");
  p.gravity = glm::vec3(f.vec3("gravity", glm::dvec3(p.gravity), g.hi));
  f.finish();
}

HeadTrajectory readMotion(Fields f);

// A text file's contents; what goes wrong names the file and what it is for.
std::string readTextFile(const std::string& path, const char* what) {
  try {
    return readRegularFile(path, kMaxTextFileBytes);
  } catch (const FileError& e) {
    throw SceneError(std::string(e.what()) + " (" + what + ")");
  }
}

// Checked and parsed JSON text; errors are SceneErrors naming `source`.
json parseJson(const std::string& text, const std::string& source) {
  checkJson(text, source, [](const std::string& message) { throw SceneError(message); });
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw SceneError(source + ": invalid JSON: " + clipped(e.what(), 200));
  }
}

WindParams readWind(Fields f) {
  WindParams w;
  const std::string model = f.text("model", "grid");
  if (model == "grid")
    w.model = AirModel::Grid;
  else if (model == "particles")
    w.model = AirModel::Particles;
  else
    f.fail("model", "must be \"grid\" or \"particles\", got \"" + model + "\"");
  w.direction = glm::vec3(f.vec3("direction", glm::dvec3(w.direction), 1e6));
  if (!(glm::length(w.direction) > 1e-6f)) f.fail("direction", "must be a non-zero direction");
  w.speed = f.real("speed", w.speed, 0.0, 100.0);
  if (f.has("profile")) {
    const json& pr = f.at("profile");
    if (!pr.is_array() || pr.empty()) f.fail("profile", "must be a non-empty array of [time, scale] pairs");
    for (std::size_t k = 0; k < pr.size(); ++k) {
      const json& q = pr[k];
      if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
        f.fail("profile[" + std::to_string(k) + "]", "must be a pair [time s, speed scale], got " + show(q));
      const double t = q[0].get<double>(), sc = q[1].get<double>();
      if (!std::isfinite(t) || t < 0 || t > 1e6)
        f.fail("profile[" + std::to_string(k) + "]", "time must be in [0, 1e6], got " + show(q[0]));
      if (!std::isfinite(sc) || sc < 0 || sc > 10)
        f.fail("profile[" + std::to_string(k) + "]", "scale must be in [0, 10], got " + show(q[1]));
      if (k > 0 && !(t > w.profile.back().first))
        f.fail("profile[" + std::to_string(k) + "]", "times must increase strictly");
      w.profile.emplace_back(t, static_cast<float>(sc));
    }
  }
  w.box_center = glm::vec3(f.vec3("box_center", glm::dvec3(w.box_center), 100.0));
  const glm::dvec3 size = f.vec3("box_size", glm::dvec3(w.box_size), 20.0);
  if (!(size.x > 0 && size.y > 0 && size.z > 0)) f.fail("box_size", "must be three positive lengths");
  w.box_size = glm::vec3(size);
  w.spacing = f.real("spacing", w.spacing, 0.0, 1.0, true);
  w.h_scale = f.real("h_scale", w.h_scale, 0.5, 4.0);
  w.density = f.real("density", w.density, 0.0, 1e4, true);
  w.sound_speed = f.real("sound_speed", w.sound_speed, 0.0, 1e4);
  w.projection_iterations = static_cast<int>(f.integer("projection_iterations", w.projection_iterations, 0, 50));
  w.viscosity_rate = f.real("viscosity_rate", w.viscosity_rate, 0.0, 1e5);
  w.drag_rate = f.real("drag_rate", w.drag_rate, 0.0, 1e5);
  const auto problems = validate(w);
  if (!problems.empty()) f.fail("", problems.front());
  f.finish();
  return w;
}

ObstacleSpec readObstacle(Fields f) {
  ObstacleSpec o;
  const std::string type = f.text("type", "sphere");
  if (type == "sphere") {
    o.shape = ObstacleSpec::Shape::Sphere;
    o.a = o.b = glm::vec3(f.vec3("center", glm::dvec3(0.0), 100.0));
  } else if (type == "capsule") {
    o.shape = ObstacleSpec::Shape::Capsule;
    if (!f.has("a") || !f.has("b")) f.fail("a", "a capsule needs both end points a and b");
    o.a = glm::vec3(f.vec3("a", glm::dvec3(0.0), 100.0));
    o.b = glm::vec3(f.vec3("b", glm::dvec3(0.0), 100.0));
  } else {
    f.fail("type", "must be \"sphere\" or \"capsule\", got \"" + type + "\"");
  }
  o.radius = f.real("radius", o.radius, 0.0, 10.0, true);
  if (f.has("motion")) o.motion = readMotion(f.child("motion"));
  o.begin = f.number("begin", 0.0, 0.0, 1e6);
  o.end = f.number("end", 1e30, 0.0, 1e30, true);
  if (!(o.end > o.begin)) f.fail("end", "must be later than begin");
  f.finish();
  return o;
}

HeadTrajectory readMotion(Fields f) {
  const std::string type = f.text("type", "still");
  HeadTrajectory t;
  if (type == "still") {
    t = HeadTrajectory::still();
  } else if (type == "shake" || type == "nod") {
    const double amplitude = f.number("amplitude_deg", 30.0, -180.0, 180.0);
    const double frequency = f.number("frequency_hz", 1.0, 0.0, 50.0, true);
    const double cycles = f.number("cycles", 2.0, 0.0, 1e4, true);
    const double start = f.number("start", 0.0, 0.0, 1e6);
    const double rad = glm::radians(amplitude);
    t = type == "shake" ? HeadTrajectory::shake(rad, frequency, cycles, start)
                        : HeadTrajectory::nod(rad, frequency, cycles, start);
  } else if (type == "keyframes") {
    if (!f.has("keys")) f.fail("keys", "is required for keyframed motion");
    const json& keys = f.at("keys");
    if (!keys.is_array() || keys.size() < 2) f.fail("keys", "must be an array of at least two keyframes");
    std::vector<HeadKeyframe> out;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      Fields kf(keys[k], "motion.keys[" + std::to_string(k) + "]", f.source());
      HeadKeyframe key;
      key.time = kf.number("time", 0.0, 0.0, 1e6);
      key.euler_deg = kf.vec3("euler_deg", glm::dvec3(0.0), 360.0);
      key.translation = kf.vec3("translation", glm::dvec3(0.0), 10.0);
      kf.finish();
      if (k > 0 && !(key.time > out.back().time))
        f.fail("keys[" + std::to_string(k) + "].time", "keyframe times must increase strictly");
      out.push_back(key);
    }
    t = HeadTrajectory::keyframes(std::move(out));
  } else {
    f.fail("type", "must be \"still\", \"shake\", \"nod\" or \"keyframes\", got \"" + type + "\"");
  }
  f.finish();
  return t;
}

}  // namespace

SceneDesc parseScene(const std::string& text, const std::string& source) {
  const json root = parseJson(text, source);
  if (root.is_object() && root.contains("wisps"))
    throw SceneError(source +
                     ": is a style file (it has \"wisps\"), not a scene; grow it on a scene's head with "
                     "--style " +
                     source + " (e.g. loosehair render data/scenes/hang.json --style " + source + ")");
  SceneDesc s;
  s.source = source;
  Fields top(root, "", source);
  s.name = top.text("name", "scene");
  s.seed = static_cast<std::uint64_t>(top.integer("seed", 1, 0, INT64_MAX));
  s.frames = static_cast<int>(top.integer("frames", s.frames, 1, 10000000));
  s.frame_rate = top.number("frame_rate", s.frame_rate, 0.0, 10000.0, true);
  s.settle = top.number("settle", 0.0, 0.0, 10.0);
  if (top.has("substeps") && top.at("substeps").is_string()) {
    if (top.at("substeps").get<std::string>() != "auto")
      top.fail("substeps", "must be a positive integer or \"auto\", got " + show(top.at("substeps")));
    s.substeps = 0;
  } else {
    s.substeps = static_cast<int>(top.integer("substeps", 0, 1, 100000));
  }

  readHeadParts(top, s);
  if (top.has("wind")) {
    s.wind = readWind(top.child("wind"));
    s.has_wind = true;
  }
  if (top.has("obstacles")) {
    const json& list = top.at("obstacles");
    if (!list.is_array()) top.fail("obstacles", "must be an array of obstacles");
    for (std::size_t k = 0; k < list.size(); ++k)
      s.obstacles.push_back(readObstacle(Fields(list[k], "obstacles[" + std::to_string(k) + "]", source)));
  }
  if (top.has("hair")) {
    Fields hair = top.child("hair");
    HairSpec& h = s.hair;
    h.particles = static_cast<int>(hair.integer("particles", h.particles, 10, 20000000));
    if (hair.has("style")) {
      const std::string file = hair.text("style", "");
      if (file.empty()) hair.fail("style", "must name a style file");
      h.style = resolvePath(source, file);
      for (const char* unused : {"length", "whorl", "w_t", "w_n", "bending_stiffness", "layering", "length_map"})
        if (hair.object().contains(unused))
          hair.fail(unused,
                    "is not used with a style (the style's key strands shape the hair); remove it or the style");
    }
    // a centimetre at least: shorter hair is thinner than the particles that
    // sample it, and fails later naming the solver's smoothing lengths
    h.length = hair.real("length", h.length, 0.01, 10.0);
    // at least a milligram: lighter "hair" rounds to zero-mass particles
    h.mass = hair.real("mass", h.mass, 1e-6, 100.0);
    const glm::dvec3 whorl = hair.vec3("whorl", glm::dvec3(h.whorl), 1e6);
    if (!(glm::length(whorl) > 1e-9)) hair.fail("whorl", "must be a non-zero direction, got [0,0,0]");
    h.whorl = glm::vec3(glm::normalize(whorl));
    h.w_t = hair.real("w_t", h.w_t, 0.0, 1e6);
    h.w_n = hair.real("w_n", h.w_n, 0.0, 1e6);
    if (!(h.w_t + h.w_n > 0.0f)) hair.fail("w_n", "w_t and w_n must not both be zero");
    h.bending_stiffness = hair.real("bending_stiffness", h.bending_stiffness, 0.0, 1e6, true);
    h.layering = hair.real("layering", h.layering, 0.0, 10.0);
    if (hair.has("length_map")) {
      const std::string file = hair.text("length_map", "");
      if (file.empty()) hair.fail("length_map", "must name an image file");
      h.length_map = resolvePath(source, file);
    }
    h.h1_scale = hair.real("h1_scale", h.h1_scale, 0.0, 100.0, true);
    h.h2_scale = hair.real("h2_scale", h.h2_scale, 0.0, 100.0, true);
    hair.finish();
  }
  if (top.has("solver")) readSolver(top.child("solver"), s);
  if (top.has("motion")) s.motion = readMotion(top.child("motion"));
  top.finish();
  return s;
}

HeadTrajectory loadMotion(const std::string& path) {
  const json root = parseJson(readTextFile(path, "the head motion file"), path);
  Fields top(root, "", path);
  if (!top.has("motion")) top.fail("motion", "is required: the file holds {\"motion\": {...}} as a scene does");
  HeadTrajectory t = readMotion(top.child("motion"));
  top.finish();
  return t;
}

std::string keyframesJson(const std::vector<HeadKeyframe>& keys) {
  // %.17g: every double reads back to the same bits
  std::string s = "{\"motion\": {\"type\": \"keyframes\", \"keys\": [\n";
  char buf[320];
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const HeadKeyframe& q = keys[k];
    std::snprintf(
        buf, sizeof buf,
        "  {\"time\": %.17g, \"euler_deg\": [%.17g, %.17g, %.17g], \"translation\": [%.17g, %.17g, %.17g]}%s\n", q.time,
        q.euler_deg.x, q.euler_deg.y, q.euler_deg.z, q.translation.x, q.translation.y, q.translation.z,
        k + 1 < keys.size() ? "," : "");
    s += buf;
  }
  return s + "]}}\n";
}

SceneDesc loadScene(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* mesh : {".ply", ".obj", ".off", ".stl", ".glb", ".gltf"})
    if (ext == mesh)
      throw SceneError(path +
                       ": is a mesh, not a scene; a scene (JSON) names its head mesh as \"head\": "
                       "{\"type\": \"mesh\", \"mesh\": \"" +
                       std::filesystem::path(path).filename().string() + "\"} (data/scenes/README.md)");
  return parseScene(readTextFile(path, "the scene file"), path);
}

}  // namespace loosehair
