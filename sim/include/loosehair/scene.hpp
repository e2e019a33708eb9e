// Scene files (JSON): the head, the scalp, the hair to grow on it, solver
// parameters and the head's motion. Documented in data/scenes/README.md.
#pragma once

#include "loosehair/head_motion.hpp"
#include "loosehair/params.hpp"
#include "loosehair/solver.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace loosehair {

/// A scene file that cannot be used. what() names the file, the field and
/// the problem, e.g. "scenes/a.json: hair.length: must be positive, got -1".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The hair to grow (SPEC §6.1 on an analytic sphere-cap scalp for now).
struct HairSpec {
  int particles = 3000;        // target particle count, roots included
  float length = 0.25f;        // hair length L (m)
  float mass = 0.06f;          // total hair mass (kg)
  glm::vec3 whorl{0, 1, 0};    // whorl normal n_w (head frame, unit)
  float w_t = 1.0f;            // weight of the direction away from the whorl
  float w_n = 1.0f;            // weight of the scalp normal
  /// Cantilever stiffness EI / (weight per length) of the initial strands
  /// (m^3): larger hangs straighter, smaller droops more.
  float bending_stiffness = 5.0e-4f;
  /// Strands lying on the head keep layering * s off it at arc length s
  /// (dimensionless), so hair from the crown lies over hair rooted lower.
  float layering = 0.2f;
  float h1_scale = 1.2f;  // h1 = h1_scale * Poisson radius (SPEC §9)
  /// h2 = min(h2_scale * mean nearest-neighbour distance, 0.8 h1) (SPEC §9)
  float h2_scale = 0.9f;
};

struct SceneDesc {
  std::string source;  // file the scene came from (for messages)
  std::string name;
  std::uint64_t seed = 1;
  int frames = 90;
  double frame_rate = 30.0;  // output frames per simulated second
  int substeps = 0;          // solver steps per frame; 0 = choose from the stable step
  glm::vec3 head_center{0.0f};
  float head_radius = 0.1f;  // m
  float cap_angle_deg = 100.0f;  // scalp: spherical cap up to this angle from the crown (+Y)
  HairSpec hair;
  SimParams sim;
  bool h1_auto = true, h2_auto = true;
  HeadTrajectory motion = HeadTrajectory::still();
};

/// Reads and validates a scene file. Throws SceneError.
SceneDesc loadScene(const std::string& path);
/// The same from text; `source` names it in messages.
SceneDesc parseScene(const std::string& text, const std::string& source);

/// What building a scene chose, for printing.
struct BuildReport {
  float poisson_radius = 0;        // r_P (m)
  float mean_neighbor_distance = 0;  // after the cantilever placement (m)
  int substeps = 0;
  double time_step = 0;  // s
};

/// Grows the hair of `scene` and returns a solver ready to step. Throws
/// SceneError if the scene cannot be simulated (for example h2 >= h1 after
/// the automatic choice).
Solver buildSolver(const SceneDesc& scene, BuildReport* report = nullptr);

}  // namespace loosehair
