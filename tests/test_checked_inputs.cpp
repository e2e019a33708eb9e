// The inputs added after the first hardening round, tried as hostile input:
// values typed into the viewer or set by scripts (checked as the scene and
// style files check them), groom files whose headers promise more than they
// hold, imports that must write what loads, and crafted snapshots (every
// field checked against what the scene allows).
#include "style_fixtures.hpp"
#include "test_support.hpp"

#include "loosehair/groom_import.hpp"
#include "loosehair/style_editor.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace loosehair;
using namespace lhtest::styles;

namespace {

template <class Error, class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The error names the source, the field and the value as given.
void expectSceneValueRefused(const std::string& field, double value, const std::string& shows) {
  const std::string m = errorOf<SceneError>([&] { (void)checkSceneValue(field, value, "events[3]"); });
  ASSERT_FALSE(m.empty()) << field << " = " << value << " was accepted";
  EXPECT_NE(m.find("events[3]"), std::string::npos) << m;
  const std::string leaf = field.substr(field.find('.') == std::string::npos ? 0 : field.find('.') + 1);
  EXPECT_NE(m.find(leaf), std::string::npos) << m;
  EXPECT_NE(m.find(shows), std::string::npos) << m;
}

}  // namespace

TEST(CheckedValues, ViewerValuesAreCheckedAsSceneFilesCheckThem) {
  // the issue's cases: each refused, naming the field and the value
  expectSceneValueRefused("seed", -1, "-1");
  expectSceneValueRefused("seed", 1e30, "1e+30");
  expectSceneValueRefused("seed", 1.5, "1.5");
  expectSceneValueRefused("hair.particles", 1e30, "1e+30");
  expectSceneValueRefused("hair.particles", -5, "-5");
  expectSceneValueRefused("solver.implicit_iterations", 1e12, "1000000000000");
  expectSceneValueRefused("solver.h1", 1e30, "1e+30");
  expectSceneValueRefused("solver.youngs_modulus", 1e30, "1e+30");
  expectSceneValueRefused("motion.amplitude_deg", 1e30, "1e+30");
  expectSceneValueRefused("wind.speed", -1, "-1");
  expectSceneValueRefused("solver.youngs_modulus", std::nan(""), "finite");
  expectSceneValueRefused("solver.no_such_parameter", 1, "no_such_parameter");
  // good values come back as the scene holds them
  EXPECT_EQ(checkSceneValue("seed", 42, "x"), 42.0);
  EXPECT_EQ(checkSceneValue("hair.particles", 5000, "x"), 5000.0);
  EXPECT_EQ(checkSceneValue("solver.youngs_modulus", 4000, "x"), 4000.0);
  EXPECT_EQ(checkSceneValue("solver.implicit_iterations", 30, "x"), 30.0);
  EXPECT_EQ(checkSceneValue("motion.frequency_hz", 2, "x"), 2.0);
}

TEST(CheckedValues, WispValuesAreCheckedAsStyleFilesCheckThem) {
  for (const auto& [field, value] : std::vector<std::pair<std::string, double>>{
           {"offset_radius", 1e30}, {"length_variation", 5}, {"density", -1}, {"density", INFINITY}}) {
    const std::string m = errorOf<StyleError>([&] { (void)checkWispValue(field, value, "the panel"); });
    EXPECT_NE(m.find("the panel"), std::string::npos) << field << ": " << m;
    EXPECT_NE(m.find(field), std::string::npos) << m;
  }
  EXPECT_FLOAT_EQ(static_cast<float>(checkWispValue("offset_radius", 0.01, "x")), 0.01f);
  // the editor takes nothing a file would refuse: a new wisp's parameters,
  // and a control point moved a huge step
  StyleEditor editor(twoWispStyle(), sphereModel());
  WispParams wild;
  wild.offset_radius = 1e30f;
  const std::size_t before = editor.style().wisps.size();
  EXPECT_THROW(editor.createWisp(square({0.4f, 0.4f}, {0.45f, 0.45f}), wild), StyleError);
  EXPECT_EQ(editor.style().wisps.size(), before);
  const Style kept = editor.style();
  EXPECT_THROW(editor.moveControlPoint(0, 1, StylingAxis::Normal, 1e27f), StyleError);
  EXPECT_TRUE(editor.style() == kept);
}

TEST(CheckedValues, AHairLengthAFloatCannotHoldIsRefusedAtItsField) {
  const std::string base = R"({"head": {"type": "sphere", "center": [0, 0, 0], "radius": 0.1},
                               "hair": {"particles": 300, "length": LEN}})";
  for (const char* len : {"1e-300", "1e-30", "0.001"}) {
    std::string text = base;
    text.replace(text.find("LEN"), 3, len);
    const std::string m = errorOf<SceneError>([&] { (void)parseScene(text, "short.json"); });
    EXPECT_NE(m.find("short.json: hair.length"), std::string::npos) << len << ": " << m;
  }
}

