// Parameters changed in a running simulation (Solver::setParams, the
// viewer's panel): the table describes every parameter with a usable range,
// a live change takes effect, setting it back gives the bits of never
// changing it, and changes that need a new solver are refused by name.
#include "loosehair/file_io.hpp"
#include "loosehair/param_table.hpp"
#include "loosehair/scene.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>

using namespace loosehair;

TEST(ParamTable, EveryEntryReadsWritesAndItsRangeIsValid) {
  std::set<std::string> names;
  for (const ParamInfo& p : paramTable()) {
    EXPECT_TRUE(names.insert(p.name).second) << "duplicate " << p.name;
    EXPECT_EQ(findParam(p.name), &p);
    EXPECT_LT(p.lo, p.hi) << p.name;
    EXPECT_GT(std::string(p.help).size(), 10u) << p.name;
    const SimParams defaults;
    const double lowest = p.lo_open ? std::nextafter(p.lo, p.hi) : p.lo;
    for (double v : {lowest, p.hi}) {
      if (p.lo_open && p.lo == 0.0) v = std::max(v, 1e-30);  // a float field's smallest positive value
      SimParams q;
      p.set(q, v);
      const double want = p.kind == ParamInfo::Kind::Switch ? (v != 0 ? 1.0 : 0.0) : v;
      EXPECT_NEAR(p.get(q), want, 1e-6 * std::abs(want)) << p.name;  // float fields round
      if (std::string(p.name) == "h2") q.h1 = 0.08f;                 // h2 < h1
      if (std::string(p.name) == "h1") q.h2 = 0.001f;
      if (std::string(p.name) == "shape_keeping") q.time_step = 1e-3;
      // a rate at the top of its range is refused with this step (rate * dt);
      // the step at the top of its range likewise for the default rates
      if (std::string(p.name) == "time_step") q.collision_rate = q.friction_rate = q.air_drag = 0.0f;
      if (v == p.hi && (std::string(p.unit) == "1/s" || std::string(p.name) == "shape_keeping")) continue;
      if (std::string(p.name) == "h1") q.h2 = v == p.hi ? 0.011f : static_cast<float>(0.5 * v);
      if (std::string(p.name) == "h2" && v == p.hi) continue;  // h2 below h1 (at most 10 m)
      EXPECT_TRUE(validate(q).empty()) << p.name << " = " << v << ": " << validate(q).front();
    }
    const double d = p.get(defaults);
    EXPECT_TRUE(p.check(d).empty()) << p.name << " default " << d << " outside its range";
  }
  EXPECT_EQ(findParam("no_such_parameter"), nullptr);
  // one entry per scalar of SimParams: 28 scalars + the 3 components of gravity
  EXPECT_EQ(paramTable().size(), 31u);
}

namespace {

std::uint64_t run(int steps, const std::function<void(Solver&, int)>& at, bool implicit = false) {
  SceneDesc scene = lhtest::sphereScene(600, "{}", R"({"type": "shake", "amplitude_deg": 30})", 6);
  scene.sim.threads = 2;
  scene.sim.implicit_springs = implicit;
  Solver s = buildSolver(scene);
  for (int k = 0; k < steps; ++k) {
    at(s, k);
    s.step();
  }
  return s.stateHash();
}

}  // namespace

