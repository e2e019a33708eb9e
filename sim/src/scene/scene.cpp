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
  if (model == "grid") w.model = AirModel::Grid;
  else if (model == "particles") w.model = AirModel::Particles;
  else f.fail("model", "must be \"grid\" or \"particles\", got \"" + model + "\"");
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
    throw SceneError(source + ": is a style file (it has \"wisps\"), not a scene; grow it on a scene's head with "
                     "--style " + source + " (e.g. loosehair render data/scenes/hang.json --style " + source + ")");
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
          hair.fail(unused, "is not used with a style (the style's key strands shape the hair); remove it or the style");
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

namespace {

// The longest step the implicit springs take by default: the hair's swing
// (its pendulum and head-shake response, 1-3 Hz) is resolved within a few
// per cent at this step (docs/design.md "Implicit springs", measured).
constexpr double kAccurateStep = 1.0 / 90.0;

// The threads the scene's build runs on: solver.threads where it is in
// range (one out of range is refused with the other solver parameters
// once the particles are made: until then, the default), else all.
int buildThreads(const SceneDesc& scene) {
  const int asked = scene.sim.threads;
  return asked > 0 && asked <= parallel::kMaxThreads ? asked : parallel::availableThreads();
}

// Particles that hang on something: in order of arc length, each must have
// a kept particle nearer the root within `reach`. One that has none, but a
// kept particle nearer the root within `pull` (> reach), is moved along the
// line towards the nearest such particle until it is within 0.9 reach of it
// (`pulled` counts them): at the edge of a pillar the sampling thins out,
// and a particle a few millimetres beyond reach is hair all the same. The
// others are left out. Moved particles may end up inside the head or a
// little beyond their tethers; the first step's corrections see to both.
std::vector<std::uint32_t> anchorableParticles(Particles& p, float reach, float pull, std::size_t& pulled) {
  const std::size_t n = p.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return p.arc_length[a] < p.arc_length[b];
  });
  NeighborGrid grid;
  grid.build(p.position, reach, 1);
  std::vector<std::uint8_t> kept(n, 0);
  std::vector<std::uint32_t> kept_list;  // by arc length
  // the kept particles by cell of `pull` at their current positions, made
  // at the first straggler (each a list in the order kept: deterministic)
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> kept_cells;
  bool cells_made = false;
  const float inv_pull = 1.0f / pull;
  auto cellOf = [&](const glm::vec3& x) { return glm::ivec3(glm::floor(x * inv_pull)); };
  auto key = [](glm::ivec3 c) {
    const auto u = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffff; };
    return (u(c.x) << 42) | (u(c.y) << 21) | u(c.z);
  };
  auto keep = [&](std::uint32_t i) {
    kept[i] = 1;
    kept_list.push_back(i);
    if (cells_made) kept_cells[key(cellOf(p.position[i]))].push_back(i);
  };
  pulled = 0;
  for (std::uint32_t i : order) {
    if (p.is_root[i]) {
      keep(i);
      continue;
    }
    bool anchored = false;
    for (std::uint32_t j : grid.neighbors(i))
      if (kept[j] && p.arc_length[j] < p.arc_length[i] &&
          glm::length(p.position[j] - p.position[i]) < reach) {
        anchored = true;
        break;
      }
    if (!anchored) {
      // a straggler: the nearest kept particle nearer the root within
      // `pull`, from the cells (a moved particle is no longer where the
      // grid has it)
      if (!cells_made) {
        for (std::uint32_t j : kept_list) kept_cells[key(cellOf(p.position[j]))].push_back(j);
        cells_made = true;
      }
      std::uint32_t best = i;
      float best_d = pull;
      const glm::ivec3 c = cellOf(p.position[i]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = kept_cells.find(key(c + glm::ivec3(dx, dy, dz)));
            if (it == kept_cells.end()) continue;
            for (std::uint32_t j : it->second) {
              if (!(p.arc_length[j] < p.arc_length[i])) continue;
              const float d = glm::length(p.position[j] - p.position[i]);
              if (d < best_d || (d == best_d && best != i && j < best)) best_d = d, best = j;
            }
          }
      if (best == i) continue;  // left out
      const glm::vec3 from = p.position[best];
      p.position[i] = from + (0.9f * reach / best_d) * (p.position[i] - from);
      ++pulled;
    }
    keep(i);
  }
  std::vector<std::uint32_t> which;
  for (std::uint32_t i = 0; i < n; ++i)
    if (kept[i]) which.push_back(i);
  return which;
}

}  // namespace

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
    std::snprintf(buf, sizeof buf,
                  "  {\"time\": %.17g, \"euler_deg\": [%.17g, %.17g, %.17g], \"translation\": [%.17g, %.17g, %.17g]}%s\n",
                  q.time, q.euler_deg.x, q.euler_deg.y, q.euler_deg.z, q.translation.x, q.translation.y,
                  q.translation.z, k + 1 < keys.size() ? "," : "");
    s += buf;
  }
  return s + "]}}\n";
}

