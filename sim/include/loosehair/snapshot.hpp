// Snapshots: the whole dynamic state of a running simulation in a file, so
// that a run can stop and go on later bit-identically (the state hash after
// N + M frames equals the uninterrupted run's).
//
// A snapshot holds what a step carries to the next (time, step count, time
// step, positions, velocities, directions, the sums the next step reuses,
// the air); what is built from the scene (particles' masses and roots,
// connections, bodies) is built again from it, so a snapshot is resumed on a
// solver built from the same scene and seed, and a fingerprint of that
// initial state (with the physical parameters) refuses any other.
//
// File format (version 1, little-endian): the 16-byte magic
// "loosehair-state\n", u32 version, u32 reserved (0), u64 scene
// fingerprint, u64 payload length, the payload, and a u64 FNV-1a checksum of
// everything before it. Written atomically (file_io.hpp).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace loosehair {

class Solver;

/// A snapshot that cannot be written, or is refused: what() names the file
/// and says why (not a snapshot, another version, damaged or truncated,
/// from another scene).
class SnapshotError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// 2: the wind's air may be a grid (issue 18).
inline constexpr std::uint32_t kSnapshotVersion = 2;

/// The snapshot of `solver` as bytes.
std::string encodeSnapshot(const Solver& solver);
/// Puts the state of `bytes` (named `name` in errors) into `solver`, which
/// must have been built from the same scene and seed and not have stepped
/// yet, or be the solver the snapshot came from. Leaves `solver` unchanged
/// if the snapshot is refused.
void decodeSnapshot(Solver& solver, std::string_view bytes, const std::string& name);

/// encodeSnapshot into the file `path`, written atomically.
void saveSnapshot(const Solver& solver, const std::string& path);
/// decodeSnapshot from the file `path`.
void loadSnapshot(Solver& solver, const std::string& path);

}  // namespace loosehair
