// Pictures in the render tests: an RGBA8 image, and a rendered picture
// against its reference image in tests/golden/ (renewed with
// LOOSEHAIR_UPDATE_GOLDEN=1): the mean channel difference under 2 of 255
// and under 1 % of the channels off by more than 48.
#pragma once

#include "png.hpp"
#include "test_support.hpp"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace lhtest {

/// A picture, RGBA8, top row first.
struct Image {
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgba;
  glm::vec3 at(int x, int y) const {
    const std::size_t k = (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 4;
    return glm::vec3(rgba[k], rgba[k + 1], rgba[k + 2]) / 255.0f;
  }
};

inline void expectMatchesReference(const std::vector<std::uint8_t>& rgba, int w, int h, const std::string& name) {
  const std::string ref_path = sourceDir() + "/tests/golden/" + name;
  if (std::getenv("LOOSEHAIR_UPDATE_GOLDEN")) {
    loosehair::app::writePng(ref_path, rgba, w, h);
    GTEST_SKIP() << "reference renewed";
  }
  int rw = 0, rh = 0, rc = 0;
  unsigned char* ref = stbi_load(ref_path.c_str(), &rw, &rh, &rc, 4);
  ASSERT_NE(ref, nullptr) << "missing " << ref_path;
  if (rw != w || rh != h) stbi_image_free(ref);
  ASSERT_EQ(rw, w);
  ASSERT_EQ(rh, h);
  double sum = 0;
  int far = 0;
  for (int k = 0; k < w * h * 4; ++k) {
    const int d = std::abs(static_cast<int>(ref[k]) - static_cast<int>(rgba[static_cast<std::size_t>(k)]));
    sum += d;
    far += d > 48 ? 1 : 0;
  }
  stbi_image_free(ref);
  EXPECT_LT(sum / (w * h * 4), 2.0) << name << ": mean difference per channel (of 255)";
  EXPECT_LT(far, w * h * 4 / 100) << name << ": channels off by more than 48";
}

}  // namespace lhtest
