#include "video.hpp"

#include "process.hpp"
#include "loosehair/file_io.hpp"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace loosehair::app {
namespace {

// ffmpeg's reading of a path: "file:" and an absolute path, which it takes
// as a local file whatever the name holds (no protocol, no option).
std::string fileUrl(const std::string& path) { return "file:" + std::filesystem::absolute(path).string(); }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::string framePattern(const std::string& dir) {
  std::string escaped;
  for (char c : fileUrl(dir)) {
    escaped += c;
    if (c == '%') escaped += '%';
  }
  return escaped + "/frame_%05d.png";
}

std::string checkVideoName(const std::string& video, const char* flag) {
  const std::string f = flag;
  if (video.empty()) throw std::runtime_error(f + " needs a file name, got an empty one");
  // "scheme:" at the start (letters, digits, + - .): ffmpeg would open that
  // as a protocol; the user may have meant one.
  std::size_t k = 0;
  while (k < video.size() &&
         (std::isalnum(static_cast<unsigned char>(video[k])) || video[k] == '+' || video[k] == '-' || video[k] == '.'))
    ++k;
  if (k > 0 && k < video.size() && video[k] == ':' && std::isalpha(static_cast<unsigned char>(video[0])))
    throw std::runtime_error(video + ": " + f + " writes a local file, and this looks like a URL ('" +
                             video.substr(0, k + 1) + "'); for a file of that name write ./" + video);
  const std::string ext = lower(std::filesystem::path(video).extension().string());
  std::string container;
  if (ext == ".mp4" || ext == ".m4v")
    container = "mp4";
  else if (ext == ".mov")
    container = "mov";
  else if (ext == ".mkv")
    container = "matroska";
  else
    throw std::runtime_error(video + ": " + f + " writes .mp4, .m4v, .mov or .mkv (H.264), and the name ends in '" +
                             ext + "'");
  checkOutputTarget(video);
  return container;
}

void encodeVideo(const std::string& ffmpeg, const std::string& frames_dir, const std::string& video,
                 double frame_rate) {
  const std::string container = checkVideoName(video, "the video");
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.9g", frame_rate);
  // The temporary ends in the video's own extension; ffmpeg writes it (-y:
  // it exists, empty) and a signal or a failure removes it.
  AtomicFile out(video, std::filesystem::path(video).extension().string());
  out.finish();
  std::vector<std::string> argv = {ffmpeg,
                                   "-nostdin",
                                   "-y",
                                   "-loglevel",
                                   "error",
                                   "-f",
                                   "image2",
                                   "-framerate",
                                   rate,
                                   "-i",
                                   framePattern(frames_dir),
                                   "-c:v",
                                   "libx264",
                                   "-pix_fmt",
                                   "yuv420p",
                                   "-vf",
                                   "pad=ceil(iw/2)*2:ceil(ih/2)*2"};
  if (container == "mp4" || container == "mov") {
    argv.push_back("-movflags");
    argv.push_back("+faststart");
  }
  for (const std::string& a : {std::string("-f"), container, fileUrl(out.temporary())}) argv.push_back(a);
  const ProgramResult run = runProgram(argv);
  // ffmpeg exits 0 when writing the file's end fails (a full disk, say), but
  // says so: at "-loglevel error" anything it writes is an error.
  std::error_code ec;
  const bool written = std::filesystem::file_size(out.temporary(), ec) > 0 && !ec;
  if (run.status != 0 || !run.error_output.empty() || !written) {
    std::string why = run.error_output.substr(0, 2000);
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
    throw std::runtime_error(video + ": ffmpeg could not encode the video (exit status " + std::to_string(run.status) +
                             (why.empty() ? "" : ": " + why) + "); no video was written");
  }
  out.commit();
}

}  // namespace loosehair::app
