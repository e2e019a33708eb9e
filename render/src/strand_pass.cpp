
#include "strand_pass.hpp"

#include "gl_program.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render/shaders.hpp"

#include <algorithm>
#include <string>

namespace loosehair::render {

namespace {
// strands drawn into the opacity maps at most (about): the maps are 256^2
// and smooth; hang at 640x480 differs from all 12,000 drawn by 0.13 grey
// levels on average (2,000: 0.2, with visibly streakier shadows on the
// skin), and the pass takes a third of the time
constexpr std::size_t kLightStrands = 4000;
}  // namespace

StrandPass::StrandPass() {
  const std::string head = "#version 330 core\nuniform vec3 u_eye;\n";
  camera_prog_.reset(program(std::string("#version 330 core\n#define SHADE 1\nuniform vec3 u_eye;\n") +
                                 shaders::nearest_hair_glsl + shaders::shadow_lookup_glsl + shaders::kajiya_kay_glsl +
                                 shaders::strand_shade_glsl + shaders::strand_vert,
                             std::string("#version 330 core\n") + shaders::strand_frag));
  composite_prog_.reset(program(shaders::fullscreen_vert, shaders::oit_composite_frag));
  opacity_prog_.reset(
      program(head + shaders::strand_vert, std::string("#version 330 core\n") + shaders::nearest_hair_glsl +
                                               shaders::opacity_slices_glsl + shaders::strand_opacity_frag));
  vao_ = GlVertexArray::make();  // no attributes: the vertex shader pulls the points
  buffer_ = GlBuffer::make();
  buffer_tex_ = GlTexture::make();
  for (GlTexture& t : lut_) {
    t = GlTexture::make();
    glBindTexture(GL_TEXTURE_2D, t.get());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
}

StrandPass::~StrandPass() = default;

void StrandPass::checkPointCount(std::size_t points) {
  GLint max_texels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_texels);
  if (points > static_cast<std::size_t>(max_texels))
    throw RenderError(std::to_string(points) + " strand points are more than this OpenGL holds (" +
                      std::to_string(max_texels) + "); draw fewer strands");
}

namespace {
void checkStrands(std::size_t points, int per_strand) {
  if (per_strand < 2) throw RenderError("strands need at least 2 points each");
  if (points % static_cast<std::size_t>(per_strand) != 0)
    throw RenderError(std::to_string(points) + " strand points are not strands of " + std::to_string(per_strand));
  StrandPass::checkPointCount(points);
}
}  // namespace

void StrandPass::setStrips(std::size_t points, int per_strand) {
  per_strand_ = per_strand;
  segments_ = points / static_cast<std::size_t>(per_strand) * static_cast<std::size_t>(per_strand - 1);
  const std::size_t strands = points / static_cast<std::size_t>(per_strand);
  strip_first_.resize(strands);
  strip_count_.assign(strands, 2 * per_strand);
  line_first_.resize(strands);
  line_count_.assign(strands, per_strand);
  for (std::size_t k = 0; k < strands; ++k) {
    strip_first_[k] = static_cast<GLint>(2 * k * static_cast<std::size_t>(per_strand));
    line_first_[k] = static_cast<GLint>(k * static_cast<std::size_t>(per_strand));
  }
}

void StrandPass::useBuffer(GLuint buffer, std::size_t points, int per_strand, float mean_length) {
  checkStrands(points, per_strand);
  glBindTexture(GL_TEXTURE_BUFFER, buffer_tex_.get());
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, buffer);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  mean_length_ = mean_length;
  setStrips(points, per_strand);
}

void StrandPass::upload(const std::vector<glm::vec3>& points, int per_strand) {
  checkStrands(points.size(), per_strand);
  staging_.resize(points.size() * 4);
  for (std::size_t q = 0; q < points.size(); ++q) {
    staging_[4 * q + 0] = points[q].x;
    staging_[4 * q + 1] = points[q].y;
    staging_[4 * q + 2] = points[q].z;
    staging_[4 * q + 3] = 0.0f;
  }
  glBindBuffer(GL_TEXTURE_BUFFER, buffer_.get());
  glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(staging_.size() * sizeof(float)), staging_.data(),
               GL_STREAM_DRAW);
  glBindTexture(GL_TEXTURE_BUFFER, buffer_tex_.get());
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, buffer_.get());
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  const std::size_t strands = points.size() / static_cast<std::size_t>(per_strand);
  double length = 0;
  for (std::size_t q = 0; q + 1 < points.size(); ++q)
    if ((q + 1) % static_cast<std::size_t>(per_strand) != 0) length += glm::length(points[q + 1] - points[q]);
  mean_length_ = strands > 0 ? static_cast<float>(length / static_cast<double>(strands)) : 0.0f;
  setStrips(points.size(), per_strand);
}

void StrandPass::drawOpacity(const glm::mat4& view_proj, const glm::mat4& slice_coords, glm::vec3 proj_dir,
                             float pixel_scale, float radius, float opacity, bool nearest_pass, GLuint nearest_tex) {
  if (segments_ == 0) return;
  const GLuint p = opacity_prog_.get();
  glUseProgram(p);
  setI(p, "u_nearest_pass", nearest_pass ? 1 : 0);
  glActiveTexture(GL_TEXTURE0 + kNearestUnit);
  glBindTexture(GL_TEXTURE_2D, nearest_pass ? 0 : nearest_tex);  // never the target it draws into
  setI(p, "u_nearest", kNearestUnit);
  setMat(p, "u_view_proj", view_proj);
  setMat(p, "u_light_coords", slice_coords);
  setVec(p, "u_proj_dir", proj_dir);
  setI(p, "u_ortho", 1);
  setF(p, "u_pixel_scale", pixel_scale);
  setF(p, "u_radius", radius);
  setF(p, "u_opacity", opacity);
  setI(p, "u_points_per_strand", per_strand_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, buffer_tex_.get());
  setI(p, "u_points", 0);
  // Opacity varies smoothly: every stride-th strand, each stride times as
  // opaque, gives the same maps for far fewer fragments.
  const std::size_t strands = strip_first_.size();
  const std::size_t stride = std::max<std::size_t>(1, strands / kLightStrands);
  setF(p, "u_opacity", opacity * static_cast<float>(stride));
  drawEvery(p, stride, asLines(radius, pixel_scale));
}

