// Encoding a folder of frames (frame_00001.png ...) to a video with ffmpeg,
// started without a shell (process.hpp).
#pragma once

#include <string>

namespace loosehair::app {

/// The ffmpeg input pattern of the frames in `dir` (a '%' in it escaped),
/// as an absolute "file:" URL so that ffmpeg cannot read it as another
/// protocol or an option.
std::string framePattern(const std::string& dir);

/// Checks a video file name before any work is done and returns ffmpeg's
/// container for it: ".mp4"/".m4v" (mp4), ".mov" (mov), ".mkv" (matroska).
/// Refuses (std::runtime_error naming the value and the flag) any other
/// ending, a name that looks like a URL ("tcp://...", "file:...": write
/// "./file:x.mp4" for a local file of that name) and a target that exists
/// and is not a regular file.
std::string checkVideoName(const std::string& video, const char* flag);

/// Encodes the frames into `video` (H.264 in the container its name asks
/// for, an MP4's index at the front so it plays while it downloads): ffmpeg
/// is started without a shell, writes a temporary file beside `video` that a
/// signal or a failure removes, and only a complete encoding is renamed to
/// `video`. Any failure is an error and leaves no partial file.
void encodeVideo(const std::string& ffmpeg, const std::string& frames_dir, const std::string& video, double frame_rate);

}  // namespace loosehair::app