SceneDesc loadScene(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* mesh : {".ply", ".obj", ".off", ".stl", ".glb", ".gltf"})
    if (ext == mesh)
      throw SceneError(path + ": is a mesh, not a scene; a scene (JSON) names its head mesh as \"head\": "
                       "{\"type\": \"mesh\", \"mesh\": \"" + std::filesystem::path(path).filename().string() +
                       "\"} (data/scenes/README.md)");
  return parseScene(readTextFile(path, "the scene file"), path);
}

namespace {
Solver buildSolverReporting(const SceneDesc& scene, BuildReport* report, BuildReport& rep);
}  // namespace

Style sceneStyle(const SceneDesc& scene, const HeadModel& model, BuildReport* report) {
  const HairSpec& hair = scene.hair;
  Style style = hair.style_data ? *hair.style_data : loadStyle(hair.style);
  if (!style.head.sameAs(scene)) {
    BuildReport other;
    const HeadModel from = HeadModel::build(style.head, style.source, scene.limits.mesh, &other);
    checkStyle(style, from);
    style = retargetStyle(style, from, model);
    if (report)
      report->warnings.push_back("hair.style: the style was made on another head; its wisps were placed on this one by their scalp (u, v)");
  } else {
    checkStyle(style, model);
  }
  return style;
}

Solver buildSolver(const SceneDesc& scene, BuildReport* report) {
  BuildReport rep;
  try {
    return buildSolverReporting(scene, report, rep);
  } catch (const SceneError& e) {
    // The warnings so far (a head far from human size, on its side) often
    // explain the error: they go with it.
    std::string msg = e.what();
    for (const std::string& w : rep.warnings)
      if (msg.find(w) == std::string::npos) msg += "\n  (" + w + ")";
    throw SceneError(msg);
  }
}

