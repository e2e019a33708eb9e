// Hair length over the scalp square (method.md §6.1): a grayscale image (PNG,
// binary or plain PGM, or anything stb_image reads) whose row 0 is v = 0
// (the front hairline) and column 0 is u = 0 (the left temple); the hair
// length is the grey level (0..1) times the maximum length.
#pragma once

#include <glm/vec2.hpp>

#include <string>
#include <vector>

namespace loosehair {

class LengthMap {
 public:
  /// A map that is 1 everywhere.
  LengthMap() = default;
  /// Reads the image; throws std::runtime_error naming the file.
  explicit LengthMap(const std::string& path);
  /// Bilinear lookup in [0, 1].
  float operator()(glm::vec2 uv) const;
  int width() const { return width_; }
  int height() const { return height_; }
  float maximum() const;

 private:
  int width_ = 1, height_ = 1;
  std::vector<float> value_{1.0f};
};

}  // namespace loosehair
