#include "loosehair/snapshot.hpp"
#include "loosehair/param_table.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/solver.hpp"

#include "wind/air.hpp"
#include "wind/air_grid.hpp"
#include "solver/spring_scratch.hpp"
#include "solver/step_context.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace loosehair {

static_assert(std::endian::native == std::endian::little,
              "snapshots are written little-endian, as this machine stores numbers");

namespace {

// What air the snapshot holds (the byte after the hair's state).
constexpr std::uint8_t kNoAir = 0, kParticleAir = 1, kGridAir = 2;

constexpr char kMagic[16] = {'l', 'o', 'o', 's', 'e', 'h', 'a', 'i', 'r', '-', 's', 't', 'a', 't', 'e', '\n'};
constexpr std::size_t kHeaderBytes = 16 + 4 + 4 + 8 + 8;

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ULL) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

class Writer {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  template <class T>
  void array(const std::vector<T>& values) {
    put<std::uint64_t>(values.size());
    if (!values.empty()) out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  std::string out;
};

// Reads the payload with every length checked against what is left.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}
  template <class T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  template <class T>
  std::vector<T> array(const char* what, std::uint64_t expected_count = UINT64_MAX) {
    const auto count = get<std::uint64_t>(what);
    if (expected_count != UINT64_MAX && count != expected_count)
      fail(std::string(what) + ": " + std::to_string(count) + " values where the scene has " +
           std::to_string(expected_count));
    if (count > (bytes_.size() - at_) / sizeof(T)) need(SIZE_MAX, what);
    std::vector<T> values(static_cast<std::size_t>(count));
    if (!values.empty())  // (an empty vector's data() may be null)
      std::memcpy(values.data(), bytes_.data() + at_, values.size() * sizeof(T));
    at_ += values.size() * sizeof(T);
    return values;
  }
  void end() {
    if (at_ != bytes_.size()) fail("has " + std::to_string(bytes_.size() - at_) + " bytes after its state");
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw SnapshotError(name_ + ": not a usable snapshot: " + why);
  }

 private:
  void need(std::size_t bytes, const char* what) const {
    if (bytes > bytes_.size() - at_) fail(std::string("ends inside ") + what);
  }
  std::string_view bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

bool finite(const std::vector<glm::vec3>& v) {
  for (const glm::vec3& p : v)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}
// The largest speed a snapshot's hair or air may have (m/s): ten times the
// fastest wind a scene may blow; the hair never comes near it.
constexpr float kMaxSnapshotSpeed = 1000.0f;
// The longest run a snapshot may be from (s) and its most steps: beyond
// these the frame counts of a resumed run overflow.
constexpr double kMaxSnapshotTime = 1e7;
// Air particles one cell of the air spacing may hold (about one at rest).
constexpr std::uint32_t kMaxAirPerCell = 64;
constexpr std::uint64_t kMaxSnapshotSteps = std::uint64_t{1} << 40;
// How far the head may have carried the hair from where it grows (m): a
// motion file's keyframes translate it by 10 m at most; a hand drag less.
constexpr float kHeadTravel = 100.0f;

// (in double: a float length of 3e38 would overflow)
double largest(const std::vector<glm::vec3>& v) {
  double m = 0.0;
  for (const glm::vec3& x : v) m = std::max(m, glm::length(glm::dvec3(x)));
  return m;
}
double largest(const std::vector<float>& v) {
  double m = 0.0;
  for (float x : v) m = std::max(m, static_cast<double>(std::abs(x)));
  return m;
}
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool finite(const std::vector<float>& v) {
  for (float f : v)
    if (!std::isfinite(f)) return false;
  return true;
}

}  // namespace

// The solver's private state, for the snapshot only.
struct SnapshotAccess {
  // The wind's air as its model (wind_air.hpp): the snapshot holds each
  // model's own state.
  static AirGrid* gridAir(const Solver& s) {
    return s.air_ && s.air_->model() == AirModel::Grid ? static_cast<AirGrid*>(s.air_.get()) : nullptr;
  }
  static AirSystem* particleAir(const Solver& s) {
    return s.air_ && s.air_->model() == AirModel::Particles ? static_cast<AirSystem*>(s.air_.get()) : nullptr;
  }
  static std::uint8_t airKind(const Solver& s) {
    return particleAir(s) ? kParticleAir : (gridAir(s) ? kGridAir : kNoAir);
  }

