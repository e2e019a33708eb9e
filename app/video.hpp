// Encoding a folder of frames (frame_00001.png ...) to an MP4 with ffmpeg,
// started without a shell (process.hpp).
#pragma once

#include <string>

namespace loosehair::app {

/// The ffmpeg input pattern of the frames in `dir` (a '%' in it escaped).
std::string framePattern(const std::string& dir);

/// Encodes the frames into `video` (H.264 MP4, the index at the front so it
/// plays while it downloads): ffmpeg is started without a shell, writes a
/// temporary file beside `video`, and only a complete encoding is renamed to
/// `video`. Any failure is an error and leaves no partial file.
void encodeVideo(const std::string& ffmpeg, const std::string& frames_dir, const std::string& video,
                 double frame_rate);

}  // namespace loosehair::app
