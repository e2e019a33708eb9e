// Drawing strands (issue "strands"): thin ribbons facing the eye from a
// buffer of strand points, into the opacity shadow maps (method.md §7.2, from the
// light) and into weighted blended transparency sums (from the camera),
// shaded by Kajiya-Kay or by Marschner's lobes from lookup tables.
#pragma once

#include "gl_handles.hpp"

#include "loosehair/render/gl_functions.hpp"

#include "marschner_lut.hpp"
#include "offscreen_target.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace loosehair::render {

struct StrandShading {
  glm::vec3 light{0, 1, 0}, color{0.3f, 0.2f, 0.1f}, spec{0.4f};
  bool marschner = false;
  float variation = 0.12f;
  float ambient = 0.2f;
};

class StrandPass {
 public:
  /// Compiles the programs (needs a current context with GL loaded).
  StrandPass();
  ~StrandPass();
  StrandPass(const StrandPass&) = delete;
  StrandPass& operator=(const StrandPass&) = delete;

  /// The strands to draw: `count` strands of `per_strand` points each.
  void upload(const std::vector<glm::vec3>& points, int per_strand);
  /// Or strands already in `buffer` (points RGBA32F texels, world xyz;
  /// GpuStrandCarry::buffer()), of `mean_length` on average.
  void useBuffer(GLuint buffer, std::size_t points, int per_strand, float mean_length);
  /// Throws RenderError where `points` are more than a buffer texture of
  /// this OpenGL holds.
  static void checkPointCount(std::size_t points);
  std::size_t segments() const { return segments_; }
  std::size_t strands() const { return strip_first_.size(); }
  /// The mean length of the uploaded strands (m).
  float meanLength() const { return mean_length_; }

  /// Opacity slices from the light (orthographic): `slice_coords` maps world
  /// to (s, t, slice), `pixel_scale` is light pixels per metre.
  /// `nearest_pass`: the pass before, the depth of the nearest hair (a MIN
  /// blend); otherwise the slices, from `nearest_tex` on.
  void drawOpacity(const glm::mat4& view_proj, const glm::mat4& slice_coords, glm::vec3 proj_dir, float pixel_scale,
                   float radius, float opacity, bool nearest_pass, GLuint nearest_tex);
  /// The texture unit of the nearest-hair depth in every program.
  static constexpr int kNearestUnit = 5;
  /// Whether strands `radius` wide at `pixels_per_metre` are drawn as lines:
  /// at most a pixel wide.
  static bool asLines(float radius, float pixels_per_metre) { return 2.0f * radius * pixels_per_metre <= 1.0f; }
  /// From the camera, into weighted blended transparency sums.
  struct Camera {
    glm::mat4 view_proj{1.0f};
    glm::vec3 eye{0.0f};
    float pixel_scale = 1.0f;                   // pixels per metre at unit depth
    float near_depth = 0.0f, far_depth = 1.0f;  // the hair's range of eye distances
  };
  /// Clears the target's transparency sums and draws the strands into them
  /// (depth-tested against its opaque picture, not written). Returns
  /// whether they were drawn as lines (asLines at the nearest hair).
  bool drawTransparent(const OffscreenTarget& target, const Camera& cam, const StrandShading& shading, float radius,
                       float opacity, const glm::mat4& lookup_coords, float kappa, bool shadows, GLuint slice_tex,
                       GLuint nearest_tex, std::size_t stride = 1);
  /// The sums over the target's opaque picture (a full-screen triangle from
  /// the attribute-less `empty_vao`).
  void composite(const OffscreenTarget& target, GLuint empty_vao);

 private:
  void setStrips(std::size_t points, int per_strand);  // the strips of points / per_strand strands
  void updateTables(const StrandShading& shading);
  // every stride-th strand, as ribbons or (where they are narrower than a
  // pixel: program p's u_lines is set here) as lines
  void drawEvery(GLuint p, std::size_t stride, bool lines);
  std::vector<GLint> strip_first_;
  std::vector<GLsizei> strip_count_;
  std::vector<GLint> line_first_;
  std::vector<GLsizei> line_count_;
  std::vector<GLint> subset_first_;  // drawEvery's strips
  std::vector<GLsizei> subset_count_;
  GlProgram camera_prog_, opacity_prog_, composite_prog_;
  GlVertexArray vao_;
  GlBuffer buffer_;
  GlTexture buffer_tex_;
  GlTexture lut_[3];
  glm::vec3 lut_color_{-1.0f};
  std::size_t segments_ = 0;
  float mean_length_ = 0.0f;
  int per_strand_ = 2;
  std::vector<float> staging_;
};

}  // namespace loosehair::render
