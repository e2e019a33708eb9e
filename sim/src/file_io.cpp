#include "loosehair/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
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

void writeFileAtomically(const std::string& path, const std::vector<std::string_view>& parts) {
  // A name of this process's own beside the target (same file system, so the
  // rename is atomic).
  std::random_device rd;
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(rd());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw FileError(path + ": cannot write: " + reason(errno));
  auto fail = [&](const std::string& what, int err) {
    ::unlink(tmp.c_str());
    throw FileError(path + ": " + what + ": " + reason(err));
  };
  for (std::string_view part : parts) {
    std::size_t done = 0;
    while (done < part.size()) {
      const ssize_t w = ::write(fd, part.data() + done, part.size() - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        const int err = w < 0 ? errno : EIO;
        ::close(fd);
        fail("write failed", err);
      }
      done += static_cast<std::size_t>(w);
    }
  }
  if (::close(fd) != 0) fail("write failed", errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot rename the finished file", errno);
}

}  // namespace loosehair
