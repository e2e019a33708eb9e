// Checks of JSON input files before they are parsed into a tree (scenes,
// styles, motions, viewer scripts): at most kMaxJsonDepth levels of nesting
// (deeper input crashed the printing of error messages), no key twice in one object (the last one
// would silently win), and the syntax itself; each problem is reported with
// the file, the path of the field and, for syntax errors, the position.
#pragma once

#include <string>
#include <string_view>

namespace loosehair {

inline constexpr int kMaxJsonDepth = 64;

/// Throws `Error` (constructed from a message string) naming `source` on
/// the first problem.
void checkJson(std::string_view text, const std::string& source, void (*raise)(const std::string& message));

/// At most `limit` characters of `text` for an error message, with "..."
/// where it was cut.
std::string clipped(std::string_view text, std::size_t limit = 60);

}  // namespace loosehair
