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

/// The file an output to `path` goes to: `path` itself, or where a symbolic
/// link at `path` leads. Refuses (FileError, naming `path` and what it is)
/// a target that exists and is not a regular file (a device such as
/// /dev/null, a FIFO, a socket, a directory) and a link that leads nowhere,
/// before anything is written: renaming a finished file over a device node
/// would replace the node.
std::string checkOutputTarget(const std::string& path);

/// One output file written atomically: the bytes go to a temporary file
/// beside the target (registered for removal on SIGINT/SIGTERM/SIGHUP, see
/// removeTemporariesOnSignal), and commit() renames it over the target.
/// Destroyed uncommitted, the temporary is removed and the target is left as
/// it was. Several AtomicFiles finished first and committed together make a
/// change of several files all or nothing up to the renames.
class AtomicFile {
 public:
  /// Checks the target (checkOutputTarget) and creates the temporary file.
  /// `suffix` ends the temporary's name (".mp4", say, for a program that
  /// reads the format from the name).
  explicit AtomicFile(const std::string& path, const std::string& suffix = "");
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends `bytes`; FileError (the temporary removed) on failure.
  void write(std::string_view bytes);
  /// Closes the temporary, checked; after this another program may write it.
  void finish();
  /// Renames the finished temporary over the target.
  void commit();

  const std::string& target() const { return target_; }
  const std::string& temporary() const { return tmp_; }

 private:
  void fail(const std::string& what, int err);
  std::string path_, target_, tmp_;
  int fd_ = -1;
  int slot_ = -1;
  bool committed_ = false;
};

/// Installs handlers of SIGINT, SIGTERM and SIGHUP that remove the
/// temporary files of unfinished writes, then end the process as the signal
/// would have. For programs (the command line, the viewer); idempotent.
void removeTemporariesOnSignal();

/// Registers a temporary file that something else writes (a child program's
/// output) for removal on those signals, for the guard's lifetime.
class TemporaryFileGuard {
 public:
  explicit TemporaryFileGuard(const std::string& path);
  ~TemporaryFileGuard();
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

 private:
  int slot_ = -1;
};

/// The default size limits of inputs (scene and style files, meshes, images,
/// snapshots).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;     // 64 MiB
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{1} << 30;      // 1 GiB
inline constexpr std::size_t kMaxImageFileBytes = std::size_t{256} << 20;   // 256 MiB
inline constexpr std::size_t kMaxSnapshotFileBytes = std::size_t{4} << 30;  // 4 GiB

}  // namespace loosehair
