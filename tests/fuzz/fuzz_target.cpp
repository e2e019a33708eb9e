#include "fuzz_target.hpp"

#include "init/length_map.hpp"
#include "loosehair/groom_import.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/strand_files.hpp"
#include "loosehair/style.hpp"
#include "loosehair/head_model.hpp"
#include "viewer/script.hpp"

#include <cstring>
#include <memory>

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <fstream>

namespace loosehair::fuzz {

Kind kindOfFile(const std::string& name) {
  auto ends = [&](const char* tail) {
    const std::size_t n = std::strlen(tail);
    return name.size() >= n && name.compare(name.size() - n, n, tail) == 0;
  };
  if (ends(".script.json")) return Kind::Script;
  if (ends(".motion.json")) return Kind::Motion;
  if (ends(".style.json")) return Kind::Style;
  if (ends(".json")) return Kind::Scene;
  if (ends(".state")) return Kind::Snapshot;
  if (ends(".hair") || ends(".groom.ply") || ends(".groom.obj")) return Kind::Groom;
  if (ends(".pgm") || ends(".png")) return Kind::Image;
  return Kind::Mesh;
}

namespace {

// Length and checksum made to agree with the bytes (the layout of
// snapshot.cpp: a 32-byte header, the payload's length, the payload, an
// FNV-1a 64 checksum of everything before it).
std::string withConsistentFraming(std::string b) {
  if (b.size() < 48) return b;
  const std::uint64_t length = b.size() - 48;
  std::memcpy(b.data() + 32, &length, 8);
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t k = 0; k + 8 < b.size(); ++k) h = (h ^ static_cast<unsigned char>(b[k])) * 0x100000001b3ULL;
  std::memcpy(b.data() + b.size() - 8, &h, 8);
  return b;
}

Solver& snapshotTarget(bool wind, bool particle_air) {
  static std::unique_ptr<Solver> solvers[3];
  const int k = wind ? (particle_air ? 2 : 1) : 0;
  if (!solvers[k]) {
    SceneDesc scene =
        loadScene(std::string(LOOSEHAIR_SOURCE_DIR) + (wind ? "/tests/data/tiny-wind.json" : "/tests/data/tiny.json"));
    if (particle_air) scene.wind.model = AirModel::Particles;
    solvers[k] = std::make_unique<Solver>(buildSolver(scene));
  }
  return *solvers[k];
}

}  // namespace

std::string readInput(Kind kind, const std::string& extension, const std::string& bytes) {
  const auto path =
      std::filesystem::temp_directory_path() / ("loosehair-fuzz-" + std::to_string(::getpid()) + extension);
  const std::string content = kind == Kind::Snapshot ? withConsistentFraming(bytes) : bytes;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  }
  std::string outcome = "read";
  try {
    switch (kind) {
      case Kind::Scene:
        (void)loadScene(path.string());
        break;
      case Kind::Mesh:
        (void)loadMesh(path.string());
        break;
      case Kind::Image:
        (void)LengthMap(path.string());
        break;
      case Kind::Style:
        (void)loadStyle(path.string());
        break;
      case Kind::Groom: {
        const Polylines lines = readPolylines(path.string());
        // and made a style on a sphere head, which must read back
        static const HeadDesc head = [] {
          HeadDesc h;
          h.head_kind = HeadKind::Sphere;
          h.head_radius = 0.1f;
          return h;
        }();
        static const HeadModel model = HeadModel::build(head, "fuzz-head");
        GroomImportOptions options;
        options.max_root_distance = 1.0f;
        const Style style = importGroom(lines, head, model, path.string(), options);
        (void)parseStyle(styleText(style), "fuzz-import");
        break;
      }
      case Kind::Snapshot: {
        // the air byte follows the hair; try the scene without air, then with
        bool done = false;
        std::string last;
        for (int target = 0; target < 3 && !done; ++target) {
          try {
            loadSnapshot(snapshotTarget(target > 0, target == 2), path.string());
            done = true;
          } catch (const SnapshotError& e) {
            last = e.what();
            if (last.find("another scene") == std::string::npos && last.find("wind") == std::string::npos &&
                last.find("air") == std::string::npos)
              throw;
          }
        }
        if (!done) throw SnapshotError(last);
        break;
      }
      case Kind::Script:
        (void)viewer::loadScript(path.string());
        break;
      case Kind::Motion:
        (void)loadMotion(path.string());
        break;
    }
  } catch (const std::exception& e) {
    outcome = e.what();
    if (outcome.empty()) outcome = "(an error without a message)";
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  return outcome;
}

}  // namespace loosehair::fuzz
