// Cubic spline (M4) SPH kernel of SPEC §2, support 2h, integrating to 1 in 3-D.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <numbers>

namespace loosehair {

class CubicKernel {
 public:
  explicit CubicKernel(float h)
      : h_(h),
        inv_h_(1.0f / h),
        norm_w_(1.0f / (4.0f * std::numbers::pi_v<float> * h * h * h)),
        norm_g_(1.0f / (4.0f * std::numbers::pi_v<float> * h * h * h * h)),
        support2_(4.0f * h * h) {}

  float h() const { return h_; }
  float support() const { return 2.0f * h_; }
  float support2() const { return support2_; }

  /// W(r, h), SPEC §2 (eq. 2 reconstructed).
  float W(float r) const {
    const float q = r * inv_h_;
    if (q < 1.0f) return norm_w_ * (4.0f - 6.0f * q * q + 3.0f * q * q * q);
    if (q < 2.0f) {
      const float a = 2.0f - q;
      return norm_w_ * a * a * a;
    }
    return 0.0f;
  }

  /// dW/dr (r, h).
  float dWdr(float r) const {
    const float q = r * inv_h_;
    if (q < 1.0f) return norm_g_ * (-12.0f * q + 9.0f * q * q);
    if (q < 2.0f) {
      const float a = 2.0f - q;
      return -3.0f * norm_g_ * a * a;
    }
    return 0.0f;
  }

  /// grad_i W(|x_i - x_j|, h) for d = x_i - x_j at distance r = |d| > 0.
  glm::vec3 gradW(const glm::vec3& d, float r) const {
    if (r <= 0.0f) return glm::vec3(0.0f);
    return (dWdr(r) / r) * d;
  }

 private:
  float h_, inv_h_, norm_w_, norm_g_, support2_;
};

}  // namespace loosehair