TEST(LiveParams, AChangeTakesEffectAndSettingItBackGivesTheSameBits) {
  const auto none = [](Solver&, int) {};
  const std::uint64_t base_explicit = run(60, none);
  EXPECT_EQ(run(60,
                [](Solver& s, int k) {
                  if (k == 20) s.setParams(s.params());
                }),
            base_explicit)
      << "setting the same parameters changes nothing";
  const std::uint64_t base_implicit = run(60, none, true);
  for (const ParamInfo& p : paramTable()) {
    // (the hair chain acts only on hair flung loose: test_hair_holds_scenarios.cpp)
    if (!p.live || std::string(p.name) == "threads" || std::string(p.name) == "shape_keeping" ||
        std::string(p.name) == "hair_chain")
      continue;
    // the implicit solve's knobs act only with the implicit springs on
    // (and a stiffer hair, which the explicit step could not take at this step)
    const bool implicit = (std::string(p.name).rfind("implicit_", 0) == 0 && p.kind != ParamInfo::Kind::Switch) ||
                          std::string(p.name) == "youngs_modulus";
    const std::uint64_t base = implicit ? base_implicit : base_explicit;
    const double v0 = p.get(SimParams{});
    // a change a user would make: ten times the default where the range
    // spans decades, half again elsewhere (or 0.37 where it is 0)
    const double factor = p.logarithmic ? 10.0 : 1.5;
    double v = p.kind == ParamInfo::Kind::Switch ? (v0 != 0.0 ? 0.0 : 1.0)
               : v0 != 0.0                       ? std::min(p.hi, std::round(factor * v0 * 1e6) / 1e6)
                                                 : std::clamp(0.37, p.lo, p.hi);
    if (p.kind == ParamInfo::Kind::Integer) v = std::max(p.lo, std::round(v + 1.0));
    // run() chooses the spring solve itself: flip it from the explicit base
    if (std::string(p.name) == "implicit_springs") v = 1.0;
    // a cap on the iterations acts only below what the solve needs
    if (std::string(p.name) == "implicit_iterations") v = p.lo;
    for (SimParams q = buildSolver(lhtest::sphereScene(50, "{}", R"({"type": "still"})", 6)).params();;) {
      p.set(q, v);  // towards lo until valid with this scene's step (rate * dt limits)
      if (validate(q).empty()) break;
      v = 0.5 * (v + p.lo);
    }
    const std::uint64_t changed = run(
        60,
        [&](Solver& s, int k) {
          if (k == 20) {
            SimParams q = s.params();
            p.set(q, v);
            s.setParams(q);
          }
        },
        implicit);
    EXPECT_NE(changed, base) << p.name << " changed live has no effect";
    const std::uint64_t restored = run(
        60,
        [&](Solver& s, int k) {
          if (k == 20) {
            SimParams q = s.params();
            const double was = p.get(q);
            p.set(q, v);
            s.setParams(q);
            p.set(q, was);
            s.setParams(q);
          }
        },
        implicit);
    EXPECT_EQ(restored, base) << p.name << " set and set back does not give the same bits";
  }
  // the thread count is live and changes no bits
  EXPECT_EQ(run(60,
                [](Solver& s, int k) {
                  if (k == 30) {
                    SimParams q = s.params();
                    q.threads = 1;
                    s.setParams(q);
                  }
                }),
            base_explicit);
}

TEST(LiveParams, ChangesThatNeedANewSolverAreRefusedByName) {
  Solver s = buildSolver(lhtest::sphereScene(300, "{}", R"({"type": "still"})", 4));
  const std::uint64_t before = s.stateHash();
  for (const ParamInfo& p : paramTable()) {
    if (p.live) continue;
    SimParams q = s.params();
    p.set(q, p.get(q) == p.lo ? p.hi : p.lo);
    if (std::string(p.name) == "h2") q.h2 = q.h1 * 0.5f;
    try {
      s.setParams(q);
      ADD_FAILURE() << p.name << " changed in a running solver";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(p.name), std::string::npos) << e.what();
    }
  }
  SimParams bad = s.params();
  bad.youngs_modulus = -1.0f;
  EXPECT_THROW(s.setParams(bad), std::invalid_argument);
  bad = s.params();
  bad.shape_keeping = 2.0f;  // off to on needs the styled rest state
  EXPECT_THROW(s.setParams(bad), std::invalid_argument);
  EXPECT_EQ(s.stateHash(), before);
  EXPECT_EQ(s.params().youngs_modulus, SimParams{}.youngs_modulus) << "a refused change left nothing behind";
}

