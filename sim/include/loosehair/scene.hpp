// Scene files (JSON): the head, the scalp, the hair to grow on it, solver
// parameters and the head's motion. Documented in data/scenes/README.md.
#pragma once

#include "loosehair/head_motion.hpp"
#include "loosehair/mesh.hpp"
#include "loosehair/params.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/wind.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace loosehair {

/// A scene file that cannot be used. what() names the file, the field and
/// the problem, e.g. "scenes/a.json: hair.length: must be positive, got -1".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The hair to grow (method.md §6.1).
struct Style;  // loosehair/style.hpp

struct HairSpec {
  int particles = 3000;  // target particle count, roots included
  /// A style file (resolved path) whose member strands the hair is seeded
  /// from instead of the cantilever placement (method.md §6.2); `style_data`, if
  /// set, is used instead of reading it. The cantilever fields below are
  /// then unused.
  std::string style;
  std::shared_ptr<const Style> style_data;
  float length = 0.25f;      // hair length L (m)
  float mass = 0.06f;        // total hair mass (kg)
  glm::vec3 whorl{0, 1, 0};  // whorl normal n_w (head frame, unit)
  float w_t = 1.0f;          // weight of the direction away from the whorl
  float w_n = 1.0f;          // weight of the scalp normal
  /// Cantilever stiffness EI / (weight per length) of the initial strands
  /// (m^3): larger hangs straighter, smaller droops more.
  float bending_stiffness = 5.0e-4f;
  /// Strands lying on the head keep layering * s off it at arc length s
  /// (dimensionless), so hair from the crown lies over hair rooted lower.
  float layering = 0.2f;
  /// Grayscale image of the length over the scalp square (resolved path;
  /// empty: every hair is `length` long). Hair length = grey * length.
  std::string length_map;
  float h1_scale = 1.2f;  // h1 = h1_scale * Poisson radius (method.md §9)
  /// h2 = min(h2_scale * mean nearest-neighbour distance, 0.8 h1) (method.md §9)
  float h2_scale = 0.9f;
};

/// A mesh named by a scene: its file and how to place it (metres, +Y up,
/// face towards +Z after conversion).
struct MeshSpec {
  std::string path;  // resolved against the scene file's folder
  MeshLoadOptions load;
  float sdf_voxel = 0.0f;  // grid spacing of its signed-distance bake (m); 0 = auto
};

/// A kinematic obstacle in the world (for example a comb or a hand that
/// parts the hair): a sphere or capsule in its own frame, moved by `motion`
/// and present while begin <= t < end.
struct ObstacleSpec {
  enum class Shape { Sphere, Capsule };
  Shape shape = Shape::Sphere;
  glm::vec3 a{0.0f}, b{0.0f};  // sphere centre = a; capsule axis a-b (m)
  float radius = 0.02f;        // m
  HeadTrajectory motion = HeadTrajectory::still();
  double begin = 0.0, end = 1e30;  // s
};

enum class HeadKind { Sphere, Mesh };
enum class ScalpKind { SphereCap, Auto, Curves };

/// The head a scene or a style grows hair on: the head (a sphere or a
/// mesh), the torso below it and the scalp (method.md §5, §6.1). Fields "head",
/// "torso" and "scalp" of scene and style files.
struct HeadDesc {
  HeadKind head_kind = HeadKind::Sphere;
  glm::vec3 head_center{0.0f};
  float head_radius = 0.1f;  // m
  MeshSpec head_mesh;        // head_kind == Mesh: head and neck, turning with the head
  bool has_torso = false;
  MeshSpec torso_mesh;  // shoulders and chest, fixed in the world
  ScalpKind scalp_kind = ScalpKind::SphereCap;
  float cap_angle_deg = 100.0f;  // scalp: spherical cap up to this angle from the crown (+Y)
  /// Control points of the front, right, back and left trimming curves
  /// (scalp_kind == Curves), head frame (m).
  std::array<std::vector<glm::vec3>, 4> scalp_curves;
  /// Same head, torso and scalp (paths compared as written, resolved).
  bool sameAs(const HeadDesc& o) const;
};

/// What HeadModel::build refuses to load or bake (a scene's cost limits,
/// which the program's --allow-expensive lifts).
struct MeshLimits {
  double max_sdf_cells = 256.0e6;          // a body's signed-distance grid (4 bytes a cell)
  std::size_t max_triangles = 10'000'000;  // a mesh's triangles (about 360 bytes each, built)
  static MeshLimits unlimited() { return {1e18, std::size_t{1} << 40}; }
};

/// The most a style may grow (a style file's densities and counts multiply
/// into millions of strands quickly): buildMemberStrands refuses a style
/// whose wisps would grow more, before building anything.
struct StrandBudget {
  std::size_t max_strands = 5'000'000;
  std::size_t max_points = 50'000'000;  // 12 bytes each
  /// No limit but what the strand set can index (2^32 points).
  static StrandBudget unlimited() { return {std::size_t{1} << 31, (std::size_t{1} << 32) - 1}; }
};

