#include "init/length_map.hpp"

#include "loosehair/file_io.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdint>
#include <stdexcept>

namespace loosehair {
namespace {

constexpr long kMaxSide = 16384;               // pixels on a side
constexpr std::size_t kMaxPixels = 64u << 20;  // 64 M pixels

// PGM ("P2" plain or "P5" binary, Netpbm), read by this project: stb's own
// PGM reader accepted negative sizes and truncated files. Returns false if
// `bytes` is not a PGM at all.
bool readPgm(const std::string& path, const std::string& bytes, int& w, int& h, std::vector<float>& out) {
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '2' && bytes[1] != '5')) return false;
  const bool plain = bytes[1] == '2';
  std::size_t at = 2;
  auto fail = [&](const std::string& why) -> bool {
    throw std::runtime_error(path + ": not a valid PGM image: " + why);
  };
  auto skipSpace = [&] {
    while (at < bytes.size()) {
      if (bytes[at] == '#') {
        while (at < bytes.size() && bytes[at] != '\n') ++at;
      } else if (std::isspace(static_cast<unsigned char>(bytes[at]))) {
        ++at;
      } else {
        break;
      }
    }
  };
  // A decimal number; anything else (a sign, a letter, the end) is an error.
  auto number = [&](const char* what, long limit) -> long {
    skipSpace();
    if (at >= bytes.size() || !std::isdigit(static_cast<unsigned char>(bytes[at])))
      fail(std::string("the ") + what + " is missing or not a positive whole number");
    long v = 0;
    while (at < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[at]))) {
      v = v * 10 + (bytes[at] - '0');
      if (v > limit) fail(std::string("the ") + what + " is above " + std::to_string(limit));
      ++at;
    }
    return v;
  };
  const long lw = number("width", kMaxSide), lh = number("height", kMaxSide);
  const long maxval = number("maximum grey value", 65535);
  if (lw <= 0 || lh <= 0) fail("the size is " + std::to_string(lw) + "x" + std::to_string(lh));
  if (maxval <= 0) fail("the maximum grey value is 0");
  const std::size_t pixels = static_cast<std::size_t>(lw) * static_cast<std::size_t>(lh);
  if (pixels > kMaxPixels) fail(std::to_string(lw) + "x" + std::to_string(lh) + " pixels is too many");
  w = static_cast<int>(lw);
  h = static_cast<int>(lh);
  if (plain) {
    // every sample takes at least two bytes (a digit and a separator)
    if (pixels > (bytes.size() - at + 1) / 2)
      fail("the file is too short for " + std::to_string(w) + "x" + std::to_string(h) + " pixels");
    out.resize(pixels);
    for (std::size_t k = 0; k < pixels; ++k) {
      const long g = number("grey value", 65535);
      if (g > maxval)
        fail("pixel " + std::to_string(k) + " is " + std::to_string(g) + ", above the maximum " +
             std::to_string(maxval));
      out[k] = static_cast<float>(g) / static_cast<float>(maxval);
    }
    return true;
  }
  // binary: one whitespace byte, then the samples (two bytes, most
  // significant first, when the maximum is above 255)
  if (at >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[at])))
    fail("no whitespace after the header");
  ++at;
  const std::size_t bytes_per = maxval > 255 ? 2 : 1;
  if (bytes.size() - at < pixels * bytes_per)
    fail("the file is truncated: " + std::to_string(bytes.size() - at) + " bytes of pixels where " + std::to_string(w) +
         "x" + std::to_string(h) + " need " + std::to_string(pixels * bytes_per));
  out.resize(pixels);
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
  for (std::size_t k = 0; k < pixels; ++k) {
    const long g = bytes_per == 2 ? (long{p[2 * k]} << 8) | p[2 * k + 1] : long{p[k]};
    if (g > maxval)
      fail("pixel " + std::to_string(k) + " is " + std::to_string(g) + ", above the maximum " + std::to_string(maxval));
    out[k] = static_cast<float>(g) / static_cast<float>(maxval);
  }
  return true;
}

}  // namespace

LengthMap::LengthMap(const std::string& path) {
  const std::string bytes = readRegularFile(path, kMaxImageFileBytes);
  if (readPgm(path, bytes, width_, height_, value_)) return;
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX))
    throw std::runtime_error(path + ": the image file is too large");
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int len = static_cast<int>(bytes.size());
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(data_in, len, &w, &h, &channels)) {
    const char* why = stbi_failure_reason();
    throw std::runtime_error(path + ": cannot read the image (" + std::string(why ? why : "unknown format") +
                             "; PNG, PGM, JPEG, BMP and TGA are read)");
  }
  if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide ||
      static_cast<std::size_t>(w) * static_cast<std::size_t>(h) > kMaxPixels)
    throw std::runtime_error(path + ": the image is " + std::to_string(w) + "x" + std::to_string(h) +
                             " pixels; at most " + std::to_string(kMaxSide) + " a side are read");
  unsigned char* data = stbi_load_from_memory(data_in, len, &w, &h, &channels, 1);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw std::runtime_error(path + ": cannot read the image (" + std::string(why ? why : "unknown error") + ")");
  }
  width_ = w;
  height_ = h;
  value_.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (std::size_t k = 0; k < value_.size(); ++k) value_[k] = static_cast<float>(data[k]) / 255.0f;
  stbi_image_free(data);
}

float LengthMap::operator()(glm::vec2 uv) const {
  const float x = std::clamp(uv.x, 0.0f, 1.0f) * static_cast<float>(width_) - 0.5f;
  const float y = std::clamp(uv.y, 0.0f, 1.0f) * static_cast<float>(height_) - 0.5f;
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, width_ - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, height_ - 1);
  const int x1 = std::min(x0 + 1, width_ - 1), y1 = std::min(y0 + 1, height_ - 1);
  const float fx = std::clamp(x - static_cast<float>(x0), 0.0f, 1.0f);
  const float fy = std::clamp(y - static_cast<float>(y0), 0.0f, 1.0f);
  auto at = [&](int i, int j) { return value_[static_cast<std::size_t>(j * width_ + i)]; };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) + fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

float LengthMap::maximum() const { return *std::max_element(value_.begin(), value_.end()); }

}  // namespace loosehair
