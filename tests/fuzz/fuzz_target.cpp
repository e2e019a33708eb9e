#include "fuzz_target.hpp"

#include "init/length_map.hpp"
#include "loosehair/loosehair.hpp"

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <fstream>

namespace loosehair::fuzz {

std::string readInput(Kind kind, const std::string& extension, const std::string& bytes) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("loosehair-fuzz-" + std::to_string(::getpid()) + extension);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
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
