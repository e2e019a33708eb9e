#include "marschner_lut.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace loosehair::render {

namespace {

constexpr double kPi = std::numbers::pi;

double gaussian(double beta, double x) {
  return std::exp(-0.5 * x * x / (beta * beta)) / (beta * std::sqrt(2.0 * kPi));
}

// Fresnel reflectance of unpolarised light for relative index eta at
// incidence angle whose cosine is cos_i.
double fresnel(double eta, double cos_i) {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin_t2);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Bravais' virtual indices for the cross-section at theta_d.
double etaPerp(double eta, double theta_d) {
  const double c = std::cos(theta_d);
  return std::sqrt(std::max(1e-6, eta * eta - std::sin(theta_d) * std::sin(theta_d))) / std::max(c, 1e-6);
}

// Marschner's cubic fit of the exit azimuth of path p for incidence gamma_i:
// phi(p, gamma_i) ~ (6 p c / pi - 2) gamma_i - 8 p c / pi^3 gamma_i^3 + p pi,
// c = asin(1 / eta').
double phiOf(int p, double c, double g) {
  return (6.0 * p * c / kPi - 2.0) * g - 8.0 * p * c / (kPi * kPi * kPi) * g * g * g + p * kPi;
}
double dPhi(int p, double c, double g) { return (6.0 * p * c / kPi - 2.0) - 24.0 * p * c / (kPi * kPi * kPi) * g * g; }

double wrapAngle(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a < -kPi) a += 2.0 * kPi;
  return a;
}

// The roots gamma_i in [-pi/2, pi/2] of phi(p, gamma_i) = phi (mod 2 pi),
// by bisection of the cubic over a fine grid.
std::vector<double> roots(int p, double c, double phi) {
  std::vector<double> out;
  constexpr int kSteps = 64;
  auto f = [&](double g) { return wrapAngle(phiOf(p, c, g) - phi); };
  double g0 = -0.5 * kPi, f0 = f(g0);
  for (int k = 1; k <= kSteps; ++k) {
    const double g1 = -0.5 * kPi + kPi * k / kSteps, f1 = f(g1);
    if ((f0 <= 0.0) != (f1 <= 0.0) && std::abs(f0 - f1) < kPi) {
      double a = g0, b = g1, fa = f0;
      for (int it = 0; it < 40; ++it) {
        const double m = 0.5 * (a + b), fm = f(m);
        if ((fa <= 0.0) == (fm <= 0.0))
          a = m, fa = fm;
        else
          b = m;
      }
      out.push_back(0.5 * (a + b));
    }
    g0 = g1;
    f0 = f1;
  }
  return out;
}

// N_p for one colour channel: the sum over the paths' incidences of the
// attenuation (Fresnel in and out, absorption along the chord) over the
// spread |2 dphi/dh|.
double azimuthal(int p, double phi, double theta_d, double eta, double sigma_a) {
  const double ep = etaPerp(eta, theta_d);
  const double c = std::asin(std::clamp(1.0 / ep, -1.0, 1.0));
  // absorption measured along the fibre axis: the path grows by 1/cos(theta_t)
  const double sin_t = std::sin(theta_d) / eta;
  const double cos_t = std::sqrt(std::max(1e-6, 1.0 - sin_t * sin_t));
  const double sa = sigma_a / cos_t;
  double sum = 0.0;
  for (double g : roots(p, c, phi)) {
    const double h = std::sin(g);
    const double gt = std::asin(std::clamp(h / ep, -1.0, 1.0));
    const double f_in = fresnel(ep, std::cos(g));
    const double t = std::exp(-2.0 * sa * (1.0 + std::cos(2.0 * gt)));
    double a = (1.0 - f_in) * (1.0 - f_in) * t;
    if (p == 2) a *= fresnel(1.0 / ep, std::cos(gt)) * t;
    const double dphidh = dPhi(p, c, g) / std::max(1e-6, std::sqrt(std::max(0.0, 1.0 - h * h)));
    sum += a / std::max(1e-3, std::abs(2.0 * dphidh));
  }
  return sum;
}

}  // namespace

glm::vec3 absorptionForColor(glm::vec3 color) {
  // TT through the middle of the fibre travels 4 radii: exp(-4 sigma) ~ colour^2
  glm::vec3 s;
  for (int c = 0; c < 3; ++c) s[c] = -0.5f * std::log(std::clamp(color[c], 0.01f, 1.0f));
  return s;
}

MarschnerTables makeMarschnerTables(const MarschnerParams& par, int size) {
  MarschnerTables t;
  t.size = size;
  const std::size_t cells = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  t.m.assign(cells * 4, 0.0f);
  t.n1.assign(cells * 4, 0.0f);
  t.n2.assign(cells * 4, 0.0f);
  const double alpha = par.shift_deg * kPi / 180.0, beta = par.width_deg * kPi / 180.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t at =
          (static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + static_cast<std::size_t>(x)) * 4;
      // M: sin theta_i along u, sin theta_r along v
      const double si = 2.0 * (x + 0.5) / size - 1.0, sr = 2.0 * (y + 0.5) / size - 1.0;
      const double ti = std::asin(si), tr = std::asin(sr);
      const double th = 0.5 * (ti + tr), td = 0.5 * (tr - ti);
      t.m[at + 0] = static_cast<float>(gaussian(beta, th - alpha));
      t.m[at + 1] = static_cast<float>(gaussian(0.5 * beta, th + 0.5 * alpha));
      t.m[at + 2] = static_cast<float>(gaussian(2.0 * beta, th + 1.5 * alpha));
      t.m[at + 3] = static_cast<float>(std::cos(td));
      // N: cos phi along u, cos theta_d along v
      const double cphi = 2.0 * (x + 0.5) / size - 1.0, ctd = (y + 0.5) / size;
      const double phi = std::acos(std::clamp(cphi, -1.0, 1.0)), theta_d = std::acos(std::clamp(ctd, 0.0, 1.0));
      // R: the cuticle's reflection, with Fresnel at the half angle
      t.n1[at + 0] =
          static_cast<float>(0.25 * std::cos(0.5 * phi) * fresnel(par.eta, std::cos(theta_d) * std::cos(0.5 * phi)));
      for (int c = 0; c < 3; ++c) {
        t.n1[at + 1 + static_cast<std::size_t>(c)] =
            static_cast<float>(azimuthal(1, phi, theta_d, par.eta, par.absorption[c]));
        t.n2[at + static_cast<std::size_t>(c)] =
            static_cast<float>(azimuthal(2, phi, theta_d, par.eta, par.absorption[c]));
      }
    }
  return t;
}

}  // namespace loosehair::render
