// The hair renderer (method.md §7): one textured billboard per particle along its
// hair direction, Goldman shading, two-pass light attenuation with 16
// opacity slices, the head and torso shaded and shadowed by the hair, and
// debug views. It draws into the OpenGL 3.3 core context that is current
// when it is created and used; it never creates one (app/ does, with OSMesa
// or GLFW). It is built against the GL headers only.
#pragma once

#include "loosehair/mesh.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace loosehair::render {

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A ray in world coordinates (unit direction).
struct Ray {
  glm::vec3 origin{0.0f}, direction{0.0f, 0.0f, -1.0f};
};

/// An orbit camera around `target`: yaw about +Y (0 = looking at the face,
/// from +Z), pitch above the horizontal, distance and vertical field of view.
struct Camera {
  glm::vec3 target{0.0f, -0.05f, 0.0f};
  float yaw_deg = 0.0f, pitch_deg = 5.0f;
  float distance = 0.75f;
  float fov_deg = 40.0f;
  float near_plane = 0.02f, far_plane = 10.0f;
  /// Moves the picture's centre right by this fraction of half the view's
  /// width (a lens shift: the viewer centres the hair in what its panel
  /// leaves free). 0 centres it.
  float shift_x = 0.0f;

  /// "front", "side" (from the right), "back", "three-quarter"; throws
  /// RenderError on anything else.
  static Camera preset(const std::string& name);
  glm::vec3 eye() const;
  /// The default light for this camera: the front camera's key light
  /// (above, to its right, in front: RenderSettings' default direction)
  /// turned about the vertical with the camera's yaw, so that the hair is
  /// lit, and its shadows fall behind it, from whichever side it is seen.
  glm::vec3 keyLight() const;
  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;
  /// The ray from the eye through window pixel (x, y) of a `width` x
  /// `height` view (x right, y down from the top-left, as mouse positions).
  Ray ray(double x, double y, int width, int height) const;
  /// The window pixel (x right, y down) where world point `p` is seen:
  /// ray()'s inverse.
  glm::vec2 pixel(glm::vec3 p, int width, int height) const;
};

enum class HairColor { Black, Brown, Blonde, Red };
/// "black", "brown", "blonde", "red"; throws RenderError otherwise.
HairColor parseHairColor(const std::string& name);

enum class DebugView { None, Density, Speed, Connections, Directions };
DebugView parseDebugView(const std::string& name);

/// What the hair is drawn as: a billboard a particle (method.md §7.1) or the
/// thin strands the particles carry (FrameInput::strand_points).
enum class HairGeometry { Billboards, Strands };
/// "billboards" or "strands"; throws RenderError otherwise.
HairGeometry parseHairGeometry(const std::string& name);
/// How strands are lit: Kajiya-Kay with Goldman's directionality (method.md
/// §7.3), or Marschner's R, TT and TRT lobes from lookup tables.
enum class HairShading { KajiyaKay, Marschner };
/// "kajiya-kay" or "marschner"; throws RenderError otherwise.
HairShading parseHairShading(const std::string& name);

struct RenderSettings {
  HairColor color = HairColor::Brown;
  /// A colour of one's own (linear RGB in [0, 1]) instead of the preset's;
  /// its highlight is a paler version of it.
  std::optional<glm::vec3> custom_color;
  /// Direction the light comes from (towards the light, world), parallel.
  glm::vec3 light_direction{0.4f, 0.8f, 0.6f};
  bool shadows = true;
  float kappa = 5.5f;          // transmittance exp(-kappa * Omega) (method.md §7.2)
  float shadow_offset = 0.6f;  // lookup offset along the light, in slices
  /// Billboard size as multiples of the particle spacing: width across the
  /// hair and length along it (before the sin(phi) foreshortening).
  float billboard_width = 2.5f, billboard_length = 9.0f;
  float max_opacity_boost = 4.0f;  // clamp of 1/sin(phi)
  float hair_opacity = 0.8f;       // alpha of one billboard at its brightest
  glm::vec3 background{0.92f, 0.93f, 0.95f};
  DebugView debug = DebugView::None;
  /// Strands where the frame has them (else billboards).
  HairGeometry hair = HairGeometry::Billboards;
  HairShading shading = HairShading::KajiyaKay;
  /// Strand half-width (m; one render strand stands for a few hairs) and
  /// the opacity of a strand that covers a whole pixel.
  float strand_radius = 1.5e-4f;
  float strand_opacity = 0.75f;
  /// Relative brightness variation between strands.
  float strand_variation = 0.15f;
  /// Supersampling: draw at factor x factor the size and filter down (1..4).
  int supersample = 1;
  /// Level of detail: where the strands overlap more than
  /// kStrandLayers deep on screen (hair small in the picture), every k-th
  /// strand is drawn, k times as opaque (strandLevelOfDetail).
  bool strand_lod = true;
  /// At most about this many strands drawn (every k-th, k times as
  /// opaque), 0 for all: for a window that must keep drawing while the
  /// hair moves on a slow (software) renderer. The level of detail's
  /// stride is then rounded up to a multiple of k.
  std::size_t strand_budget = 0;
};

