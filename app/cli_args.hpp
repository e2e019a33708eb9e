// Command-line argument helpers shared by the loosehair commands.
#pragma once

#include <string>

namespace loosehair::app {

/// Bad usage: the message and the usage text of the command.
struct UsageError {
  std::string message;
  const char* usage = nullptr;  // null: the program's overall usage
};

/// An integer in [lo, hi] given for `flag`; UsageError otherwise.
long long parseInteger(const std::string& flag, const std::string& value, long long lo, long long hi,
                       const char* usage = nullptr);
/// A finite number in [lo, hi] given for `flag`; UsageError otherwise.
double parseReal(const std::string& flag, const std::string& value, double lo, double hi,
                 const char* usage = nullptr);

}  // namespace loosehair::app
