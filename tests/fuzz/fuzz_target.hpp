// The one function both fuzz drivers call (fuzz_readers.cpp, the
// deterministic one, and libfuzzer_entry.cpp).
#pragma once

#include <string>

namespace loosehair::fuzz {

enum class Kind { Scene, Mesh, Image };

/// Writes `bytes` to a file of this process's with `extension` and reads it
/// with the reader of `kind`; returns "read" or the error's message. Any
/// other outcome (a crash, a hang, an exception not derived from
/// std::exception) is a finding.
std::string readInput(Kind kind, const std::string& extension, const std::string& bytes);

}  // namespace loosehair::fuzz