TEST(CheckedValues, AStyleOrAMeshGivenAsASceneSaysWhatItIs) {
  const std::string style = lhtest::sourceDir() + "/data/styles/bob.json";
  std::string m = errorOf<SceneError>([&] { (void)loadScene(style); });
  EXPECT_NE(m.find("is a style file"), std::string::npos) << m;
  EXPECT_NE(m.find("--style"), std::string::npos) << m;
  m = errorOf<SceneError>([&] { (void)loadScene(lhtest::sourceDir() + "/data/meshes/head.ply"); });
  EXPECT_NE(m.find("is a mesh, not a scene"), std::string::npos) << m;
  m = errorOf<SceneError>([&] { (void)parseScene("ply\nformat binary_little_endian 1.0\n", "x.json"); });
  EXPECT_NE(m.find("x.json: is not a JSON file"), std::string::npos) << m;
  EXPECT_EQ(m.find("json.exception"), std::string::npos) << m;
  m = errorOf<SceneError>([&] { (void)parseScene("{\n  \"frames\": 3,\n  \"seed\": }", "y.json"); });
  EXPECT_NE(m.find("y.json: invalid JSON at line 3"), std::string::npos) << m;
  EXPECT_EQ(m.find("json.exception"), std::string::npos) << m;
}

// ---- groom files --------------------------------------------------------------

namespace {

std::filesystem::path groomDir() {
  const auto d = std::filesystem::temp_directory_path() / ("loosehair-grooms-" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

std::string writeFile(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

}  // namespace

TEST(GroomFiles, HeadersThatPromiseMoreThanTheFileHoldsAreRefusedAtOnce) {
  const auto dir = groomDir();
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 500000000\nproperty float x\n"
      "property float y\nproperty float z\nelement edge 400000000\nproperty int vertex1\n"
      "property int vertex2\nend_header\n";
  const std::string huge = writeFile(dir / "huge.ply", header + std::string(24, '\0'));
  const auto t0 = std::chrono::steady_clock::now();
  std::string m = errorOf<FileError>([&] { (void)readPolylines(huge); });
  // refused from the header, before gigabytes are allocated
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_NE(m.find("huge.ply: the header promises 500000000 vertices"), std::string::npos) << m;
  // ASCII too
  std::string ascii = header;
  ascii.replace(ascii.find("binary_little_endian"), 20, "ascii");
  m = errorOf<FileError>([&] { (void)readPolylines(writeFile(dir / "huge-ascii.ply", ascii + "0 0 0\n")); });
  EXPECT_NE(m.find("promises"), std::string::npos) << m;
  // a .hair header promising a million strands in 200 bytes
  std::string hair = "HAIR";
  auto put32 = [&](std::uint32_t v) { hair.append(reinterpret_cast<const char*>(&v), 4); };
  put32(1000000);
  put32(2000000);
  put32(0x3);
  put32(1);
  hair.resize(200, '\0');
  m = errorOf<FileError>([&] { (void)readPolylines(writeFile(dir / "huge.hair", hair)); });
  EXPECT_NE(m.find("huge.hair: the header promises 1000000 strands"), std::string::npos) << m;
  std::filesystem::remove_all(dir);
}

TEST(GroomFiles, APlyHeaderWithoutItsNewlineIsNotReadFromByteZero) {
  const auto dir = groomDir();
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header";
  std::string m = errorOf<FileError>([&] { (void)readPolylines(writeFile(dir / "nonewline.ply", text)); });
  EXPECT_NE(m.find("nonewline.ply: the header's last line must be \"end_header\" followed by a newline"),
            std::string::npos)
      << m;
  m = errorOf<FileError>([&] { (void)readPolylines(writeFile(dir / "glued.ply", text + "0 0 0 0 1 0 0 1")); });
  EXPECT_NE(m.find("followed by a newline"), std::string::npos) << m;
  // with it, the same file reads
  const Polylines ok = readPolylines(writeFile(dir / "ok.ply", text + "\n0 0 0\n0 1 0\n0 1\n"));
  EXPECT_EQ(ok.size(), 1u);
  std::filesystem::remove_all(dir);
}

TEST(GroomImport, WhatAnImportMakesLoadsAsAStyle) {
  const HeadModel& h = sphereModel();
  const StrandSet strands = buildMemberStrands(twoWispStyle(), h);
  Polylines groom;
  groom.points = strands.points;
  groom.first = strands.first;
  // a strand reaching 10 km out (another unit): left out, not written
  const glm::vec3 root = h.scalpPoint({0.5f, 0.5f});
  groom.points.push_back(root);
  groom.points.push_back(root + glm::vec3(0.0f, 0.0f, 1e4f));
  groom.first.push_back(static_cast<std::uint32_t>(groom.points.size()));
  // a short strand whose points crowd together: resampled and moved onto
  // the scalp they would repeat control points
  const glm::vec3 r2 = h.scalpPoint({0.3f, 0.6f}), n2 = h.scalpNormal({0.3f, 0.6f});
  for (int k = 0; k < 8; ++k) groom.points.push_back(r2 + (2e-6f * static_cast<float>(k)) * n2);
  groom.points.push_back(r2 + 0.05f * n2);
  groom.first.push_back(static_cast<std::uint32_t>(groom.points.size()));
  GroomImportReport rep;
  const Style s = importGroom(groom, sphereHead(), h, "groom.ply", {}, &rep);
  EXPECT_EQ(rep.skipped_beyond, 1u);
  const std::string text = styleText(s, "");
  Style back;
  ASSERT_NO_THROW(back = parseStyle(text, "imported.json"));
  EXPECT_NO_THROW(checkStyle(back, h));
  for (const Wisp& w : back.wisps)
    for (std::size_t k = 1; k < w.key_strand.size(); ++k)
      EXPECT_GE(glm::length(w.key_strand[k] - w.key_strand[k - 1]), kMinControlPointGap) << w.name;
}