namespace {

// The hair between the scalp and a tie, per particle: its tether towards
// the tie (Solver::setTieTethers) and the tie's hold (HairTie::hold, given
// to Solver::setShapeKeepingStrengths).
struct TieTethers {
  std::vector<glm::vec3> point;
  std::vector<float> reach;  // < 0: none
  std::vector<float> hold;   // Hz; 0 where reach < 0
  /// The entries of the particles `which` (as Particles::select).
  void select(const std::vector<std::uint32_t>& which) {
    if (reach.empty()) return;
    TieTethers t;
    for (std::uint32_t k : which) {
      t.point.push_back(point[k]);
      t.reach.push_back(reach[k]);
      t.hold.push_back(hold[k]);
    }
    *this = std::move(t);
  }
};

// The particles of a styled scene (method.md §6.2): the style's member strands,
// on the scene's head (retargeted by (u, v) when the style was made on
// another one), sampled by Poisson-disc darts; particles inside a tie are
// held like roots.
// Returns the style's own shape-keeping strength (Hz).
float growFromStyle(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp,
                    BuildReport& rep, TieTethers& tethers) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const HairSpec& hair = scene.hair;
  const Style style = sceneStyle(scene, model, &rep);
  const StrandSet strands = buildMemberStrands(style, model, kStrandSpacing, scene.limits.style, buildThreads(scene));
  if (strands.size() == 0) throw SceneError(scene.source + ": hair.style: the style grows no strands");
  rep.style_wisps = style.wisps.size();
  rep.style_strands = strands.size();
  rep.style_points = strands.points.size();
  rep.seconds_strands = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto t1 = Clock::now();
  const StrandSeeding seeded = seedFromStrands(strands, hair.particles, scene.seed);
  rep.seconds_sampling = std::chrono::duration<double>(Clock::now() - t1).count();
  const std::size_t n = seeded.samples.size();
  if (n < 2) throw SceneError(scene.source + ": hair.particles: too few particles could be placed on the style's strands");
  rp = seeded.radius;
  // Beyond a tie the ring is the hair's new root: a particle there measures
  // its arc length from where its strand crosses the ring, and its tether
  // (|x - r| <= s) runs to that point. (Measured from the scalp, strands of
  // the wisps gathered into one tail would have very different s side by
  // side, and the connections, made between neighbours in order of s, would
  // not hang the tail from the tie.)
  std::vector<std::optional<TieCrossing>> crossing(strands.size());
  std::vector<float> crossing_hold(strands.size(), 0.0f);
  if (!style.ties.empty()) {
    std::vector<glm::vec3> line;
    for (std::size_t k = 0; k < strands.size(); ++k) {
      line.assign(strands.points.begin() + strands.first[k], strands.points.begin() + strands.first[k + 1]);
      for (const HairTie& t : style.ties)
        if (auto c = crossTie(line, t); c && (!crossing[k] || c->arc_length < crossing[k]->arc_length)) {
          crossing[k] = c;
          crossing_hold[k] = t.hold;
        }
    }
  }
  p.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const StrandSample& q = seeded.samples[k];
    p.position[k] = q.position;
    p.direction[k] = q.direction;
    p.velocity[k] = glm::vec3(0.0f);
    p.uv[k] = q.uv;
    p.arc_length[k] = q.s;
    p.root_point[k] = q.root;
    p.mass[k] = hair.mass / static_cast<float>(n);
    bool tied = false;
    for (const HairTie& t : style.ties) tied = tied || insideTie(t, q.position);
    const std::optional<TieCrossing>& c = crossing[q.strand];
    if (c && q.s >= c->arc_length) {
      p.arc_length[k] = q.s - c->arc_length;
      p.root_point[k] = c->point;
    } else if (c && q.s >= 0.0f) {  // between scalp and tie: held from both ends
      if (tethers.reach.empty()) {
        tethers.point.assign(n, glm::vec3(0.0f));
        tethers.reach.assign(n, -1.0f);
        tethers.hold.assign(n, 0.0f);
      }
      tethers.point[k] = c->point;
      tethers.reach[k] = c->arc_length - q.s;
      tethers.hold[k] = crossing_hold[q.strand];
    }
    p.is_root[k] = (q.s < 0.0f || tied) ? 1 : 0;
    if (tied && q.s >= 0.0f) ++rep.tied_particles;
  }
  return style.shape_keeping;
}

// Particles a thread takes at a time while growing their strands.
constexpr std::size_t kStrandBatch = 64;

// The particles of a scene without a style (method.md §6.1): Poisson-disc
// samples of the hair pillar in (u, v, s), hung by cantilever strands from
// root directions given by the whorl.
void growCantilever(const SceneDesc& scene, const HeadModel& model, Particles& p, float& rp, BuildReport& rep) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); };
  const HairSpec& hair = scene.hair;
  const ScalpSurface& scalp = model.scalp();
  const HangingHair hanging(scene, model);
  auto length_at = [&](glm::vec2 uv) { return hanging.length(uv); };
  const float max_length = hanging.maxLength();
  PillarOptions popt;
  popt.target_count = hair.particles;
  popt.seed = scene.seed;
  auto t_sampling = Clock::now();
  const PillarResult pillar = samplePillar(scalp, length_at, max_length, popt);
  rep.seconds_sampling = since(t_sampling);
  rp = pillar.radius;
  const std::size_t n = pillar.samples.size();
  if (n < 2) throw SceneError(scene.source + ": hair.particles: too few particles could be placed");

  // 2. Root directions from the whorl and cantilever strands (method.md §6.1).
  const float clearance = std::max(scene.sim.contact_thickness, 0.25f * rp);
  auto t_strands = Clock::now();

  p.resize(n);
  // Each particle's own strand, grown only as far as the particle (the
  // pieces beyond do not change the ones before): the particles are
  // independent, so they are shared among the threads (the same bits on
  // any count). The bodies' queries and the scalp's are read-only.
  parallel::forEachDynamic(buildThreads(scene), (n + kStrandBatch - 1) / kStrandBatch, [&](std::size_t batch) {
    for (std::size_t k = batch * kStrandBatch, e = std::min(n, k + kStrandBatch); k < e; ++k) {
      const PillarSample& smp = pillar.samples[k];
      p.uv[k] = smp.uv;
      p.arc_length[k] = smp.s;
      p.root_point[k] = smp.point;
      p.mass[k] = hair.mass / static_cast<float>(n);
      p.velocity[k] = glm::vec3(0.0f);
      if (smp.s < 0.0f) {
        const glm::vec3 root_dir = hanging.rootDirection(smp.uv);
        p.is_root[k] = 1;
        p.position[k] = smp.point + smp.s * root_dir;
        p.direction[k] = root_dir;
      } else {
        p.is_root[k] = 0;
        const float length = length_at(smp.uv);
        const int segments = std::max(8, static_cast<int>(std::ceil(length / (0.5f * rp))));
        const CantileverStrand strand = hanging.strand(smp.uv, segments, clearance, smp.s);
        p.position[k] = strand.position(smp.s);
        p.direction[k] = strand.tangent(smp.s);
      }
    }
  });

  rep.seconds_strands = since(t_strands);
}

