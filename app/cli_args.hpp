// Command-line argument helpers shared by the loosehair commands.
#pragma once

#include <string>
#include <vector>

namespace loosehair::app {

/// Bad usage: the message and the usage text of the command.
struct UsageError {
  std::string message;
  const char* usage = nullptr;  // null: the program's overall usage
};

/// The arguments with each "--flag=value" split into "--flag" "value".
std::vector<std::string> splitFlagValues(const std::vector<std::string>& args);

/// The "unknown option" error for `given`, suggesting the nearest option
/// that `usage` lists (within two edits, or one the given text begins).
UsageError unknownOption(const std::string& given, const char* usage);

/// An integer in [lo, hi] given for `flag`; UsageError otherwise.
long long parseInteger(const std::string& flag, const std::string& value, long long lo, long long hi,
                       const char* usage = nullptr);
/// A finite number in [lo, hi] given for `flag`; UsageError otherwise.
double parseReal(const std::string& flag, const std::string& value, double lo, double hi, const char* usage = nullptr);

}  // namespace loosehair::app
