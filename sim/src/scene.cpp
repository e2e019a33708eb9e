#include "loosehair/scene.hpp"

#include "init/cantilever.hpp"
#include "init/poisson_pillar.hpp"
#include "init/scalp_surface.hpp"
#include "neighbor_grid.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <set>
#include <sstream>

namespace loosehair {
namespace {

using json = nlohmann::json;

std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

// A JSON object being read: remembers its path for messages and which keys
// were used, so that misspelt fields are reported instead of ignored.
class Fields {
 public:
  Fields(const json& obj, std::string path, const std::string& source)
      : obj_(obj), path_(std::move(path)), source_(source) {
    if (!obj_.is_object()) fail("", "must be a JSON object, got " + show(obj_));
  }

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    std::string field = path_;
    if (!key.empty()) field += (field.empty() ? "" : ".") + key;
    throw SceneError(source_ + ": " + (field.empty() ? "" : field + ": ") + problem);
  }

  const std::string& source() const { return source_; }

  bool has(const std::string& key) {
    used_.insert(key);
    return obj_.contains(key);
  }
  const json& at(const std::string& key) {
    used_.insert(key);
    return obj_.at(key);
  }

  double number(const std::string& key, double fallback, double lo, double hi,
                bool lo_open = false) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_number()) fail(key, "must be a number, got " + show(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi || (lo_open && d == lo)) {
      std::ostringstream os;
      os << "must be a number in " << (lo_open ? "(" : "[") << lo << ", " << hi << "], got "
         << show(v);
      fail(key, os.str());
    }
    return d;
  }
  float real(const std::string& key, float fallback, double lo, double hi, bool lo_open = false) {
    return static_cast<float>(number(key, fallback, lo, hi, lo_open));
  }
  std::int64_t integer(const std::string& key, std::int64_t fallback, std::int64_t lo,
                       std::int64_t hi) {
    if (!has(key)) return fallback;
    const json& v = obj_.at(key);
    if (!v.is_number_integer()) fail(key, "must be an integer, got " + show(v));
    const std::int64_t i = v.get<std::int64_t>();
    if (i < lo || i > hi)
      fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + show(v));
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
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
      fail(key, "must be an array of three numbers, got " + show(v));
    glm::dvec3 out(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(out[a]) || std::abs(out[a]) > bound)
        fail(key, "must hold finite numbers of magnitude at most " + std::to_string(bound) +
                      ", got " + show(v));
    return out;
  }
  /// A number, or "auto" (returns nullopt-like: sets is_auto).
  double numberOrAuto(const std::string& key, double fallback, bool& is_auto, double lo,
                      double hi) {
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
    return Fields(obj_.at(key), path_.empty() ? key : path_ + "." + key, source_);
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
  std::set<std::string> used_;
};