/// The k of "every k-th strand" for `strands` strands and a `budget`
/// (RenderSettings::strand_budget; 0: no limit).
std::size_t strandBudgetStride(std::size_t strands, std::size_t budget);

/// How many strands overlap on screen, on average over the hair's area,
/// before the level of detail thins them.
inline constexpr float kStrandLayers = 8.0f;
/// The level of detail's stride: every k-th of `strands` strands of mean
/// length `mean_length` (m) and half-width `radius` (m), in hair of
/// bounding radius `hair_radius` (m) at `depth` (m) from the eye, seen at
/// `pixel_scale` pixels per metre at unit depth, so that about
/// kStrandLayers of them overlap (at least 1: all of them).
std::size_t strandLevelOfDetail(std::size_t strands, float mean_length, float radius, float hair_radius, float depth,
                                float pixel_scale);

/// What one frame shows, in world coordinates.
struct FrameInput {
  std::vector<glm::vec3> position, direction;
  std::vector<float> density, speed;  // for the debug views (may be empty)
  /// Connection lines (pairs of indices into position) for DebugView::Connections.
  std::vector<std::uint32_t> connections;
  float spacing = 0.01f;  // typical distance between neighbouring particles (m)
  /// Render strands (RenderSettings::hair): strand after strand, each of
  /// strand_points_each points (loosehair::StrandField::deformWorld).
  std::vector<glm::vec3> strand_points;
  int strand_points_each = 0;
  /// Or strands already on the GPU, in a buffer of the renderer's context
  /// (GpuStrandCarry::buffer(): RGBA32F texels, world xyz) of
  /// strand_buffer_points points, strand_points_each a strand, of
  /// strand_mean_length (m) on average; strand_points is then empty. The
  /// light's frame is fitted to the particles, widened by twice `spacing`.
  unsigned strand_buffer = 0;
  std::size_t strand_buffer_points = 0;
  float strand_mean_length = 0.0f;
  glm::mat4 head_pose{1.0f};  // head frame -> world for the head mesh
};

/// Wall-clock seconds of the last frame's parts.
struct FrameTimes {
  double sort = 0, light_pass = 0, camera_pass = 0, upload = 0;
  double resolve = 0;             // transparency composite and supersampling filter
  std::size_t strands_drawn = 0;  // from the camera (the level of detail's choice)
  bool strands_as_lines = false;  // from the camera: a pixel wide or less, as lines
};

/// What the density and speed debug views' colours mean: the value range
/// of a frame drawn in one (blue at `low`, red at `high`).
struct DebugLegend {
  bool shown = false;  // drawn in the density or speed view
  DebugView view = DebugView::None;
  float low = 0, high = 0;
  const char* unit = "";  // "kg/m^3" or "m/s"
};

/// The debug views' colour for t in [0, 1]: blue, cyan, yellow, red (the
/// ramp render/shaders/debug.frag is given, for legends).
glm::vec3 debugRamp(float t);

/// The legend of `frame` drawn with `settings` (shown only in the density
/// and speed views): the range the renderer colours by.
DebugLegend debugLegend(const FrameInput& frame, const RenderSettings& settings);

class Renderer {
 public:
  /// Needs a current OpenGL 3.3 core context; throws RenderError if shaders
  /// do not compile or the context lacks what is needed.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// The head (moving with FrameInput::head_pose) and the torso (fixed).
  void setBodies(const TriangleMesh* head, const TriangleMesh* torso);

  /// Draws a frame into the framebuffer bound now, `width` x `height`.
  void render(const FrameInput& frame, const Camera& camera, const RenderSettings& settings, int width, int height);

  const FrameTimes& lastTimes() const { return times_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  FrameTimes times_;
};

/// Back-to-front order of `depth` (larger first) by an O(N) radix sort of
/// the float bits; ties keep index order.
void sortBackToFront(const std::vector<float>& depth, std::vector<std::uint32_t>& order,
                     std::vector<std::uint32_t>& scratch);

/// The hair-strand texture (RGBA, `width` x `height`, rows bottom to top):
/// thin vertical strands, alpha fading towards the ends. Deterministic.
std::vector<std::uint8_t> makeHairTexture(int width, int height, std::uint64_t seed = 7);

}  // namespace loosehair::render
