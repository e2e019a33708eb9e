// The hair as billboards (billboard_pass.hpp, method.md §7.1).
#include "billboard_pass.hpp"

#include "loosehair/render/shaders.hpp"
#include "gl_program.hpp"
#include "render_passes.hpp"
#include "shadow_maps.hpp"
#include "strand_pass.hpp"

#include <algorithm>
#include <cstring>
#include <string>

namespace loosehair::render {

BillboardPass::BillboardPass() {
  const std::string frag_head = "#version 330 core\n";
  hair_prog_.reset(program(std::string("#version 330 core\n#define SHADE 1\nuniform vec3 u_eye;\n") +
                               shaders::kajiya_kay_glsl + shaders::hair_shade_glsl + shaders::billboard_vert,
                           frag_head + shaders::nearest_hair_glsl + shaders::shadow_lookup_glsl + shaders::hair_frag));
  opacity_prog_.reset(
      program(std::string("#version 330 core\nuniform vec3 u_eye;\n") + shaders::billboard_vert,
              frag_head + shaders::nearest_hair_glsl + shaders::opacity_slices_glsl + shaders::opacity_frag));
  // The hair-strand texture, mipmapped (method.md §7.1).
  const int tw = kStrandWidth, th = kStrandHeight;
  static_assert((1 << kStrandLevels) == kStrandWidth && kStrandHeight >= kStrandWidth);
  const auto pixels = makeHairTexture(tw, th);
  hair_tex_ = GlTexture::make();
  glBindTexture(GL_TEXTURE_2D, hair_tex_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, tw, th, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  // Vertices: position, direction, value (the same for the 4 corners; the
  // vertex shader takes the corner from gl_VertexID).
  quad_vao_ = GlVertexArray::make();
  quad_vbo_ = GlBuffer::make();
  quad_ibo_ = GlBuffer::make();
  glBindVertexArray(quad_vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, quad_vbo_.get());
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, quad_ibo_.get());
  for (GLuint a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 28, nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 28, reinterpret_cast<void*>(12));
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 28, reinterpret_cast<void*>(24));
  glBindVertexArray(0);
}

// Back to front by an O(N) sort, as 4 vertices each (the index buffer
// grows with the count).
void BillboardPass::upload(const FrameInput& in, const glm::mat4& view, const std::vector<float>& values,
                           FrameTimes& times) {
  const std::size_t n = in.position.size();
  count_ = n;
  auto t0 = PassClock::now();
  depth_.resize(n);
  for (std::size_t i = 0; i < n; ++i) depth_[i] = -(view * glm::vec4(in.position[i], 1.0f)).z;
  sortBackToFront(depth_, order_, scratch_);
  times.sort = since(t0);

  t0 = PassClock::now();
  quads_.resize(n * 4 * 7);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = order_[k];
    const float v[7] = {in.position[i].x,
                        in.position[i].y,
                        in.position[i].z,
                        in.direction[i].x,
                        in.direction[i].y,
                        in.direction[i].z,
                        i < values.size() ? values[i] : 0.0f};
    for (int corner = 0; corner < 4; ++corner) std::memcpy(&quads_[(k * 4 + corner) * 7], v, sizeof v);
  }
  glBindVertexArray(quad_vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, quad_vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads_.size() * sizeof(float)), quads_.data(), GL_STREAM_DRAW);
  if (quad_capacity_ < n) {
    quad_capacity_ = std::max<std::size_t>(n, 2 * quad_capacity_);
    quad_indices_.resize(quad_capacity_ * 6);
    for (std::size_t k = 0; k < quad_capacity_; ++k) {
      const auto b = static_cast<std::uint32_t>(4 * k);
      const std::uint32_t tri[6] = {b, b + 1, b + 2, b + 2, b + 1, b + 3};  // the strip 0 1 2 3
      std::memcpy(&quad_indices_[6 * k], tri, sizeof tri);
    }
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(quad_indices_.size() * sizeof(std::uint32_t)),
                 quad_indices_.data(), GL_STATIC_DRAW);
  }
  glBindVertexArray(0);
  times.upload = since(t0);
}

void BillboardPass::setLook(GLuint p, const BillboardLook& look) const {
  setF(p, "u_width", look.width);
  setF(p, "u_length", look.length);
  setF(p, "u_max_boost", look.max_boost);
  setF(p, "u_opacity", look.opacity);
  setF(p, "u_strand_width", static_cast<float>(kStrandWidth));
  setF(p, "u_strand_max_level", static_cast<float>(kStrandLevels));
}

// the sorted billboards with program p (its other uniforms set)
void BillboardPass::draw(GLuint p) const {
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, hair_tex_.get());
  setI(p, "u_hair", 0);
  glBindVertexArray(quad_vao_.get());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * count_), GL_UNSIGNED_INT, nullptr);
}

void BillboardPass::drawOpacity(const BillboardLook& look, const glm::mat4& light_view_proj,
                                const glm::mat4& slice_coords, const glm::vec3& light, float pixel_scale,
                                bool nearest_pass, GLuint nearest_tex) const {
  const GLuint p = opacity_prog_.get();
  glUseProgram(p);
  setI(p, "u_nearest_pass", nearest_pass ? 1 : 0);
  glActiveTexture(GL_TEXTURE0 + StrandPass::kNearestUnit);
  glBindTexture(GL_TEXTURE_2D, nearest_pass ? 0 : nearest_tex);  // never the target it draws into
  setI(p, "u_nearest", StrandPass::kNearestUnit);
  setMat(p, "u_view_proj", light_view_proj);
  setMat(p, "u_light_coords", slice_coords);
  setVec(p, "u_proj_dir", -light);
  setI(p, "u_ortho", 1);
  setF(p, "u_pixel_scale", pixel_scale);
  setLook(p, look);
  draw(p);
}

void BillboardPass::drawShaded(const BillboardLook& look, const Shading& sh, const ShadowMaps& shadows,
                               const glm::mat4& light_coords, float kappa, bool shadows_on) const {
  // blended back to front, tested against the bodies' depth; "over" for
  // colour, the framebuffer's alpha stays opaque
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glDepthMask(GL_FALSE);
  const GLuint p = hair_prog_.get();
  glUseProgram(p);
  setMat(p, "u_view_proj", sh.view_proj);
  setVec(p, "u_eye", sh.eye);
  setI(p, "u_ortho", 0);
  setF(p, "u_pixel_scale", sh.pixel_scale);
  setLook(p, look);
  setHairShading(p, sh.light, sh.color, sh.spec, 0.22f);
  shadows.bindLookups(p, light_coords, kappa, shadows_on);
  draw(p);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

}  // namespace loosehair::render
