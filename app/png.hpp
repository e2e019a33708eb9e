// PNG output of rendered frames (stb_image_write).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace loosehair::app {

/// Writes RGBA8 pixels (top row first) as a PNG, whole or not at all (a
/// temporary file renamed when complete); throws std::runtime_error.
void writePng(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height);

}  // namespace loosehair::app