void StrandPass::drawEvery(GLuint p, std::size_t stride, bool lines) {
  setI(p, "u_lines", lines ? 1 : 0);
  GLint viewport[4] = {0, 0, 1, 1};
  glGetIntegerv(GL_VIEWPORT, viewport);
  glUniform2f(loc(p, "u_viewport"), static_cast<float>(viewport[2]), static_cast<float>(viewport[3]));
  const std::vector<GLint>& first = lines ? line_first_ : strip_first_;
  const std::vector<GLsizei>& count = lines ? line_count_ : strip_count_;
  const GLenum mode = lines ? GL_LINE_STRIP : GL_TRIANGLE_STRIP;
  glBindVertexArray(vao_.get());
  if (stride <= 1) {
    glMultiDrawArrays(mode, first.data(), count.data(), static_cast<GLsizei>(first.size()));
  } else {
    subset_first_.clear();
    subset_count_.clear();
    for (std::size_t k = 0; k < first.size(); k += stride) {
      subset_first_.push_back(first[k]);
      subset_count_.push_back(count[k]);
    }
    glMultiDrawArrays(mode, subset_first_.data(), subset_count_.data(), static_cast<GLsizei>(subset_first_.size()));
  }
  glBindVertexArray(0);
}

void StrandPass::updateTables(const StrandShading& sh) {
  if (sh.color == lut_color_) return;
  lut_color_ = sh.color;
  MarschnerParams par;
  par.absorption = absorptionForColor(sh.color);
  const MarschnerTables t = makeMarschnerTables(par);
  const std::vector<float>* data[3] = {&t.m, &t.n1, &t.n2};
  for (int k = 0; k < 3; ++k) {
    glBindTexture(GL_TEXTURE_2D, lut_[k].get());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t.size, t.size, 0, GL_RGBA, GL_FLOAT, data[k]->data());
  }
}

bool StrandPass::drawTransparent(const OffscreenTarget& target, const Camera& cam, const StrandShading& sh,
                                 float radius, float opacity, const glm::mat4& lookup_coords, float kappa, bool shadows,
                                 GLuint slice_tex, GLuint nearest_tex, std::size_t stride) {
  target.bindTransparency();
  const GLfloat zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  glClearBufferfv(GL_COLOR, 1, zero);
  if (segments_ == 0) return false;
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glDepthMask(GL_FALSE);
  if (sh.marschner) updateTables(sh);
  const GLuint p = camera_prog_.get();
  glUseProgram(p);
  setMat(p, "u_view_proj", cam.view_proj);
  setVec(p, "u_eye", cam.eye);
  setI(p, "u_ortho", 0);
  setF(p, "u_pixel_scale", cam.pixel_scale);
  setF(p, "u_radius", radius);
  setF(p, "u_opacity", opacity * static_cast<float>(stride));  // the strands left stand for the others
  setI(p, "u_points_per_strand", per_strand_);
  setMat(p, "u_light_coords", lookup_coords);
  setF(p, "u_kappa", kappa);
  setI(p, "u_shadows", shadows ? 1 : 0);
  glUniform2f(loc(p, "u_depth_range"), cam.near_depth, cam.far_depth);
  setF(p, "u_depth_falloff", 6.0f);
  setHairShading(p, glm::normalize(sh.light), sh.color, sh.spec, sh.ambient);
  setF(p, "u_variation", sh.variation);
  setI(p, "u_marschner", sh.marschner ? 1 : 0);
  setF(p, "u_marschner_gain", 10.0f);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, buffer_tex_.get());
  setI(p, "u_points", 0);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D_ARRAY, slice_tex);
  setI(p, "u_slices", 1);
  for (int k = 0; k < 3; ++k) {
    glActiveTexture(GL_TEXTURE2 + static_cast<GLenum>(k));
    glBindTexture(GL_TEXTURE_2D, lut_[k].get());
  }
  setI(p, "u_lut_m", 2);
  setI(p, "u_lut_n1", 3);
  setI(p, "u_lut_n2", 4);
  glActiveTexture(GL_TEXTURE0 + kNearestUnit);
  glBindTexture(GL_TEXTURE_2D, nearest_tex);
  setI(p, "u_nearest", kNearestUnit);
  glActiveTexture(GL_TEXTURE0);
  // the nearest hair is the widest on screen
  const bool lines = asLines(radius, cam.pixel_scale / std::max(1e-3f, cam.near_depth));
  drawEvery(p, stride, lines);
  return lines;
}

void StrandPass::composite(const OffscreenTarget& target, GLuint empty_vao) {
  target.bindOpaque();
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glUseProgram(composite_prog_.get());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, target.accum());
  setI(composite_prog_.get(), "u_accum", 0);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, target.reveal());
  setI(composite_prog_.get(), "u_reveal", 1);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
}

}  // namespace loosehair::render
