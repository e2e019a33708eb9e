#include "cli_args.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <algorithm>
#include <cctype>

namespace loosehair::app {

std::vector<std::string> splitFlagValues(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const std::string& a : args) {
    const std::size_t eq = a.find('=');
    if (a.rfind("--", 0) == 0 && eq != std::string::npos && eq > 2) {
      out.push_back(a.substr(0, eq));
      out.push_back(a.substr(eq + 1));
    } else {
      out.push_back(a);
    }
  }
  return out;
}

namespace {

// Edits (insertions, deletions, substitutions) between a and b.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

UsageError unknownOption(const std::string& given, const char* usage) {
  // the options the usage text names: "--" and letters, digits and '-'
  std::vector<std::string> known;
  const std::string text = usage ? usage : "";
  for (std::size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at + 2)) {
    std::size_t end = at + 2;
    while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '-')) ++end;
    if (end > at + 2) known.push_back(text.substr(at, end - at));
  }
  std::string best;
  std::size_t best_distance = 3;
  // an option the text names for another command ("render's --out") is
  // not this one's: nothing to suggest for it
  if (std::find(known.begin(), known.end(), given) != known.end())
    return UsageError{"unknown option " + given + " (not an option of this command)", usage};
  for (const std::string& k : known) {
    const std::size_t d = k.rfind(given, 0) == 0 && given.size() > 3 ? 1 : editDistance(given, k);
    if (d < best_distance) best = k, best_distance = d;
  }
  return UsageError{"unknown option " + given + (best.empty() ? "" : " (did you mean " + best + "?)"), usage};
}

long long parseInteger(const std::string& flag, const std::string& value, long long lo, long long hi,
                       const char* usage) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw UsageError{
        flag + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + value + "'",
        usage};
  return v;
}

double parseReal(const std::string& flag, const std::string& value, double lo, double hi, const char* usage) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
    throw UsageError{
        flag + " needs a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + value + "'",
        usage};
  return v;
}

}  // namespace loosehair::app
