#include "png.hpp"

#include "loosehair/file_io.hpp"

#include <stb/stb_image_write.h>

#include <stdexcept>

namespace loosehair::app {

void writePng(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height) {
  // Encoded in memory, then written whole with every write checked (stb's
  // own file writer does not check them: a full disk gave truncated PNGs).
  std::string encoded;
  const int ok = stbi_write_png_to_func(
      [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
      },
      &encoded, width, height, 4, rgba.data(), width * 4);
  if (!ok || encoded.empty()) throw std::runtime_error(path + ": cannot encode the PNG");
  writeFileAtomically(path, {encoded});
}

}  // namespace loosehair::app