  static std::uint64_t fingerprint(const Solver& s) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    auto mix = [&h](const auto& vec) {
      h = fnv1a(std::string_view(reinterpret_cast<const char*>(vec.data()), vec.size() * sizeof(vec[0])),
                h ^ vec.size());
    };
    const Particles& p = s.particles_;
    mix(p.position);
    mix(p.velocity);
    mix(p.direction);
    mix(p.mass);
    mix(p.is_root);
    mix(p.uv);
    mix(p.arc_length);
    mix(p.root_point);
    const ConnectionSet& c = s.connections_;
    mix(c.offset);
    mix(c.partner);
    mix(c.rest_length);
    mix(c.strength);
    if (const AirSystem* air = particleAir(s)) {
      mix(air->positions());
      mix(air->velocities());
    }
    if (const AirGrid* grid = gridAir(s))
      for (const auto& u : grid->state().u) mix(u);
    if (s.air_) {
      // the wind: its initial air can be the same for another wind (a
      // grid air that starts still, or a box far from the hair)
      const WindParams& w = s.air_->params();
      std::vector<double> wind = {static_cast<double>(w.model),
                                  w.direction.x,
                                  w.direction.y,
                                  w.direction.z,
                                  w.speed,
                                  w.box_center.x,
                                  w.box_center.y,
                                  w.box_center.z,
                                  w.box_size.x,
                                  w.box_size.y,
                                  w.box_size.z,
                                  w.spacing,
                                  w.h_scale,
                                  w.density,
                                  static_cast<double>(w.projection_iterations),
                                  w.sound_speed,
                                  w.viscosity_rate,
                                  w.drag_rate};
      for (const auto& [time, scale] : w.profile) {
        wind.push_back(time);
        wind.push_back(scale);
      }
      mix(wind);
    }
    // the physical parameters (not the thread count, nor the time step,
    // which the snapshot carries)
    // (param_table.cpp: those marked Always, in the table's order, then
    // the count of world bodies; those marked WhenOn below)
    const SimParams& q = s.params_;
    std::vector<float> values;
    for (const ParamInfo& info : paramTable())
      if (info.print == ParamInfo::Print::Always) values.push_back(static_cast<float>(info.get(q)));
    values.push_back(static_cast<float>(s.world_bodies_.size()));
    mix(values);
    if (q.shape_keeping > 0.0f) mix(std::vector<float>{q.shape_keeping});
    if (q.hair_chain) mix(std::vector<float>{2.0f});
    if (q.implicit_springs)
      mix(std::vector<float>{1.0f, q.implicit_tolerance, static_cast<float>(q.implicit_iterations)});
    return h;
  }

  static std::string encode(const Solver& s) {
    Writer w;
    w.put<double>(s.time_);
    w.put<std::uint64_t>(s.stats_.steps);
    w.put<double>(s.params_.time_step);
    w.array(s.particles_.position);
    w.array(s.particles_.velocity);
    w.array(s.particles_.direction);
    w.put<std::uint8_t>(s.absorb_corrections_ ? 1 : 0);
    const auto& scratch = *s.scratch_;
    w.put<std::uint8_t>(scratch.sums_current ? 1 : 0);
    if (scratch.sums_current) {
      w.array(scratch.sum_root);
      w.array(scratch.sum_tip);
      w.put<std::uint64_t>(scratch.active_entries);
    }
    // the implicit springs' last velocity change: the next solve's start
    w.array(s.spring_dv_);
    w.put<std::uint8_t>(airKind(s));
    if (const AirGrid* grid = gridAir(s)) {
      const AirGrid::State g = grid->state();
      for (const auto& u : g.u) w.array(u);
      w.array(g.pressure);
      w.put<double>(g.pending);
    }
    if (const AirSystem* air = particleAir(s)) {
      const AirSystem::State a = air->state();
      w.array(a.x);
      w.array(a.v);
      w.array(a.density);
      w.put<double>(a.advance);
      w.put<std::uint64_t>(a.layer_counter);
      w.put<std::uint64_t>(a.emitted);
      w.put<std::uint64_t>(a.removed);
    }
    return std::move(w.out);
  }

  // What a snapshot holds, read and not yet checked.
  struct Decoded {
    double time = 0, dt = 0;
    std::uint64_t steps = 0;
    std::vector<glm::vec3> position, velocity, direction, spring_dv;
    bool absorb = false, sums_current = false;
    std::vector<float> sum_root, sum_tip;
    std::uint64_t active = 0;
    std::uint8_t air_kind = 0;
    AirGrid::State grid;
    AirSystem::State air;
  };

  // Reads every field (sizes checked against the scene, the wind's kind too).
  static Decoded read(Reader& r, Solver& s) {
    const std::size_t n = s.particles_.size();
    Decoded d;
    const std::uint8_t scene_kind = airKind(s);
    AirGrid* const scene_grid = gridAir(s);
    d.time = r.get<double>("the time");
    d.steps = r.get<std::uint64_t>("the step count");
    d.dt = r.get<double>("the time step");
    d.position = r.array<glm::vec3>("the positions", n);
    d.velocity = r.array<glm::vec3>("the velocities", n);
    d.direction = r.array<glm::vec3>("the directions", n);
    d.absorb = r.get<std::uint8_t>("the correction flag") != 0;
    d.sums_current = r.get<std::uint8_t>("the sums flag") != 0;
    if (d.sums_current) {
      d.sum_root = r.array<float>("the root-side sums", n);
      d.sum_tip = r.array<float>("the tip-side sums", n);
      d.active = r.get<std::uint64_t>("the active connection count");
    }
    d.spring_dv = r.array<glm::vec3>("the implicit springs' last velocity change");
    if (!d.spring_dv.empty() && d.spring_dv.size() != n)
      r.fail("the implicit springs' last velocity change has " + std::to_string(d.spring_dv.size()) +
             " values where the scene has " + std::to_string(n) + " particles");
    d.air_kind = r.get<std::uint8_t>("the wind flag");
    if (d.air_kind != scene_kind) {
      if (d.air_kind == kNoAir) r.fail("the scene has wind and it has none");
      if (scene_kind == kNoAir) r.fail("it has wind and the scene has none");
      r.fail("its air is on a " + std::string(d.air_kind == kGridAir ? "grid" : "set of particles") +
             " and the scene's is not");
    }
    if (d.air_kind == kGridAir) {
      for (int c = 0; c < 3; ++c)
        d.grid.u[static_cast<std::size_t>(c)] = r.array<float>("the air grid's velocities", scene_grid->faceCount(c));
      d.grid.pressure = r.array<float>("the air grid's pressures", scene_grid->cellCount());
      d.grid.pending = r.get<double>("the air grid's time since its step");
    }
    if (d.air_kind == kParticleAir) {
      d.air.x = r.array<glm::vec3>("the air positions");
      d.air.v = r.array<glm::vec3>("the air velocities", d.air.x.size());
      d.air.density = r.array<float>("the air densities");
      if (d.air.density.size() > d.air.x.size()) r.fail("more air densities than air particles");
      d.air.advance = r.get<double>("the wind run");
      d.air.layer_counter = r.get<std::uint64_t>("the air layer count");
      d.air.emitted = r.get<std::uint64_t>("the emitted air count");
      d.air.removed = r.get<std::uint64_t>("the removed air count");
    }
    r.end();
    return d;
  }

  // The hair's state within what the scene allows: finite, unit
  // directions, hair within its length of the scalp as far as a head may
  // travel, speeds and air within bounds no run reaches.
  static void checkHair(Reader& r, const Solver& s, const Decoded& d) {
    const std::size_t n = s.particles_.size();
    const auto& position = d.position;
    const auto& velocity = d.velocity;
    const auto& direction = d.direction;
    const auto& spring_dv = d.spring_dv;
    const auto& sum_root = d.sum_root;
    const auto& sum_tip = d.sum_tip;
    const auto& air = d.air;
    const auto& grid = d.grid;
    const double time = d.time;
    const std::uint64_t steps = d.steps;
    if (!std::isfinite(time) || time < 0.0 || time > kMaxSnapshotTime)
      r.fail("the time is " + num(time) + " s, outside [0, " + num(kMaxSnapshotTime) + "]");
    if (steps > kMaxSnapshotSteps)
      r.fail("the step count is " + std::to_string(steps) + ", more than the " + std::to_string(kMaxSnapshotSteps) +
             " a run may have");
    if (!finite(position) || !finite(velocity) || !finite(direction) || !finite(sum_root) || !finite(sum_tip) ||
        !finite(spring_dv) || !finite(air.x) || !finite(air.v) || !finite(air.density) || !std::isfinite(air.advance) ||
        !finite(grid.u[0]) || !finite(grid.u[1]) || !finite(grid.u[2]) || !finite(grid.pressure))
      r.fail("it holds non-finite numbers");
    for (const glm::vec3& t : direction)
      if (std::abs(glm::dot(t, t) - 1.0f) > 1e-3f) r.fail("a hair direction is not a unit vector");
    {
      const Particles& p = s.particles_;
      double reach = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        reach = std::max(reach, static_cast<double>(glm::length(p.root_point[i]) + 2.0f * std::abs(p.arc_length[i])));
      const double far = largest(position);
      if (far > reach + kHeadTravel)
        r.fail("a hair particle lies " + num(far) + " m from the head's origin; this scene's hair reaches " +
               num(reach) + " m and a head travels " + num(kHeadTravel) + " m at most");
      const double fast = std::max({largest(velocity), largest(spring_dv), largest(air.v), largest(grid.u[0]),
                                    largest(grid.u[1]), largest(grid.u[2])});
      if (fast > kMaxSnapshotSpeed)
        r.fail("it holds a speed of " + num(fast) + " m/s, above the " + num(kMaxSnapshotSpeed) +
               " m/s a hair or air state may have");
    }
  }

  // Particle air within its box and spacing.
  static void checkParticleAir(Reader& r, const AirSystem& scene_air, const AirSystem::State& air) {
    const WindParams& w = scene_air.params();
    const double box = static_cast<double>(w.box_size.x) * w.box_size.y * w.box_size.z;
    const double capacity = 4.0 * box / (static_cast<double>(w.spacing) * w.spacing * w.spacing) + 1000.0;
    if (static_cast<double>(air.x.size()) > capacity)
      r.fail("it holds " + std::to_string(air.x.size()) + " air particles where this scene's air box holds about " +
             num(capacity / 4.0));
    if (!(air.advance >= 0.0 && air.advance <= w.spacing))
      r.fail("the wind run is " + num(air.advance) + " m, outside [0, " + num(w.spacing) + "] (the air spacing)");
    if (air.removed > air.emitted) r.fail("more air particles removed than emitted");
    const double box_reach = glm::length(w.box_size) + glm::length(w.box_center) + kHeadTravel;
    if (largest(air.x) > box_reach)
      r.fail("an air particle lies " + num(largest(air.x)) + " m away, beyond the air box");
    // air crowded into one place would make every pair of it neighbours
    std::unordered_map<std::uint64_t, std::uint32_t> cells;
    cells.reserve(air.x.size());
    for (const glm::vec3& x : air.x) {
      const glm::ivec3 c = glm::ivec3(glm::floor(x / w.spacing)) + glm::ivec3(1 << 20);
      const std::uint64_t key = (static_cast<std::uint64_t>(c.x) << 42) ^ (static_cast<std::uint64_t>(c.y) << 21) ^
                                static_cast<std::uint64_t>(c.z);
      if (++cells[key] > kMaxAirPerCell)
        r.fail("more than " + std::to_string(kMaxAirPerCell) +
               " air particles crowd into one cell of the air "
               "spacing, near (" +
               num(x.x) + ", " + num(x.y) + ", " + num(x.z) + ")");
    }
  }

  static void decode(Solver& s, std::string_view payload, const std::string& name) {
    Reader r(payload, name);
    Decoded d = read(r, s);
    checkHair(r, s, d);
    AirGrid* const scene_grid = gridAir(s);
    AirSystem* const scene_air = particleAir(s);
    if (d.air_kind == kParticleAir) checkParticleAir(r, *scene_air, d.air);
    const double dt = d.dt;
    const auto& grid = d.grid;
    const std::uint8_t air_kind = d.air_kind;
    if (dt != s.params_.time_step) {
      SimParams next = s.params_;
      next.time_step = dt;
      if (!validate(next).empty() || !std::isfinite(dt))
        r.fail("its time step " + std::to_string(dt) + " s is not valid for this scene");
    }

    if (air_kind == kGridAir &&
        (!std::isfinite(grid.pending) || grid.pending < 0.0 || grid.pending > 10.0 * scene_grid->stepLength()))
      r.fail("the air grid's time since its step is " + std::to_string(grid.pending) + " s");
    // Everything checked: the solver changes only from here on.
    if (dt != s.params_.time_step) s.setTimeStep(dt);
    s.time_ = d.time;
    s.stats_ = StepStats{};
    s.stats_.steps = d.steps;
    s.particles_.position = std::move(d.position);
    s.particles_.velocity = std::move(d.velocity);
    s.particles_.direction = std::move(d.direction);
    s.absorb_corrections_ = d.absorb;
    s.spring_dv_ = std::move(d.spring_dv);
    if (scene_air) scene_air->restore(std::move(d.air));
    if (scene_grid) scene_grid->restore(std::move(d.grid));  // checked above: cannot throw
    // Queries between steps see the state (as after a step).
    s.findNeighbors();
    s.measureDensity(s.step_->pair_records);
    auto& scratch = *s.scratch_;
    scratch.sums_current = d.sums_current;
    if (d.sums_current) {
      scratch.sum_root = std::move(d.sum_root);
      scratch.sum_tip = std::move(d.sum_tip);
      scratch.active_entries = static_cast<std::size_t>(d.active);
    }
  }
};