void readSolver(Fields f, SceneDesc& s) {
  SimParams& p = s.sim;
  p.h1 = static_cast<float>(f.numberOrAuto("h1", p.h1, s.h1_auto, 0.0, 10.0));
  p.h2 = static_cast<float>(f.numberOrAuto("h2", p.h2, s.h2_auto, 0.0, 10.0));
  p.alignment_threshold = f.real("alignment_threshold", p.alignment_threshold, 0.0, 1.0);
  p.target_connections =
      static_cast<int>(f.integer("target_connections", p.target_connections, 1, 256));
  p.youngs_modulus = f.real("youngs_modulus", p.youngs_modulus, 0.0, 1e12, true);
  p.material_density = f.real("material_density", p.material_density, 0.0, 1e5, true);
  p.stiffness_clamp = f.real("stiffness_clamp", p.stiffness_clamp, 1.0, 1e6);
  p.spring_damping = f.real("spring_damping", p.spring_damping, 0.0, 1.0);
  p.strain_limit = f.boolean("strain_limit", p.strain_limit);
  p.max_strain = f.real("max_strain", p.max_strain, 0.0, 0.5);
  p.strain_limit_iterations =
      static_cast<int>(f.integer("strain_limit_iterations", p.strain_limit_iterations, 0, 1000));
  p.tether = f.boolean("tether", p.tether);
  p.tether_slack = f.real("tether_slack", p.tether_slack, 0.0, 1.0);
  p.hair_hair = f.boolean("hair_hair", p.hair_hair);
  p.pressure_stiffness = f.real("pressure_stiffness", p.pressure_stiffness, 0.0, 1e6);
  p.rest_density_scale = f.real("rest_density_scale", p.rest_density_scale, 0.0, 100.0, true);
  p.collision_rate = f.real("collision_rate", p.collision_rate, 0.0, 1e6);
  p.friction_rate = f.real("friction_rate", p.friction_rate, 0.0, 1e6);
  p.gravity = glm::vec3(f.vec3("gravity", glm::dvec3(p.gravity), 1e3));
  p.air_drag = f.real("air_drag", p.air_drag, 0.0, 1e6);
  p.body_friction = f.real("body_friction", p.body_friction, 0.0, 100.0);
  p.contact_thickness = f.real("contact_thickness", p.contact_thickness, 0.0, 1.0);
  f.finish();
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
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw SceneError(source + ": invalid JSON: " + e.what());
  }
  SceneDesc s;
  s.source = source;
  Fields top(root, "", source);
  s.name = top.text("name", "scene");
  s.seed = static_cast<std::uint64_t>(top.integer("seed", 1, 0, INT64_MAX));
  s.frames = static_cast<int>(top.integer("frames", s.frames, 1, 10000000));
  s.frame_rate = top.number("frame_rate", s.frame_rate, 0.0, 10000.0, true);
  if (top.has("substeps") && top.at("substeps").is_string()) {
    if (top.at("substeps").get<std::string>() != "auto")
      top.fail("substeps", "must be a positive integer or \"auto\", got " + show(top.at("substeps")));
    s.substeps = 0;
  } else {
    s.substeps = static_cast<int>(top.integer("substeps", 0, 1, 100000));
  }

  if (!top.has("head")) top.fail("head", "is required");
  {
    Fields head = top.child("head");
    const std::string type = head.text("type", "sphere");
    if (type != "sphere") head.fail("type", "must be \"sphere\" (mesh heads come later), got \"" + type + "\"");
    s.head_center = glm::vec3(head.vec3("center", glm::dvec3(0.0), 100.0));
    s.head_radius = head.real("radius", s.head_radius, 0.0, 10.0, true);
    head.finish();
  }
  if (top.has("scalp")) {
    Fields scalp = top.child("scalp");
    const std::string type = scalp.text("type", "sphere-cap");
    if (type != "sphere-cap") scalp.fail("type", "must be \"sphere-cap\", got \"" + type + "\"");
    s.cap_angle_deg = scalp.real("cap_angle_deg", s.cap_angle_deg, 0.0, 180.0, true);
    scalp.finish();
  }
  if (top.has("hair")) {
    Fields hair = top.child("hair");
    HairSpec& h = s.hair;
    h.particles = static_cast<int>(hair.integer("particles", h.particles, 10, 20000000));
    h.length = hair.real("length", h.length, 0.0, 10.0, true);
    h.mass = hair.real("mass", h.mass, 0.0, 100.0, true);
    const glm::dvec3 whorl = hair.vec3("whorl", glm::dvec3(h.whorl), 1e6);
    if (!(glm::length(whorl) > 1e-9)) hair.fail("whorl", "must be a non-zero direction, got [0,0,0]");
    h.whorl = glm::vec3(glm::normalize(whorl));
    h.w_t = hair.real("w_t", h.w_t, 0.0, 1e6);
    h.w_n = hair.real("w_n", h.w_n, 0.0, 1e6);
    if (!(h.w_t + h.w_n > 0.0f)) hair.fail("w_n", "w_t and w_n must not both be zero");
    h.bending_stiffness = hair.real("bending_stiffness", h.bending_stiffness, 0.0, 1e6, true);
    h.layering = hair.real("layering", h.layering, 0.0, 10.0);
    h.h1_scale = hair.real("h1_scale", h.h1_scale, 0.0, 100.0, true);
    h.h2_scale = hair.real("h2_scale", h.h2_scale, 0.0, 100.0, true);
    hair.finish();
  }
  if (top.has("solver")) readSolver(top.child("solver"), s);
  if (top.has("motion")) s.motion = readMotion(top.child("motion"));
  top.finish();
  return s;
}

SceneDesc loadScene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read the scene file");
  return parseScene(text.str(), path);
}

