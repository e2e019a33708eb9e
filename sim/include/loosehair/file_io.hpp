// Reading input files and writing output files safely (the project's rules
// for files: inputs are regular files of bounded size, read whole; outputs
// are written whole or not at all, every write, close and rename checked).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace loosehair {

/// An input or output file that cannot be read or written; what() names the
/// file and says why.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The whole content of the regular file `path`, at most `limit` bytes.
/// Refuses (FileError, naming `path`) what is missing, unreadable (with the
/// system's reason, e.g. "Permission denied"), a directory, a FIFO, a device
/// or another non-regular file, and a file larger than `limit`. Never
/// blocks on a FIFO and never reads past `limit`.
std::string readRegularFile(const std::string& path, std::size_t limit);

/// Checks that `path` is a readable regular file of at most `limit` bytes
/// (as readRegularFile, without reading it), for readers that open the file
/// themselves; returns its size.
std::size_t checkRegularFile(const std::string& path, std::size_t limit);

/// Writes `parts` one after the other to `path`, atomically: into a
/// temporary file beside it, renamed over `path` once every write and the
/// close have succeeded. On any failure (a full disk, say) the temporary file
/// is removed, `path` is left as it was and FileError is thrown.
void writeFileAtomically(const std::string& path, const std::vector<std::string_view>& parts);

/// The default size limits of inputs (scene and style files, meshes, images,
/// snapshots).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;     // 64 MiB
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{1} << 30;      // 1 GiB
inline constexpr std::size_t kMaxImageFileBytes = std::size_t{256} << 20;   // 256 MiB
inline constexpr std::size_t kMaxSnapshotFileBytes = std::size_t{4} << 30;  // 4 GiB

}  // namespace loosehair
