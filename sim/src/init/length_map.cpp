#include "init/length_map.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace loosehair {
namespace {

// Plain (ASCII, "P2") PGM, which stb_image does not read.
bool readPlainPgm(const std::string& path, int& w, int& h, std::vector<float>& out) {
  std::ifstream in(path);
  std::string magic;
  if (!(in >> magic) || magic != "P2") return false;
  auto next = [&](long& v) {
    for (;;) {
      in >> std::ws;
      if (in.peek() == '#') {
        std::string skip;
        std::getline(in, skip);
        continue;
      }
      return static_cast<bool>(in >> v);
    }
  };
  long lw = 0, lh = 0, maxval = 0;
  if (!next(lw) || !next(lh) || !next(maxval) || lw <= 0 || lh <= 0 || maxval <= 0 ||
      lw > 65536 || lh > 65536 || maxval > 65535)
    throw std::runtime_error(path + ": malformed plain PGM header");
  w = static_cast<int>(lw);
  h = static_cast<int>(lh);
  out.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (auto& v : out) {
    long g = 0;
    if (!next(g) || g < 0 || g > maxval) throw std::runtime_error(path + ": malformed plain PGM pixel data");
    v = static_cast<float>(g) / static_cast<float>(maxval);
  }
  return true;
}

}  // namespace

LengthMap::LengthMap(const std::string& path) {
  if (readPlainPgm(path, width_, height_, value_)) return;
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 1);
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
