// Cubic spline (M4) SPH kernel of method.md §2, support 2h, integrating to 1 in 3-D.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <numbers>

namespace loosehair {

/// W(r, h) of the cubic kernel below from 1/h and 1/(4 pi h^3), and dW/dr
/// from 1/h and 1/(4 pi h^4): the expressions CubicKernel uses, as free
/// functions of plain floats for the solver's vectorised pair loops (each
/// caller gets the same bits as CubicKernel::W and dWdr).
inline float cubicW(float r, float inv_h, float norm_w) {
  const float q = r * inv_h;
  const float a = std::max(2.0f - q, 0.0f), b = std::max(1.0f - q, 0.0f);
  return norm_w * (a * a * a - 4.0f * (b * b * b));
}
inline float cubicDWdr(float r, float inv_h, float norm_g) {
  const float q = r * inv_h;
  const float a = std::max(2.0f - q, 0.0f), b = std::max(1.0f - q, 0.0f);
  return -3.0f * norm_g * (a * a - 4.0f * (b * b));
}

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

  /// W(r, h), method.md §2 (eq. 2 reconstructed). Written as
  /// (2-q)^3_+ - 4 (1-q)^3_+ (the same polynomial as the piecewise form
  /// 4 - 6q^2 + 3q^3 on [0,1)) so that it compiles to selects, not branches:
  /// the solver's pair loops call it millions of times a step with
  /// unpredictable q.
  float W(float r) const { return cubicW(r, inv_h_, norm_w_); }

  /// dW/dr (r, h) = -(3/h) [(2-q)^2_+ - 4 (1-q)^2_+] norm_w.
  float dWdr(float r) const { return cubicDWdr(r, inv_h_, norm_g_); }

  /// grad_i W(|x_i - x_j|, h) for d = x_i - x_j at distance r = |d| > 0.
  glm::vec3 gradW(const glm::vec3& d, float r) const {
    if (r <= 0.0f) return glm::vec3(0.0f);
    return (dWdr(r) / r) * d;
  }

 private:
  float h_, inv_h_, norm_w_, norm_g_, support2_;
};

}  // namespace loosehair
