// The viewer's command line (loosehair-view --help): its options and their
// parsing.
#pragma once

#include "loosehair/render/renderer.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace loosehair::viewer {

/// The usage text (--help, and after a usage error).
extern const char* const kUsage;

struct UsageError {
  std::string message;
};

struct ViewOptions {
  std::string scene;
  int width = 960, height = 720;
  std::string camera = "three-quarter";
  render::RenderSettings settings;
  std::optional<int> threads;
  std::optional<std::uint64_t> seed;
  bool paused = false;
  std::optional<int> frames;
  std::string screenshot;
  std::string script;
  std::optional<double> seconds;
  bool allow_expensive = false;
  std::string strand_carry = "auto";
  bool hair_given = false;           // --hair
  std::optional<int> strand_budget;  // --playing-strands
};

// Strands drawn while the hair moves on software OpenGL (llvmpipe): about
// 4 frames a second with all 12,000 at 1280x720, 2 cores; see
// docs/performance.md.
constexpr int kSoftwareStrandBudget = 4000;

/// The options of the command line (`args` split by app::splitFlagValues);
/// throws UsageError.
ViewOptions parseOptions(const std::vector<std::string>& args);

}  // namespace loosehair::viewer
