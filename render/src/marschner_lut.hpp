// Marschner et al.'s hair scattering model ("Light Scattering from Human
// Hair Fibers", 2003) tabulated as in the Nalu chapter (GPU Gems 2, ch. 23):
// the longitudinal terms M_p(theta_h) and the azimuthal terms
// N_p(phi, theta_d) of the lobes R, TT and TRT in 2-D tables the fragment
// shader reads. No GL here: the renderer uploads the tables.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace loosehair::render {

struct MarschnerParams {
  float eta = 1.55f;                       // index of refraction of the fibre
  float shift_deg = -6.0f;                 // alpha_R: the cuticle tilt (R shifts by it, TT by -1/2, TRT by -3/2)
  float width_deg = 7.0f;                  // beta_R: R's longitudinal width (TT half, TRT double)
  glm::vec3 absorption{0.3f, 0.6f, 1.2f};  // sigma_a per unit fibre radius (colour of TT, TRT)
};

/// Absorption that gives a fibre of about `color` (linear RGB, each in (0, 1]).
glm::vec3 absorptionForColor(glm::vec3 color);

struct MarschnerTables {
  int size = 0;  // each table is size x size, RGBA float, rows bottom to top
  /// u = (sin theta_i + 1) / 2, v = (sin theta_r + 1) / 2 -> (M_R, M_TT, M_TRT, cos theta_d)
  std::vector<float> m;
  /// u = (cos phi + 1) / 2, v = cos theta_d -> (N_R, N_TT r g b)
  std::vector<float> n1;
  /// the same -> (N_TRT r g b, 0)
  std::vector<float> n2;
};

MarschnerTables makeMarschnerTables(const MarschnerParams& params, int size = 64);

}  // namespace loosehair::render