// The explicit springs are stable only below their limit: switching to
// them (or stiffening them) live at a longer step is refused, by name, and
// changes nothing.
TEST(LiveParams, ExplicitSpringsBeyondTheirStableStepAreRefused) {
  const char* stiff = R"({"youngs_modulus": 50000})";
  Solver s = buildSolver(lhtest::sphereScene(600, stiff, R"({"type": "still"})", 3));
  ASSERT_TRUE(s.params().implicit_springs);
  ASSERT_GT(s.params().time_step, s.initReport().stable_time_step) << "3 steps a frame are beyond the explicit limit";
  s.advance(3);
  const std::uint64_t before = s.stateHash();
  SimParams q = s.params();
  q.implicit_springs = false;
  try {
    s.setParams(q);
    ADD_FAILURE() << "explicit springs accepted at " << q.time_step << " s";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("implicit_springs"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(s.params().implicit_springs);
  EXPECT_EQ(s.stateHash(), before);
  // within the limit it is accepted
  Solver fine = buildSolver(lhtest::sphereScene(600, stiff, R"({"type": "still"})", 40));
  q = fine.params();
  q.implicit_springs = false;
  ASSERT_LT(q.time_step, fine.initReport().stable_time_step);
  EXPECT_NO_THROW(fine.setParams(q));
}

TEST(LiveParams, ShapeKeepingTurnedOffLiveIsPlainLcpFromThen) {
  auto build = [](const char* solver) {
    return buildSolver(lhtest::sphereScene(400, solver, R"({"type": "still"})", 4));
  };
  Solver plain = build(R"({"shape_keeping": 0})");
  Solver off = build(R"({"shape_keeping": 2.0})");
  Solver held = build(R"({"shape_keeping": 2.0})");
  Solver weaker = build(R"({"shape_keeping": 2.0})");
  SimParams p = off.params();
  p.shape_keeping = 0.0f;
  off.setParams(p);  // before the first step: exactly the plain solver
  p.shape_keeping = 1.0f;
  weaker.setParams(p);
  for (Solver* s : {&plain, &off, &held, &weaker}) s->advance(200);
  EXPECT_EQ(off.stateHash(), plain.stateHash()) << "off is plain LCP";
  EXPECT_NE(held.stateHash(), plain.stateHash()) << "the hold acts";
  EXPECT_NE(weaker.stateHash(), held.stateHash()) << "a new strength acts";
  EXPECT_THROW(off.setParams(weaker.params()), std::invalid_argument) << "turned back on live";
}

// The parameter reference users read (data/scenes/README.md) is the table
// itself, between its markers.
TEST(ParamTable, TheSceneReferenceIsTheTable) {
  const std::string path = lhtest::sourceDir() + "/data/scenes/README.md";
  std::string text = readRegularFile(path, kMaxTextFileBytes);
  const std::string begin = "<!-- solver parameters: begin -->\n", end = "<!-- solver parameters: end -->";
  const std::size_t a = text.find(begin), b = text.find(end);
  ASSERT_NE(a, std::string::npos) << path;
  ASSERT_NE(b, std::string::npos) << path;
  const std::string now = text.substr(a + begin.size(), b - a - begin.size());
  if (std::getenv("LOOSEHAIR_UPDATE_GOLDEN")) {
    text.replace(a + begin.size(), b - a - begin.size(), paramReferenceMarkdown());
    writeFileAtomically(path, {text});
    GTEST_SKIP() << "reference renewed: " << path;
  }
  EXPECT_EQ(now, paramReferenceMarkdown()) << path << " is not the table; renew it (see the file)";
}

// One range: what the table allows, validate() and the scene file take, and
// what it refuses they refuse, naming the parameter.
TEST(ParamTable, ValidateAndTheSceneFileKeepTheTablesRange) {
  for (const ParamInfo& p : paramTable()) {
    if (p.kind == ParamInfo::Kind::Switch) continue;
    const double below =
        p.lo_open ? p.lo : p.lo - (p.kind == ParamInfo::Kind::Integer ? 1.0 : 1e-3 * (1.0 + std::abs(p.lo)));
    const double above = p.hi + (p.kind == ParamInfo::Kind::Integer ? 1.0 : 1e-3 * (1.0 + std::abs(p.hi)));
    for (double bad : {below, above}) {
      EXPECT_FALSE(p.check(bad).empty()) << p.name << " " << bad;
      SimParams q;
      q.time_step = 1e-3;
      p.set(q, bad);
      const auto problems = validate(q);
      ASSERT_FALSE(problems.empty()) << p.name << " = " << bad << " passes validate()";
      EXPECT_NE(problems.front().find(p.name), std::string::npos) << problems.front();
      if (p.in_scene && std::string(p.name) != "h1" && std::string(p.name) != "h2") {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", bad);
        const std::string scene =
            std::string(R"({"head": {"type": "sphere", "center": [0, 0, 0], "radius": 0.1}, "solver": {")") + p.name +
            "\": " + value + "}}";
        try {
          (void)parseScene(scene, "range.json");
          ADD_FAILURE() << p.name << " = " << value << " read from a scene file";
        } catch (const SceneError& e) {
          EXPECT_NE(std::string(e.what()).find(std::string("solver.") + p.name), std::string::npos) << e.what();
        }
      }
    }
  }
}