Solver buildSolver(const SceneDesc& scene, BuildReport* report) {
  const HairSpec& hair = scene.hair;
  const float cap = glm::radians(scene.cap_angle_deg);
  SphereCapScalp scalp(scene.head_center, scene.head_radius, cap);
  auto head = std::make_shared<SphereBody>(scene.head_center, scene.head_radius);

  // 1. Poisson-disc particles in (u, v, s), SPEC §6.1.
  PillarOptions popt;
  popt.target_count = hair.particles;
  popt.seed = scene.seed;
  const float length = hair.length;
  const PillarResult pillar =
      samplePillar(scalp, [length](glm::vec2) { return length; }, length, popt);
  const float rp = pillar.radius;
  const std::size_t n = pillar.samples.size();
  if (n < 2) throw SceneError(scene.source + ": hair.particles: too few particles could be placed");

  // 2. Root directions from the whorl and cantilever strands (SPEC §6.1).
  const glm::dmat3 r0 = scene.motion.pose(0.0).rotation;
  glm::vec3 gdir(glm::transpose(r0) * glm::dvec3(scene.sim.gravity));
  const bool has_gravity = glm::length(gdir) > 0.0f;
  if (has_gravity) gdir = glm::normalize(gdir);
  const float clearance = std::max(scene.sim.contact_thickness, 0.25f * rp);
  const int segments = std::max(8, static_cast<int>(std::ceil(length / (0.5f * rp))));
  const float total_mass = hair.mass;

  Particles p;
  p.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const PillarSample& smp = pillar.samples[k];
    const glm::vec3 nrm = scalp.normal(smp.uv);
    glm::vec3 away = -hair.whorl - glm::dot(-hair.whorl, nrm) * nrm;
    const float away_len = glm::length(away);
    glm::vec3 root_dir = hair.w_n * nrm;
    if (away_len > 1e-6f) root_dir += hair.w_t * (away / away_len);
    root_dir = glm::length(root_dir) > 1e-6f ? glm::normalize(root_dir) : nrm;

    p.uv[k] = smp.uv;
    p.arc_length[k] = smp.s;
    p.root_point[k] = smp.point;
    p.mass[k] = total_mass / static_cast<float>(n);
    p.velocity[k] = glm::vec3(0.0f);
    if (smp.s < 0.0f) {
      p.is_root[k] = 1;
      p.position[k] = smp.point + smp.s * root_dir;
      p.direction[k] = root_dir;
    } else {
      p.is_root[k] = 0;
      const CantileverStrand strand(smp.point, root_dir, has_gravity ? gdir : root_dir, length,
                                    hair.bending_stiffness, head.get(), clearance, hair.layering,
                                    segments);
      p.position[k] = strand.position(smp.s);
      p.direction[k] = strand.tangent(smp.s);
    }
  }

  // 3. Order the particles along a Morton curve so that neighbours are near
  //    in memory (SPEC-independent; keeps the gather loops cache-friendly).
  {
    std::vector<std::uint64_t> key(n);
    for (std::size_t k = 0; k < n; ++k) key[k] = NeighborGrid::cellKey(p.position[k], 1.0f / rp);
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    Particles q;
    q.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t o = order[k];
      q.position[k] = p.position[o];
      q.velocity[k] = p.velocity[o];
      q.direction[k] = p.direction[o];
      q.mass[k] = p.mass[o];
      q.is_root[k] = p.is_root[o];
      q.uv[k] = p.uv[o];
      q.arc_length[k] = p.arc_length[o];
      q.root_point[k] = p.root_point[o];
    }
    p = std::move(q);
  }

  // 4. Smoothing lengths from the sampling (SPEC §9).
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
  if (scene.h1_auto) params.h1 = hair.h1_scale * rp;
  // h2 a little below the spacing of the placed hair (SPEC §9), and in any
  // case below h1: hair that hangs loosely is not denser than its sampling.
  if (scene.h2_auto) params.h2 = std::min(hair.h2_scale * mean_nn, 0.8f * params.h1);
  if (!(params.h2 < params.h1))
    throw SceneError(scene.source + ": solver.h2 = " + std::to_string(params.h2) +
                     " must be smaller than solver.h1 = " + std::to_string(params.h1) +
                     " (Poisson radius " + std::to_string(rp) +
                     " m, mean nearest-neighbour distance " + std::to_string(mean_nn) + " m)");

  // 5. Time step: the given substeps, or the fewest that keep the step at
  //    60% of the stable limit and the damping rates stable.
  const double frame_time = 1.0 / scene.frame_rate;
  int substeps = scene.substeps > 0 ? scene.substeps : 1;
  params.time_step = frame_time / substeps;
  if (scene.substeps == 0) params.time_step = std::min(params.time_step, 1.0e-3);
  auto problems = validate(params);
  if (!problems.empty()) {
    std::string msg = scene.source + ": invalid solver parameters:";
    for (const auto& pr : problems) msg += "\n  solver." + pr;
    throw SceneError(msg);
  }
  Solver solver(params, std::move(p), head, scene.motion);
  if (scene.substeps == 0) {
    // 60% of the stable spring step, and no velocity-decay rate above
    // 0.25 per step (validate() rejects more).
    const double fastest_rate = std::max({params.collision_rate, params.friction_rate,
                                          params.air_drag, 1e-9f});
    const double longest = std::min(0.6 * solver.initReport().stable_time_step,
                                    0.25 / fastest_rate);
    substeps = std::max(1, static_cast<int>(std::ceil(frame_time / longest)));
    solver.setTimeStep(frame_time / substeps);
  }
  if (report) {
    report->poisson_radius = rp;
    report->mean_neighbor_distance = mean_nn;
    report->substeps = substeps;
    report->time_step = solver.params().time_step;
  }
  return solver;
}

}  // namespace loosehair