std::uint64_t Solver::sceneFingerprint() const {
  if (!fingerprint_taken_) {
    fingerprint_ = SnapshotAccess::fingerprint(*this);
    fingerprint_taken_ = true;
  }
  return fingerprint_;
}

std::string encodeSnapshot(const Solver& solver) {
  const std::string payload = SnapshotAccess::encode(solver);
  Writer w;
  w.out.append(kMagic, sizeof kMagic);
  w.put<std::uint32_t>(kSnapshotVersion);
  w.put<std::uint32_t>(0);
  w.put<std::uint64_t>(solver.sceneFingerprint());
  w.put<std::uint64_t>(payload.size());
  w.out += payload;
  w.put<std::uint64_t>(fnv1a(w.out));
  return std::move(w.out);
}

void decodeSnapshot(Solver& solver, std::string_view bytes, const std::string& name) {
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw SnapshotError(name + ": not a loosehair snapshot (it does not start with \"loosehair-state\")");
  if (bytes.size() < kHeaderBytes + 8)
    throw SnapshotError(name + ": the snapshot is truncated (" + std::to_string(bytes.size()) + " bytes)");
  std::uint32_t version = 0;
  std::uint64_t fingerprint = 0, length = 0, checksum = 0;
  std::memcpy(&version, bytes.data() + 16, 4);
  std::memcpy(&fingerprint, bytes.data() + 24, 8);
  std::memcpy(&length, bytes.data() + 32, 8);
  if (version != kSnapshotVersion)
    throw SnapshotError(name + ": snapshot version " + std::to_string(version) + ", this program reads version " +
                        std::to_string(kSnapshotVersion));
  if (length != bytes.size() - kHeaderBytes - 8)
    throw SnapshotError(name + ": the snapshot is truncated or damaged (" + std::to_string(bytes.size()) +
                        " bytes where its header says " + std::to_string(length + kHeaderBytes + 8) + ")");
  std::memcpy(&checksum, bytes.data() + bytes.size() - 8, 8);
  if (checksum != fnv1a(bytes.substr(0, bytes.size() - 8)))
    throw SnapshotError(name + ": the snapshot is damaged (its checksum does not match)");
  if (fingerprint != solver.sceneFingerprint())
    throw SnapshotError(name +
                        ": the snapshot was saved from another scene (or another seed, "
                        "particle count or physical parameter) than the one given");
  SnapshotAccess::decode(solver, bytes.substr(kHeaderBytes, length), name);
}

void saveSnapshot(const Solver& solver, const std::string& path) {
  const std::string bytes = encodeSnapshot(solver);
  try {
    writeFileAtomically(path, {bytes});
  } catch (const FileError& e) {
    throw SnapshotError(e.what());
  }
}

void loadSnapshot(Solver& solver, const std::string& path) {
  std::string bytes;
  try {
    bytes = readRegularFile(path, kMaxSnapshotFileBytes);
  } catch (const FileError& e) {
    throw SnapshotError(e.what());
  }
  decodeSnapshot(solver, bytes, path);
}

}  // namespace loosehair
