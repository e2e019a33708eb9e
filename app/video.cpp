#include "video.hpp"

#include "process.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace loosehair::app {

// ffmpeg's image-sequence pattern for DIR/frame_%05d.png: a '%' of the
// directory's name is doubled so that ffmpeg reads it literally.
std::string framePattern(const std::string& dir) {
  std::string escaped;
  for (char c : dir) {
    escaped += c;
    if (c == '%') escaped += '%';
  }
  return (std::filesystem::path(escaped) / "frame_%05d.png").string();
}

// Encodes the frames into `video` (H.264 MP4, the index at the front so it
// plays while it downloads): ffmpeg is started without a shell, writes a
// temporary file beside `video`, and only a complete encoding is renamed to
// `video`. Any failure is an error and leaves no partial file.
void encodeVideo(const std::string& ffmpeg, const std::string& frames_dir, const std::string& video,
                 double frame_rate) {
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.9g", frame_rate);
  const std::string tmp = video + ".tmp-" + std::to_string(::getpid()) + ".mp4";
  const std::vector<std::string> argv = {
      ffmpeg, "-nostdin", "-y", "-loglevel", "error", "-framerate", rate,
      "-i", framePattern(frames_dir), "-c:v", "libx264", "-pix_fmt", "yuv420p",
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-movflags", "+faststart", "-f", "mp4", tmp};
  const ProgramResult run = runProgram(argv);
  // ffmpeg exits 0 when writing the file's end fails (a full disk, say), but
  // says so: at "-loglevel error" anything it writes is an error.
  std::error_code ec;
  const bool written = std::filesystem::file_size(tmp, ec) > 0 && !ec;
  if (run.status != 0 || !run.error_output.empty() || !written) {
    std::filesystem::remove(tmp, ec);
    std::string why = run.error_output.substr(0, 2000);
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
    throw std::runtime_error(video + ": ffmpeg could not encode the video (exit status " +
                             std::to_string(run.status) + (why.empty() ? "" : ": " + why) +
                             "); no video was written");
  }
  std::filesystem::rename(tmp, video, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(video + ": cannot rename the finished video: " + ec.message());
  }
}

}  // namespace loosehair::app
