// A fuzz driver for the readers of user input: scene files, meshes (OBJ,
// PLY, OFF, STL, glTF, GLB) and images (hair-length maps). Every input must
// be read or refused with a std::exception: no crash, no hang, no
// unbounded allocation (run under AddressSanitizer in scripts/test.sh).
//
// Deterministic mutation mode (the test suite runs a short round):
//   loosehair_fuzz [--iterations N] [--seed S]
//                  [--kind scene|mesh|image|style|groom|snapshot|script|motion|all]
// Replaying inputs (the regression corpus, tests/fuzz/regressions/, whose
// file names end in the reader's extension):
//   loosehair_fuzz FILE...
// Coverage-guided with libFuzzer (clang; docs/testing.md):
//   cmake -S . -B build/fuzz -DCMAKE_CXX_COMPILER=clang++ -DLOOSEHAIR_LIBFUZZER=ON
//   cmake --build build/fuzz --target loosehair_libfuzzer
//   build/fuzz/tests/loosehair_libfuzzer -max_total_time=600 -max_len=65536
#include "fuzz_target.hpp"

#include "util/random.hpp"
#include "loosehair/loosehair.hpp"
#include "loosehair/strand_files.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using loosehair::fuzz::Kind;

struct Seed {
  Kind kind;
  std::string extension;
  std::string bytes;
};

std::string readAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A small closed mesh in every format, and images of both PGM kinds.
std::vector<Seed> builtinSeeds() {
  const char* obj =
      "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  const char* off =
      "OFF\n8 6 0\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const char* ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  std::string binary_ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  binary_ply.append(reinterpret_cast<const char*>(v), sizeof v);
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : f) {
    binary_ply.push_back(3);
    binary_ply.append(reinterpret_cast<const char*>(t), sizeof t);
  }
  const char* stl =
      "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\n"
      "endfacet\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\n"
      "endfacet\nfacet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\n"
      "endfacet\nfacet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\n"
      "endfacet\nendsolid t\n";
  // a glTF triangle with its buffer inline (base64 of 3 float3 positions)
  const char* gltf =
      R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"children":[1]},{"mesh":0,"translation":[0,0,1]}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
      R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  std::string p5 = "P5\n4 2\n255\n";
  for (int k = 0; k < 8; ++k) p5.push_back(static_cast<char>(k * 30));
  return {{Kind::Mesh, ".obj", obj},
          {Kind::Mesh, ".off", off},
          {Kind::Mesh, ".ply", ply},
          {Kind::Mesh, ".ply", binary_ply},
          {Kind::Mesh, ".stl", stl},
          {Kind::Mesh, ".gltf", gltf},
          {Kind::Image, ".pgm", "P2\n# c\n3 2\n15\n0 5 10\n15 3 7\n"},
          {Kind::Image, ".pgm", p5}};
}

std::vector<Seed> fileSeeds() {
  std::vector<Seed> seeds;
  const std::string src = LOOSEHAIR_SOURCE_DIR;
  for (const char* dir : {"/data/scenes", "/tests/data"})
    for (const auto& e : std::filesystem::directory_iterator(src + dir))
      if (e.path().extension() == ".json") seeds.push_back({Kind::Scene, ".json", readAll(e.path())});
  seeds.push_back({Kind::Image, ".png", readAll(src + "/data/maps/hair_length.png")});
  for (const auto& e : std::filesystem::directory_iterator(src + "/data/styles"))
    if (e.path().extension() == ".json") seeds.push_back({Kind::Style, ".style.json", readAll(e.path())});
  for (const auto& e : std::filesystem::directory_iterator(src + "/tests/viewer"))
    if (e.path().extension() == ".json") seeds.push_back({Kind::Script, ".script.json", readAll(e.path())});
  seeds.push_back({Kind::Motion, ".motion.json",
                   R"({"motion": {"type": "keyframes", "keys": [{"time": 0, "euler_deg": [0, 0, 0]},)"
                   R"( {"time": 0.5, "euler_deg": [30, 5, 0], "translation": [0, 0.01, 0]}]}})"});
  // grooms: two strands rooted on a sphere of radius 0.1, in each format
  loosehair::Polylines groom;
  groom.points = {{0, 0.1f, 0}, {0, 0.15f, 0.01f},  {0.02f, 0.2f, 0.02f},
                  {0.1f, 0, 0}, {0.15f, -0.02f, 0}, {0.2f, -0.1f, 0}};
  groom.first = {0, 3, 6};
  for (const auto& [ext, format] : {std::pair{".hair", "g.hair"}, {".groom.ply", "g.ply"}, {".groom.obj", "g.obj"}})
    seeds.push_back({Kind::Groom, ext, loosehair::polylineFileBytes(groom, format)});
  // snapshots of the tiny scenes, without air, with a grid, with particles
  for (int k = 0; k < 3; ++k) {
    loosehair::SceneDesc scene =
        loosehair::loadScene(src + (k ? "/tests/data/tiny-wind.json" : "/tests/data/tiny.json"));
    if (k == 2) scene.wind.model = loosehair::AirModel::Particles;
    loosehair::Solver solver = loosehair::buildSolver(scene);
    solver.advance(2);
    seeds.push_back({Kind::Snapshot, ".state", loosehair::encodeSnapshot(solver)});
  }
  return seeds;
}

