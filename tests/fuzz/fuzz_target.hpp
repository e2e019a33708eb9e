// The one function both fuzz drivers call (fuzz_readers.cpp, the
// deterministic one, and libfuzzer_entry.cpp).
#pragma once

#include <string>

namespace loosehair::fuzz {

enum class Kind { Scene, Mesh, Image, Style, Groom, Snapshot, Script, Motion };

/// The kind a file of this extension is read as when replayed (a snapshot
/// is ".state", a viewer script ".script.json", a motion ".motion.json").
Kind kindOfFile(const std::string& name);

/// Snapshots: the length field and the checksum are made to agree with
/// the (mutated) bytes first, so that mutations reach the field checks;
/// they are read into a solver of tests/data/tiny.json (or tiny-wind.json
/// when the snapshot holds air). Writes `bytes` to a file of this process's with `extension` and reads it
/// with the reader of `kind`; returns "read" or the error's message. Any
/// other outcome (a crash, a hang, an exception not derived from
/// std::exception) is a finding.
std::string readInput(Kind kind, const std::string& extension, const std::string& bytes);

}  // namespace loosehair::fuzz
