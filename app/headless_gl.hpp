// An OpenGL 3.3 core context without a display or GPU (OSMesa, llvmpipe),
// rendering into a buffer this object owns (SPEC §7.4).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace loosehair::app {

class HeadlessGL {
 public:
  /// Creates the context and makes it current; throws std::runtime_error.
  HeadlessGL(int width, int height);
  ~HeadlessGL();
  HeadlessGL(const HeadlessGL&) = delete;
  HeadlessGL& operator=(const HeadlessGL&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  /// The finished frame, RGBA8, top row first.
  std::vector<std::uint8_t> pixels() const;
  std::string renderer() const;

 private:
  void* context_ = nullptr;
  int width_, height_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace loosehair::app