// One mutation of `s`, chosen by `rng`.
void mutate(std::string& s, loosehair::Random& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng.next() % n); };
  static const char* const kTokens[] = {"1e400",
                                        "-1",
                                        "0",
                                        "nan",
                                        "1e-300",
                                        "-0",
                                        "99999999999999999999",
                                        "2147483648",
                                        "-2147483649",
                                        "4294967296",
                                        "\"",
                                        "[",
                                        "{",
                                        "}",
                                        "]",
                                        ",",
                                        ":",
                                        "null",
                                        "true",
                                        "\n",
                                        "#",
                                        "/",
                                        "//",
                                        "-",
                                        "e",
                                        "\"\\u0000\"",
                                        "element vertex 9999",
                                        "f 1 2 99",
                                        "v nan 0 0"};
  switch (pick(8)) {
    case 0:  // flip a bit
      if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << pick(8));
      break;
    case 1:  // an interesting byte
      if (!s.empty()) s[pick(s.size())] = "\0\xff\x7f\x80 09-.e\n"[pick(11)];
      break;
    case 2:  // a token inserted
      s.insert(pick(s.size() + 1), kTokens[pick(std::size(kTokens))]);
      break;
    case 3: {  // a number replaced by a token
      const std::size_t at = pick(s.size() + 1);
      std::size_t b = at;
      while (b < s.size() && !std::isdigit(static_cast<unsigned char>(s[b]))) ++b;
      std::size_t e = b;
      while (e < s.size() && (std::isdigit(static_cast<unsigned char>(s[e])) || s[e] == '.')) ++e;
      s.replace(std::min(b, s.size()), e - std::min(b, s.size()), kTokens[pick(std::size(kTokens))]);
      break;
    }
    case 4: {  // a range deleted
      const std::size_t at = pick(s.size() + 1), len = pick(std::min<std::size_t>(64, s.size() - at) + 1);
      s.erase(at, len);
      break;
    }
    case 5: {  // a range repeated
      const std::size_t at = pick(s.size() + 1), len = pick(std::min<std::size_t>(256, s.size() - at) + 1);
      const std::string part = s.substr(at, len);
      for (std::size_t k = pick(4) + 1; k > 0; --k) s.insert(at, part);
      break;
    }
    case 6:  // truncated
      s.resize(pick(s.size() + 1));
      break;
    default:  // random bytes
      for (std::size_t k = pick(8) + 1; k > 0; --k) s.insert(pick(s.size() + 1), 1, static_cast<char>(rng.next()));
      break;
  }
  if (s.size() > (1u << 20)) s.resize(1u << 20);
}

const char* kindName(Kind k) {
  switch (k) {
    case Kind::Scene:
      return "scene";
    case Kind::Mesh:
      return "mesh";
    case Kind::Image:
      return "image";
    case Kind::Style:
      return "style";
    case Kind::Groom:
      return "groom";
    case Kind::Snapshot:
      return "snapshot";
    case Kind::Script:
      return "script";
    case Kind::Motion:
      return "motion";
  }
  return "";
}

int usage() {
  std::fputs(
      "usage: loosehair_fuzz [--iterations N] [--seed S]\n"
      "                      [--kind scene|mesh|image|style|groom|snapshot|script|motion|all] [FILE...]\n",
      stderr);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  long iterations = 1000;
  std::uint64_t seed = 1;
  std::string kind = "all";
  std::vector<std::string> files;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if ((a == "--iterations" || a == "--seed" || a == "--kind") && k + 1 < argc) {
      const std::string v = argv[++k];
      if (a == "--iterations")
        iterations = std::stol(v);
      else if (a == "--seed")
        seed = std::stoull(v);
      else
        kind = v;
    } else if (!a.empty() && a[0] == '-') {
      return usage();
    } else {
      files.push_back(a);
    }
  }
  if (!files.empty()) {  // replay
    for (const std::string& f : files) {
      const std::filesystem::path p(f);
      const std::string ext = p.extension().string();
      const Kind k = loosehair::fuzz::kindOfFile(p.filename().string());
      const std::string bytes = readAll(p);
      const std::string outcome = loosehair::fuzz::readInput(k, ext, bytes);
      std::printf("%s: %s\n", f.c_str(), outcome.c_str());
    }
    return 0;
  }
  std::vector<Seed> seeds = builtinSeeds();
  for (Seed& s : fileSeeds()) seeds.push_back(std::move(s));
  std::vector<Seed> chosen;
  for (Seed& s : seeds)
    if (kind == "all" || kind == kindName(s.kind)) chosen.push_back(s);
  if (chosen.empty()) return usage();
  loosehair::Random rng(seed);
  long refused = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long it = 0; it < iterations; ++it) {
    const Seed& s = chosen[static_cast<std::size_t>(rng.next() % chosen.size())];
    std::string input = s.bytes;
    for (std::uint64_t m = rng.next() % 4 + 1; m > 0; --m) mutate(input, rng);
    if (std::getenv("LOOSEHAIR_FUZZ_TRACE")) {  // which input is running, for a hang
      std::ofstream("fuzz-current" + s.extension, std::ios::binary) << input;
      std::fprintf(stderr, "input %ld%s\n", it, s.extension.c_str());
    }
    const auto t_in = std::chrono::steady_clock::now();
    const std::string outcome = loosehair::fuzz::readInput(s.kind, s.extension, input);
    refused += outcome == "read" ? 0 : 1;
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_in).count();
    if (took > 2.0) {  // slow inputs are findings too: kept for replaying
      const std::string keep = "slow-input-" + std::to_string(it) + s.extension;
      std::ofstream(keep, std::ios::binary) << input;
      std::printf("input %ld took %.1f s (kept as %s): %s\n", it, took, keep.c_str(), outcome.substr(0, 200).c_str());
      std::fflush(stdout);
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%ld inputs (%ld refused with an error, %ld read) in %.1f s, seed %llu: no crash\n", iterations, refused,
              iterations - refused, seconds, static_cast<unsigned long long>(seed));
  return 0;
}
