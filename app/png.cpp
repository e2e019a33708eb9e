#include "png.hpp"

#include <stb/stb_image_write.h>

#include <cstdio>
#include <stdexcept>

namespace loosehair::app {

void writePng(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height) {
  const std::string tmp = path + ".tmp.png";
  if (!stbi_write_png(tmp.c_str(), width, height, 4, rgba.data(), width * 4)) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot write the PNG");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the finished PNG");
  }
}

}  // namespace loosehair::app
