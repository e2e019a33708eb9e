#include "cli_args.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace loosehair::app {

long long parseInteger(const std::string& flag, const std::string& value, long long lo, long long hi,
                       const char* usage) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw UsageError{flag + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                         value + "'",
                     usage};
  return v;
}

double parseReal(const std::string& flag, const std::string& value, double lo, double hi, const char* usage) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
    throw UsageError{flag + " needs a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                         value + "'",
                     usage};
  return v;
}

}  // namespace loosehair::app