struct SceneDesc : HeadDesc {
  std::string source;  // file the scene came from (for messages)
  std::string name;
  std::uint64_t seed = 1;
  int frames = 90;
  double frame_rate = 30.0;  // output frames per simulated second
  int substeps = 0;          // solver steps per frame; 0 = choose from the stable step
  /// Seconds of simulation with the head still before the first frame, so
  /// that the hair starts at rest rather than fanned out in the shape it
  /// was grown in (0..10; Solver::settle).
  double settle = 0.0;
  std::vector<ObstacleSpec> obstacles;
  bool has_wind = false;
  WindParams wind;
  HairSpec hair;
  SimParams sim;
  bool h1_auto = true, h2_auto = true;
  /// solver.shape_keeping not given: a styled scene takes the style's own
  /// strength, others 0.
  bool shape_keeping_auto = true;
  HeadTrajectory motion = HeadTrajectory::still();
  /// What buildSolver refuses to start (not read from the file: the
  /// program's --allow-expensive lifts them).
  struct CostLimits {
    int max_substeps = 2000;                     // solver steps a frame
    std::size_t max_particles = 2'000'000;       // hair.particles
    std::size_t max_air_particles = 4'000'000;   // wind
    MeshLimits mesh;                             // head and torso meshes
    StrandBudget style;                          // a style's member strands
    std::size_t max_strand_points = 20'000'000;  // render strands' points (about 120 bytes each, bound)
    /// No limits (--allow-expensive): whatever the scene costs is started.
    static CostLimits unlimited() {
      return {1 << 30,
              std::size_t{1} << 40,
              std::size_t{1} << 40,
              MeshLimits::unlimited(),
              StrandBudget::unlimited(),
              StrandBudget::unlimited().max_points};
    }
  } limits;
};

/// Reads and validates a scene file. Throws SceneError.
SceneDesc loadScene(const std::string& path);
/// The same from text; `source` names it in messages.
SceneDesc parseScene(const std::string& text, const std::string& source);

/// One value typed into the viewer or set by a script, checked exactly as
/// the scene reader checks that field in a scene file. `field` is its path
/// in a scene file: "seed", "frames", "hair.particles", "hair.length",
/// "solver.youngs_modulus" (any scalar of "solver"), "wind.speed", or
/// "motion.amplitude_deg" / "motion.frequency_hz" (of a shake or nod).
/// Returns the value as the scene holds it (a float's rounding, say).
/// Throws SceneError naming `source`, the field and the value.
double checkSceneValue(const std::string& field, double value, const std::string& source);

/// A head motion file: {"motion": {...}}, the object a scene's "motion"
/// holds (data/scenes/README.md). Throws SceneError naming the file and field.
HeadTrajectory loadMotion(const std::string& path);
/// A head motion file of these keys (the viewer's recorded drag), exact:
/// loadMotion reads back the same bits.
std::string keyframesJson(const std::vector<HeadKeyframe>& keys);

/// What building a scene chose, for printing.
struct BuildReport {
  float poisson_radius = 0;          // r_P (m)
  float mean_neighbor_distance = 0;  // after the cantilever placement (m)
  int substeps = 0;
  double time_step = 0;  // s
  // mesh heads
  std::size_t head_vertices = 0, head_triangles = 0, torso_triangles = 0;
  std::size_t scalp_triangles = 0;
  double scalp_area = 0;          // m^2
  bool scalp_mean_value = false;  // the harmonic map fell back to mean-value weights
  bool sdf_from_cache = false;
  double seconds_meshes = 0, seconds_sdf = 0, seconds_scalp = 0, seconds_sampling = 0, seconds_strands = 0;
  /// Things the scene allows but a user should look at (a head far from
  /// human size, say), each a sentence naming the field and what to set.
  std::vector<std::string> warnings;
  /// Particles dropped after sampling because no particle nearer the root
  /// was within the springs' reach (they would hang on their tether alone).
  std::size_t stragglers_dropped = 0;
  /// Particles drawn in to hair nearer the root at the start (it was
  /// within twice the springs' reach), rather than dropped.
  std::size_t stragglers_pulled = 0;
  // styled scenes
  std::size_t style_wisps = 0, style_strands = 0, style_points = 0;
  std::size_t tied_particles = 0;  // held by a tie
  float shape_keeping = 0;         // Hz, the strength used
  /// The particles as grown, before the scene's settle (null without one):
  /// render strands are grown in that shape, so they are bound to it.
  std::shared_ptr<const Particles> grown;
};

/// Grows the hair of `scene` and returns a solver ready to step. Throws
/// SceneError if the scene cannot be simulated (for example h2 >= h1 after
/// the automatic choice).
Solver buildSolver(const SceneDesc& scene, BuildReport* report = nullptr);

class HeadModel;
struct Style;
/// The style of a styled scene (hair.style or hair.style_data) placed on
/// `model`, the scene's head: as it is when it was made on that head,
/// otherwise re-rooted by (u, v) (a warning in `report`). Throws SceneError
/// or StyleError.
Style sceneStyle(const SceneDesc& scene, const HeadModel& model, BuildReport* report = nullptr);

}  // namespace loosehair
