// Writes that respect what they replace (loosehair/file_io.hpp): a target
// that is a device, a FIFO, a socket or a directory is refused before
// anything is written (renaming over /dev/null as root replaced the device
// node with a file), a link is written through, and a signal during a write
// leaves no temporary file behind.
#include "loosehair/file_io.hpp"

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

using namespace loosehair;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const char* name) {
  const fs::path d =
      fs::temp_directory_path() / (std::string("loosehair-writes-") + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void expectRefused(const std::string& path, const char* says) {
  try {
    writeFileAtomically(path, {"data"});
    ADD_FAILURE() << "wrote to " << path;
  } catch (const FileError& e) {
    EXPECT_NE(std::strstr(e.what(), path.c_str()), nullptr) << e.what();
    EXPECT_NE(std::strstr(e.what(), says), nullptr) << e.what();
  }
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++n;
  }
  return n;
}

}  // namespace

TEST(FileWrites, ADeviceIsRefusedAndStaysADevice) {
  struct stat before {};
  ASSERT_EQ(::stat("/dev/null", &before), 0);
  expectRefused("/dev/null", "character device");
  struct stat after {};
  ASSERT_EQ(::lstat("/dev/null", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode)) << "/dev/null is no longer a device";
  EXPECT_EQ(after.st_rdev, before.st_rdev);
  // and the check itself, as the command line uses it before a run
  EXPECT_THROW(checkOutputTarget("/dev/full"), FileError);
}

TEST(FileWrites, FifosSocketsAndDirectoriesAreRefusedUntouched) {
  const fs::path d = freshDir("kinds");
  const std::string fifo = (d / "pipe").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectRefused(fifo, "FIFO");
  EXPECT_TRUE(fs::is_fifo(fifo));

  const std::string sock = (d / "sock").string();
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  ASSERT_LT(sock.size(), sizeof addr.sun_path);
  std::memcpy(addr.sun_path, sock.c_str(), sock.size() + 1);
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  expectRefused(sock, "socket");
  EXPECT_TRUE(fs::is_socket(sock));
  ::close(fd);

  fs::create_directories(d / "folder");
  expectRefused((d / "folder").string(), "directory");
  EXPECT_TRUE(fs::is_directory(d / "folder"));

  fs::create_symlink(d / "nowhere" / "x", d / "dangling");
  expectRefused((d / "dangling").string(), "leads nowhere");
  EXPECT_TRUE(fs::is_symlink(d / "dangling"));
  // nothing was left beside them: no temporary of a refused write
  EXPECT_EQ(entries(d), 4u);
  fs::remove_all(d);
}

TEST(FileWrites, ALinkIsWrittenThroughAndKept) {
  const fs::path d = freshDir("link");
  { std::ofstream(d / "real") << "old"; }
  fs::create_symlink("real", d / "link");
  writeFileAtomically((d / "link").string(), {"new ", "bytes"});
  EXPECT_TRUE(fs::is_symlink(d / "link"));
  EXPECT_EQ(read(d / "real"), "new bytes");
  EXPECT_EQ(entries(d), 2u);
  fs::remove_all(d);
}

TEST(FileWrites, SeveralFilesAreCommittedTogetherOrNotAtAll) {
  const fs::path d = freshDir("together");
  { std::ofstream(d / "a") << "old a"; }
  {
    AtomicFile a((d / "a").string());
    a.write("new a");
    AtomicFile b((d / "b").string());
    b.write("new b");
    // destroyed uncommitted (a later step failed): both as they were
  }
  EXPECT_EQ(read(d / "a"), "old a");
  EXPECT_FALSE(fs::exists(d / "b"));
  EXPECT_EQ(entries(d), 1u);
  {
    AtomicFile a((d / "a").string()), b((d / "b").string());
    a.write("new a");
    b.write("new b");
    a.finish();
    b.finish();
    a.commit();
    b.commit();
  }
  EXPECT_EQ(read(d / "a"), "new a");
  EXPECT_EQ(read(d / "b"), "new b");
  EXPECT_EQ(entries(d), 2u);
  fs::remove_all(d);
}

// The child process is a fresh run of this test binary (the "threadsafe"
// death-test style), so the solver's thread pools of other tests do not
// matter; it is killed by the signal in the middle of a write.
TEST(FileWritesDeathTest, ASignalDuringAWriteLeavesNoTemporary) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const fs::path d = freshDir(("signal" + std::to_string(sig)).c_str());
    const std::string target = (d / "frame.ply").string();
    EXPECT_EXIT(
        {
          removeTemporariesOnSignal();
          AtomicFile f(target);
          f.write("half a frame");
          TemporaryFileGuard other((d / "child-output.mp4").string());
          { std::ofstream((d / "child-output.mp4")) << "a child program's half video"; }
          std::raise(sig);
          std::_Exit(0);  // not reached
        },
        ::testing::KilledBySignal(sig), "");
    EXPECT_EQ(entries(d), 0u) << "signal " << sig << " left a temporary in " << d;
    fs::remove_all(d);
  }
}
