// `loosehair style`: build a style's member strands and export them, or
// import a groom from another tool as a style (method.md §6.2).
#pragma once

#include <string>
#include <vector>

namespace loosehair::app {

extern const char* const kStyleUsage;

/// Runs `loosehair style ARGS...`; throws UsageError or an exception whose
/// what() names the file, field and value.
int styleCommand(const std::vector<std::string>& args);

}  // namespace loosehair::app
