// Starting other programs (ffmpeg) without a shell: an argument vector,
// never a command line built from user input.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace loosehair::app {

/// The full path of `program` found on PATH (as a shell would look it up,
/// without one), or nothing.
std::optional<std::string> findProgram(const std::string& program);

struct ProgramResult {
  int status = -1;           // the exit status, -1 if killed by a signal
  std::string error_output;  // what it wrote to its standard error
};

/// Runs `argv` (argv[0] a full path) and waits for it; its standard input is
/// /dev/null, its standard error is collected. Throws std::runtime_error if
/// it cannot be started.
ProgramResult runProgram(const std::vector<std::string>& argv);

}  // namespace loosehair::app
