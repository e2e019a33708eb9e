// The bodies in the camera pass (body_pass.hpp).
#include "body_pass.hpp"

#include "loosehair/render/shaders.hpp"
#include "gl_program.hpp"
#include "shadow_maps.hpp"

#include <string>
#include <utility>
#include <vector>

namespace loosehair::render {

BodyPass::BodyPass()
    : prog_(program(shaders::body_vert, std::string("#version 330 core\n") + shaders::nearest_hair_glsl +
                                            shaders::shadow_lookup_glsl + shaders::body_frag)) {}

void BodyPass::setBodies(const TriangleMesh* head, const TriangleMesh* torso) {
  upload(head_, head);
  upload(torso_, torso);
}

void BodyPass::upload(Mesh& b, const TriangleMesh* mesh) {
  if (!b.vao.get()) {
    b.vao = GlVertexArray::make();
    b.vbo = GlBuffer::make();
    b.ibo = GlBuffer::make();
  }
  b.count = 0;
  if (!mesh) return;
  const auto normals = vertexNormals(*mesh);
  std::vector<float> data;
  data.reserve(mesh->vertices.size() * 6);
  for (std::size_t v = 0; v < mesh->vertices.size(); ++v)
    data.insert(data.end(), {mesh->vertices[v].x, mesh->vertices[v].y, mesh->vertices[v].z, normals[v].x, normals[v].y,
                             normals[v].z});
  glBindVertexArray(b.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, b.vbo.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.ibo.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh->triangles.size() * 12), mesh->triangles.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 24, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 24, reinterpret_cast<void*>(12));
  glBindVertexArray(0);
  b.count = static_cast<GLsizei>(mesh->triangles.size() * 3);
}

void BodyPass::draw(const glm::mat4& view_proj, const glm::vec3& eye, const glm::vec3& light,
                    const glm::mat4& head_pose, const ShadowMaps& shadows, const glm::mat4& light_coords, float kappa,
                    bool shadows_on) const {
  const GLuint p = prog_.get();
  glUseProgram(p);
  setMat(p, "u_view_proj", view_proj);
  setVec(p, "u_eye", eye);
  setVec(p, "u_light", light);
  setVec(p, "u_skin", glm::vec3(0.86f, 0.68f, 0.58f));
  shadows.bindLookups(p, light_coords, kappa, shadows_on);
  for (const auto& [mesh, model] : {std::pair{&head_, head_pose}, std::pair{&torso_, glm::mat4(1.0f)}}) {
    if (mesh->count == 0) continue;
    setMat(p, "u_model", model);
    glBindVertexArray(mesh->vao.get());
    glDrawElements(GL_TRIANGLES, mesh->count, GL_UNSIGNED_INT, nullptr);
  }
}

}  // namespace loosehair::render
