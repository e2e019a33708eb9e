#include "loosehair/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <random>

namespace loosehair {
namespace {

std::string reason(int err) { return std::strerror(err); }

const char* kindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Opens `path` for reading without blocking on a FIFO, and checks that it is
// a regular file within `limit`; returns the descriptor and the size.
int openRegular(const std::string& path, std::size_t limit, std::size_t& size) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw FileError(path + ": cannot open: " + reason(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::close(fd);
    throw FileError(path + ": cannot read: " + reason(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw FileError(path + ": is " + std::string(kindOf(st.st_mode)) + ", not a file to read");
  }
  if (st.st_size < 0 || static_cast<std::uint64_t>(st.st_size) > limit) {
    ::close(fd);
    throw FileError(path + ": is " + std::to_string(st.st_size) + " bytes, more than the limit of " +
                    std::to_string(limit) + " bytes for this kind of file");
  }
  size = static_cast<std::size_t>(st.st_size);
  return fd;
}

}  // namespace

std::size_t checkRegularFile(const std::string& path, std::size_t limit) {
  std::size_t size = 0;
  ::close(openRegular(path, limit, size));
  return size;
}

std::string readRegularFile(const std::string& path, std::size_t limit) {
  std::size_t size = 0;
  const int fd = openRegular(path, limit, size);
  std::string out;
  out.resize(size);
  std::size_t got = 0;
  // A file that grows while it is read is cut at the size it had (and at
  // the limit): read until the end, never past `limit`.
  while (got < out.size()) {
    const ssize_t r = ::read(fd, out.data() + got, out.size() - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      const int err = errno;
      ::close(fd);
      throw FileError(path + ": cannot read: " + reason(err));
    }
    if (r == 0) break;
    got += static_cast<std::size_t>(r);
  }
  ::close(fd);
  out.resize(got);
  return out;
}

// ---- temporaries removed on a signal ------------------------------------------
// A fixed table, so that the signal handler touches no allocator: a slot is
// claimed (kClaiming), filled, then published (kLive); the handler unlinks
// the live ones. unlink and raise are async-signal-safe.
namespace {

constexpr int kSlots = 64;
constexpr std::size_t kSlotPath = 4096;
enum : int { kFree = 0, kClaiming = 1, kLive = 2 };
std::atomic<int> g_slot_state[kSlots];
char g_slot_path[kSlots][kSlotPath];

int registerTemporary(const std::string& path) {
  if (path.size() >= kSlotPath) return -1;  // not removed on a signal; written all the same
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slot_state[i].compare_exchange_strong(expected, kClaiming)) continue;
    std::memcpy(g_slot_path[i], path.c_str(), path.size() + 1);
    g_slot_state[i].store(kLive);
    return i;
  }
  return -1;
}

void unregisterTemporary(int slot) {
  if (slot >= 0) g_slot_state[slot].store(kFree);
}

extern "C" void removeTemporariesAndDie(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (g_slot_state[i].load() == kLive) ::unlink(g_slot_path[i]);
  // SA_RESETHAND restored the default action: end as the signal would have.
  ::raise(sig);
}

std::atomic<bool> g_handlers_installed{false};

}  // namespace

void removeTemporariesOnSignal() {
  if (g_handlers_installed.exchange(true)) return;
  struct sigaction sa {};
  sa.sa_handler = removeTemporariesAndDie;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // a signal the caller ignores (nohup's SIGHUP) stays ignored
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &sa, nullptr);
  }
}

TemporaryFileGuard::TemporaryFileGuard(const std::string& path) : slot_(registerTemporary(path)) {}
TemporaryFileGuard::~TemporaryFileGuard() { unregisterTemporary(slot_); }

// ---- output targets and atomic writes ---------------------------------------

std::string checkOutputTarget(const std::string& path) {
  if (path.empty()) throw FileError("an output file needs a name (got an empty one)");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return path;  // a new file
    throw FileError(path + ": cannot write: " + reason(errno));
  }
  std::string target = path;
  if (S_ISLNK(st.st_mode)) {
    char* resolved = ::realpath(path.c_str(), nullptr);
    if (!resolved) throw FileError(path + ": is a symbolic link that leads nowhere (" + reason(errno) + ")");
    target = resolved;
    std::free(resolved);
    if (::stat(target.c_str(), &st) != 0) throw FileError(path + ": cannot write: " + reason(errno));
  }
  if (!S_ISREG(st.st_mode))
    throw FileError(path + ": is " + std::string(kindOf(st.st_mode)) +
                    ", not a file to write; nothing was written (choose a file name)");
  return target;
}

AtomicFile::AtomicFile(const std::string& path, const std::string& suffix)
    : path_(path), target_(checkOutputTarget(path)) {
  // A name of this process's own beside the target (same file system, so the
  // rename is atomic).
  std::random_device rd;
  tmp_ = target_ + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(rd()) + suffix;
  slot_ = registerTemporary(tmp_);
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    const int err = errno;
    unregisterTemporary(slot_);
    slot_ = -1;
    throw FileError(path_ + ": cannot write: " + reason(err));
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !tmp_.empty()) ::unlink(tmp_.c_str());
  unregisterTemporary(slot_);
}

void AtomicFile::fail(const std::string& what, int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(tmp_.c_str());
  unregisterTemporary(slot_);
  slot_ = -1;
  tmp_.clear();
  throw FileError(path_ + ": " + what + ": " + reason(err));
}

void AtomicFile::write(std::string_view bytes) {
  if (fd_ < 0) throw FileError(path_ + ": write after the file was finished");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) fail("write failed", w < 0 ? errno : EIO);
    done += static_cast<std::size_t>(w);
  }
}

void AtomicFile::finish() {
  if (fd_ < 0) return;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("write failed", errno);
}

void AtomicFile::commit() {
  if (committed_) return;
  if (tmp_.empty()) throw FileError(path_ + ": the write failed earlier; nothing to commit");
  finish();
  // The target may have been replaced by a device or a directory meanwhile.
  struct stat st {};
  if (::lstat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    fail("is " + std::string(kindOf(st.st_mode)) + " now, not a file to write", EEXIST);
  if (::rename(tmp_.c_str(), target_.c_str()) != 0) fail("cannot rename the finished file", errno);
  committed_ = true;
  unregisterTemporary(slot_);
  slot_ = -1;
}

void writeFileAtomically(const std::string& path, const std::vector<std::string_view>& parts) {
  AtomicFile file(path);
  for (std::string_view part : parts) file.write(part);
  file.commit();
}

}  // namespace loosehair
