// libFuzzer's entry point (clang -fsanitize=fuzzer): the first byte picks
// the reader and the extension, the rest is the file.
#include "fuzz_target.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using loosehair::fuzz::Kind;
  if (size == 0) return 0;
  static const struct {
    Kind kind;
    const char* ext;
  } kTargets[] = {{Kind::Scene, ".json"},        {Kind::Mesh, ".obj"},       {Kind::Mesh, ".ply"},
                  {Kind::Mesh, ".off"},          {Kind::Mesh, ".stl"},       {Kind::Mesh, ".gltf"},
                  {Kind::Mesh, ".glb"},          {Kind::Image, ".pgm"},      {Kind::Image, ".png"},
                  {Kind::Style, ".style.json"},  {Kind::Groom, ".hair"},     {Kind::Groom, ".groom.ply"},
                  {Kind::Groom, ".groom.obj"},   {Kind::Snapshot, ".state"}, {Kind::Script, ".script.json"},
                  {Kind::Motion, ".motion.json"}};
  const auto& t = kTargets[data[0] % (sizeof kTargets / sizeof kTargets[0])];
  (void)loosehair::fuzz::readInput(t.kind, t.ext, std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  return 0;
}