Solver buildSolverReporting(const SceneDesc& scene, BuildReport* report, BuildReport& rep) {
  const HairSpec& hair = scene.hair;
  // about 3.7 kB a particle with its connections, neighbours and scratch
  // (1 million: 3.6 GB and 100 s to start, on the sphere)
  if (static_cast<std::size_t>(hair.particles) > scene.limits.max_particles)
    throw SceneError(scene.source + ": hair.particles: " + std::to_string(hair.particles) +
                     " is above the limit of " + std::to_string(scene.limits.max_particles) +
                     " (about 3.7 kB of memory a particle): use fewer (or --allow-expensive)");

  // 0. The head, its scalp and the bodies (method.md §5, §6.1).
  const HeadModel model = HeadModel::build(scene, scene.source, scene.limits.mesh, &rep);
  const std::shared_ptr<const Body> head = model.head();
  const std::shared_ptr<const Body> torso = model.torso();
  // The head turns about its frame's origin (data/scenes/README.md, Meshes):
  // a mesh placed far from it swings on a long arm, at accelerations no
  // neck gives (an origin at the feet of a whole-body model, say).
  if (scene.motion.kind() != HeadTrajectory::Kind::Still && !model.headMesh().vertices.empty()) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& v : model.headMesh().vertices) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    const float size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const float arm = glm::length(glm::max(glm::max(lo, -hi), glm::vec3(0.0f)));  // origin to the box
    if (arm > 0.5f * size) {
      char text[160];
      std::snprintf(text, sizeof text, "%.2f m from the head's bounding box (the head is %.2f m across)", arm,
                    size);
      rep.warnings.push_back(std::string("motion: the head turns about its frame's origin, ") + text +
                             ", so it swings on a long arm; place the origin on the neck axis at about ear "
                             "height (head.offset or head.center)");
    }
  }

  // 1-2. The particles: from a style's strands (method.md §6.2) or hung by
  //      cantilever strands (method.md §6.1).
  const float total_mass = hair.mass;
  const bool styled = hair.style_data || !hair.style.empty();
  Particles p;
  float rp = 0;
  float style_shape_keeping = 0;
  TieTethers tie_tethers;
  if (styled)
    style_shape_keeping = growFromStyle(scene, model, p, rp, rep, tie_tethers);
  else
    growCantilever(scene, model, p, rp, rep);
  const std::size_t n = p.size();

  // 3. Order the particles along a Morton curve so that neighbours are near
  //    in memory (our choice, not the method's; keeps the gather loops cache-friendly).
  {
    std::vector<std::uint64_t> key(n);
    for (std::size_t k = 0; k < n; ++k) key[k] = NeighborGrid::cellKey(p.position[k], 1.0f / rp);
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    p = p.select(order);
    tie_tethers.select(order);
  }

  // 4. Smoothing lengths from the sampling (method.md §9).
  float mean_nn = 0;
  {
    NeighborGrid grid;
    grid.build(p.position, 2.0f * rp, 1);
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (p.is_root[i]) continue;
      float best = INFINITY;
      for (std::uint32_t j : grid.neighbors(i))
        best = std::min(best, glm::length(p.position[j] - p.position[i]));
      if (std::isfinite(best)) {
        sum += best;
        ++count;
      }
    }
    mean_nn = count ? static_cast<float>(sum / static_cast<double>(count)) : rp;
  }
  SimParams params = scene.sim;
  if (scene.shape_keeping_auto) params.shape_keeping = styled ? style_shape_keeping : 0.0f;
  rep.shape_keeping = params.shape_keeping;
  if (scene.h1_auto) params.h1 = hair.h1_scale * rp;
  // h2 a little below the spacing of the placed hair (method.md §9), and in any
  // case below h1: hair that hangs loosely is not denser than its sampling.
  if (scene.h2_auto) params.h2 = std::min(hair.h2_scale * mean_nn, 0.8f * params.h1);
  if (!(params.h2 < params.h1))
    throw SceneError(scene.source + ": solver.h2 = " + num(params.h2) +
                     " must be smaller than solver.h1 = " + num(params.h1) +
                     " (Poisson radius " + num(rp) +
                     " m, mean nearest-neighbour distance " + num(mean_nn) + " m)");

  // 5. Time step: the given substeps, or the fewest that keep the step at
  //    60% of the stable limit and the damping rates stable.
  const double frame_time = 1.0 / scene.frame_rate;
  int substeps = scene.substeps > 0 ? scene.substeps : 1;
  params.time_step = frame_time / substeps;
  if (scene.substeps == 0) {
    // a provisional step for the checks below; "auto" sets the real one
    // from every bound (below). It is short enough for the damping rates
    // and the holds, whose own bounds then decide how many steps they need.
    double dt = std::min(static_cast<double>(params.time_step), 1.0e-3);
    for (const DecayRate& r : decayRates(params))
      if (std::isfinite(r.rate) && r.rate > 0.0f) dt = std::min(dt, 0.8 * kMaxDecayPerStep / r.rate);
    if (std::isfinite(params.shape_keeping) && params.shape_keeping > 0.0f)
      dt = std::min(dt, 0.8 * kMaxHoldPhasePerStep / (2.0 * std::numbers::pi * params.shape_keeping));
    params.time_step = static_cast<float>(dt);
  }
  auto problems = validate(params);
  if (!problems.empty()) {
    std::string msg = scene.source + ": invalid solver parameters:";
    for (const auto& pr : problems) msg += "\n  solver." + pr;
    const bool about_step = std::any_of(problems.begin(), problems.end(), [](const std::string& pr) {
      return pr.find("time_step") != std::string::npos;
    });
    if (scene.substeps > 0 && about_step)
      msg += "\n  (time_step = 1 / (frame_rate x substeps) = 1 / (" + num(scene.frame_rate) + " x " +
             std::to_string(scene.substeps) + "): more substeps, or \"substeps\": \"auto\", shorten it)";
    throw SceneError(msg);
  }
  // 4b. Stragglers (method.md §3.1 connectivity): a particle with no particle
  //     nearer the root within the springs' reach (most of 2 h1) can hang
  //     on its root tether alone; the Poisson sampling leaves a few where a
  //     pillar thins out at its edge. In order of s, those within twice
  //     that reach of hair nearer the root are drawn in to it, the others
  //     are dropped, so that the rest each have a neighbour on the root
  //     side; the dropped ones' mass is shared.
  {
    const std::size_t before = p.size();
    std::size_t free_before = 0;
    for (std::size_t k = 0; k < before; ++k) free_before += p.is_root[k] ? 0 : 1;
    const std::vector<std::uint32_t> kept =
        anchorableParticles(p, 1.8f * params.h1, 3.6f * params.h1, rep.stragglers_pulled);
    if (kept.size() < before) {
      p = p.select(kept);
      tie_tethers.select(kept);
      for (float& m : p.mass) m = total_mass / static_cast<float>(kept.size());
    }
    rep.stragglers_dropped = before - kept.size();
    if (free_before > 0 && 2 * rep.stragglers_dropped > free_before)
      throw SceneError(scene.source + ": " + std::to_string(rep.stragglers_dropped) + " of " +
                       std::to_string(free_before) +
                       " hair particles have no particle nearer the root within 1.8 h1 = " +
                       num(1.8 * params.h1) + " m, so they cannot reach a root and would fall (" +
                       (scene.h1_auto ? "raise hair.h1_scale or hair.particles, or make the scalp larger"
                                      : "solver.h1 is too small for the particle spacing: raise it, or "
                                        "leave it out to have it set from the sampling") + ")");
  }
  Solver solver(params, std::move(p), head, scene.motion);
  if (!tie_tethers.reach.empty()) {
    if (params.shape_keeping > 0.0f) {
      try {
        solver.setShapeKeepingStrengths(tie_tethers.hold);
      } catch (const std::invalid_argument& e) {
        throw SceneError(scene.source + ": hair.style: a tie's hold is too strong for the time step (" +
                         std::string(e.what()) + "): lower ties[].hold or raise substeps");
      }
    }
    solver.setTieTethers(std::move(tie_tethers.point), std::move(tie_tethers.reach));
  }
  // Hair that hangs on nothing: no roots, no connections, or most of the
  // hair unable to reach a root through its connections (a scalp too small
  // for the sampling, a smoothing length below the particle spacing).
  {
    const InitReport& r = solver.initReport();
    const std::size_t free_particles = r.particles - r.roots;
    const std::string fix =
        " (the scalp is too small for the hair, or hair.h1_scale too small for the particle "
        "spacing: make the head or scalp larger, or raise hair.h1_scale or hair.particles)";
    if (r.roots == 0)
      throw SceneError(scene.source + ": no particle lies under the scalp, so the hair hangs on nothing" + fix);
    if (r.connection_pairs == 0)
      throw SceneError(scene.source + ": no two particles are within h1 = " + num(params.h1) +
                       " m of each other, so nothing holds the hair together" + fix);
    if (free_particles > 0 && 2 * r.unanchored > free_particles)
      throw SceneError(scene.source + ": " + std::to_string(r.unanchored) + " of " + std::to_string(free_particles) +
                       " hair particles cannot reach a root through their connections and would fall" + fix);
  }
  if (torso) solver.addWorldBody(torso);
  for (const ObstacleSpec& o : scene.obstacles) {
    std::shared_ptr<const Body> shape;
    if (o.shape == ObstacleSpec::Shape::Sphere)
      shape = std::make_shared<SphereBody>(o.a, o.radius);
    else
      shape = std::make_shared<CapsuleBody>(o.a, o.b, o.radius);
    solver.addWorldBody(shape, o.motion, o.begin, o.end, true);
  }
  if (scene.has_wind) {
    const glm::vec3 box = scene.wind.box_size;
    const double air = static_cast<double>(box.x) * box.y * box.z /
                       std::pow(static_cast<double>(scene.wind.spacing), 3.0);
    if (air > static_cast<double>(scene.limits.max_air_particles))
      throw SceneError(scene.source + ": wind.spacing: " + num(scene.wind.spacing) +
                       " m fills the air box with about " + std::to_string(static_cast<long long>(air)) +
                       " air particles (or cells of the air grid), above the limit of " + std::to_string(scene.limits.max_air_particles) +
                       ": use a larger spacing or a smaller wind.box_size (or --allow-expensive)");
    try {
      solver.setWind(scene.wind);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.source + ": " + e.what());
    }
    // A wind that cannot reach the hair runs (hair may swing into the box)
    // but is rarely what was meant: say so.
    auto text = [](glm::vec3 v) {
      std::string t = "[";
      for (int a = 0; a < 3; ++a) (t += num(v[a])) += a < 2 ? ", " : "]";
      return t;
    };
    const std::string where =
        "wind.box_center " + text(scene.wind.box_center) + ", wind.box_size " + text(scene.wind.box_size);
    if (solver.airCount() == 0)
      rep.warnings.push_back(where + ": the air box holds no air (it is smaller than wind.spacing " +
                             num(scene.wind.spacing) + " m, or inside the bodies): the wind does nothing");
    else {
      std::vector<glm::vec3> world;
      solver.worldPositions(world);
      const WindAxes axes = windAxes(scene.wind);
      const glm::vec3 half = 0.5f * scene.wind.box_size;
      const bool reaches = std::any_of(world.begin(), world.end(), [&](const glm::vec3& x) {
        const glm::vec3 d = x - scene.wind.box_center;
        return std::abs(glm::dot(d, axes.wind)) <= half.x && std::abs(glm::dot(d, axes.up)) <= half.y &&
               std::abs(glm::dot(d, axes.side)) <= half.z;
      });
      if (!reaches)
        rep.warnings.push_back(where + ": the air box holds none of the hair at the start: the wind touches it "
                               "only where it swings into the box");
    }
  }
  // The longest step each bound allows, and what to change to relax it: the
  // auto step takes the shortest; a scene that would need more steps a
  // frame than the limit (given or auto) is refused naming the bound.
  struct StepBound {
    double seconds;
    std::string what, fix;
  };
  std::vector<StepBound> bounds;
  if (params.implicit_springs)  // accuracy only (docs/design.md "Implicit springs": kAccurateStep)
    bounds.push_back({kAccurateStep, "the implicit springs' accuracy (at most 1/90 s a step)",
                      "raise frame_rate (shorter frames)"});
  else  // 60% of the stable spring step
    bounds.push_back({0.6 * solver.initReport().stable_time_step,
                      "the explicit springs' stability (solver.youngs_modulus = " + num(params.youngs_modulus) + ")",
                      "lower solver.youngs_modulus, raise the particle spacing (fewer hair.particles) or set "
                      "solver.implicit_springs to true"});
  // no velocity-decay rate above kMaxDecayPerStep a step (validate() rejects more)
  for (const DecayRate& r : decayRates(params))
    if (r.rate > 0.0f)
      bounds.push_back({kMaxDecayPerStep / r.rate, std::string("solver.") + r.name + " = " + num(r.rate) + " 1/s",
                        std::string("lower solver.") + r.name});
  bounds.push_back({solver.airStableTimeStep(), "the wind's air particles (wind.speed, wind.spacing)",
                    "use the grid air (wind.model \"grid\"), a larger wind.spacing or a lower wind.speed"});
  bounds.push_back({solver.holdTimeStep(), "the style's holds (solver.shape_keeping and the ties' stiffness)",
                    "soften the style's holds (a lower solver.shape_keeping)"});
  const StepBound& tightest = *std::min_element(
      bounds.begin(), bounds.end(), [](const StepBound& a, const StepBound& b) { return a.seconds < b.seconds; });
  // (a bound that divides the frame exactly is not rounded up a step)
  const double needed =
      scene.substeps > 0 ? scene.substeps : std::ceil(frame_time / tightest.seconds * (1.0 - 1e-6));
  if (needed > scene.limits.max_substeps) {
    const std::string frame = "a frame (1/" + num(scene.frame_rate) + " s)";
    if (scene.substeps > 0)
      throw SceneError(scene.source + ": substeps: " + std::to_string(scene.substeps) +
                       " steps a frame are above the limit of " + std::to_string(scene.limits.max_substeps) +
                       ": use fewer substeps or \"auto\" (or --allow-expensive)");
    throw SceneError(scene.source + ": " + tightest.what + " bounds the step to " + num(tightest.seconds * 1e3) +
                     " ms, so " + frame + " would need " + std::to_string(static_cast<long long>(needed)) +
                     " steps, above the limit of " + std::to_string(scene.limits.max_substeps) + ": " + tightest.fix +
                     " (or --allow-expensive)");
  }
  if (scene.substeps == 0) {
    substeps = std::max(1, static_cast<int>(needed));
    solver.setTimeStep(frame_time / substeps);
  }
  // the hair comes to rest before the first frame (as grown, it fans out)
  if (scene.settle > 0.0) {
    rep.grown = std::make_shared<const Particles>(solver.particles());
    solver.settle(static_cast<int>(std::lround(scene.settle * scene.frame_rate * substeps)));
  }
  if (report) {
    rep.poisson_radius = rp;
    rep.mean_neighbor_distance = mean_nn;
    rep.substeps = substeps;
    rep.time_step = solver.params().time_step;
    *report = rep;
  }
  return solver;
}

}  // namespace

}  // namespace loosehair
