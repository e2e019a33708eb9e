// SPEC §7: billboards (7.1), opacity shadow maps (7.2), Goldman shading
// (7.3). Built against the GL headers only; the executable links the one
// library that provides the GL functions (SPEC §7.4).
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "loosehair/render/renderer.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

namespace loosehair::render {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

constexpr int kSlices = 16;
constexpr int kSliceLayers = 5;  // RGBA layers holding slices 3l .. 3l+3
constexpr int kStrandWidth = 32, kStrandHeight = 128;  // the strand texture, texels
constexpr int kStrandLevels = 5;  // its mip levels down to 1 texel across: log2(kStrandWidth)
constexpr int kShadowSize = 256;  // opacity varies smoothly; 256^2 keeps the light pass cheap

// ---- shaders ------------------------------------------------------------------
// Billboard geometry (SPEC §7.1), shared by both passes: the vertical axis is
// the hair direction made perpendicular to the projection direction d, whose
// length is foreshortened by sin(phi); opacity is boosted by 1/sin(phi).
const char* kBillboardVS = R"(
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_dir;
layout(location = 2) in float a_value;
uniform mat4 u_view_proj;
uniform vec3 u_proj_dir;   // (u_eye, the perspective eye, is declared before)   // orthographic: projection direction
uniform int u_ortho;
uniform float u_width, u_length, u_max_boost, u_opacity;
uniform mat4 u_light_coords;  // world -> (s, t, slice) of the opacity maps
// pixels per metre at unit depth (perspective) or per metre (orthographic)
uniform float u_pixel_scale;
uniform float u_strand_width;  // texels across the strand texture
uniform float u_strand_max_level;
out vec2 v_uv;
flat out int v_level;
out vec3 v_T;
out vec3 v_light;
out float v_alpha;
out float v_value;
#ifdef SHADE
out vec3 v_color;
#endif
void main() {
  vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
  vec3 d = u_ortho == 1 ? u_proj_dir : normalize(a_pos - u_eye);
  vec3 T = normalize(a_dir);
  float c = clamp(abs(dot(T, d)), 0.0, 1.0);
  float s = sqrt(max(0.0, 1.0 - c * c));
  vec3 axis = T - dot(T, d) * d;
  float al = length(axis);
  vec3 helper = abs(d.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  axis = al > 1e-5 ? axis / al : normalize(cross(d, helper));
  vec3 side = normalize(cross(d, axis));
  float len = max(u_length * s, u_width);
  vec3 p = a_pos + (0.5 * u_width * corner.x) * side + (0.5 * len * corner.y) * axis;
  v_uv = 0.5 * corner + 0.5;
  // the strand texture's mip level, once per billboard: its texels across
  // the billboard's width on screen
  float depth = u_ortho == 1 ? 1.0 : max(1e-4, length(a_pos - u_eye));
  float width_px = u_width * u_pixel_scale / depth;
  float level = floor(log2(u_strand_width / max(width_px, 1e-3)) + 0.5);
  v_level = int(clamp(level, 0.0, u_strand_max_level));
  v_T = T;
  v_light = (u_light_coords * vec4(p, 1.0)).xyz;  // affine (orthographic light): exact to interpolate
  v_alpha = u_opacity * min(1.0 / max(s, 1e-4), u_max_boost);
  v_value = a_value;
#ifdef SHADE
  v_color = shade(T, a_pos);
#endif
  gl_Position = u_view_proj * vec4(p, 1.0);
}
)";

// Pass 1: every fragment adds its opacity to the slices behind it, with a
// one-slice ramp (so the lookup interpolates). Layer l of the slice array
// holds slices 3l .. 3l+3 (neighbouring layers share one slice), so any two
// adjacent slices k, k+1 are in one layer and the lookup reads one texel.
const char* kOpacityFS = R"(#version 330 core
in vec2 v_uv;
flat in int v_level;
in vec3 v_light;  // z: position in slices
in float v_alpha;
uniform sampler2D u_hair;
layout(location = 0) out vec4 o0;
layout(location = 1) out vec4 o1;
layout(location = 2) out vec4 o2;
layout(location = 3) out vec4 o3;
layout(location = 4) out vec4 o4;
void main() {
  ivec2 size = textureSize(u_hair, v_level);
  float a = texelFetch(u_hair, min(ivec2(v_uv * vec2(size)), size - 1), v_level).a * v_alpha;
  if (a < 1e-4) discard;
  vec4 z = vec4(v_light.z) - vec4(0.0, 1.0, 2.0, 3.0);
  o0 = a * clamp(0.0 - z, 0.0, 1.0);
  o1 = a * clamp(3.0 - z, 0.0, 1.0);
  o2 = a * clamp(6.0 - z, 0.0, 1.0);
  o3 = a * clamp(9.0 - z, 0.0, 1.0);
  o4 = a * clamp(12.0 - z, 0.0, 1.0);
}
)";

// The opacity lookup shared by the hair and the bodies (SPEC §7.2), per
// fragment, at light coordinates (s, t, z) interpolated from the vertices:
// z is the depth in slices, less the offset against self-shadowing.
// Omega(z) = sum_k Omega_k max(0, 1 - |z - k|): only the slices k and k+1
// around z weigh, and both are in layer l = k / 3 (one bilinear fetch).
// The slices are 8-bit (Omega clamped at 1, where exp(-kappa) leaves 0.4%
// of the light): llvmpipe reads and blends them much faster than floats.
// Written without branches or dynamic indexing (llvmpipe runs every path of
// a branch in its SIMD lanes).
const char* kShadowLookup = R"(
uniform sampler2DArray u_slices;  // 5 layers x RGBA: slices 3l .. 3l+3 in layer l
uniform float u_kappa;
uniform int u_shadows;
float transmittance(vec3 lc) {
  if (u_shadows == 0) return 1.0;
  float z = clamp(lc.z, 0.0, 15.0);
  int l = min(int(z) / 3, 4);
  vec4 a = texture(u_slices, vec3(lc.xy, float(l)));
  vec4 w = max(vec4(0.0), 1.0 - abs(z - (float(3 * l) + vec4(0.0, 1.0, 2.0, 3.0))));
  float omega = dot(a, w);
  // outside the maps (and in front of the first slice) nothing shadows
  bool inside = all(greaterThanEqual(lc.xy, vec2(0.0))) && all(lessThanEqual(lc.xy, vec2(1.0))) && lc.z > 0.0;
  return inside ? exp(-u_kappa * omega) : 1.0;
}
)";

const char* kHairShade = R"(
uniform vec3 u_light, u_color, u_spec_color;
uniform float u_kd, u_ks, u_shine, u_reflect, u_transmit, u_ambient;
out vec3 v_lit;
vec3 shade(vec3 T, vec3 world) {
  vec3 L = normalize(u_light);
  vec3 E = normalize(u_eye - world);
  float tl = dot(T, L), te = dot(T, E);
  float sin_tl = sqrt(max(0.0, 1.0 - tl * tl)), sin_te = sqrt(max(0.0, 1.0 - te * te));
  float diffuse = u_kd * sin_tl;
  float specular = u_ks * pow(max(0.0, sin_tl * sin_te - tl * te), u_shine);
  vec3 txl = cross(T, L), txe = cross(T, E);
  float denom = length(txl) * length(txe);
  float kd = denom > 1e-6 ? dot(txl, txe) / denom : 1.0;
  float f_dir = u_reflect * (1.0 + kd) * 0.5 + u_transmit * (1.0 - kd) * 0.5;
  v_lit = u_color * (f_dir * diffuse) + u_spec_color * (f_dir * specular);
  return u_color * u_ambient;
}
)";

const char* kHairFSBody = R"(
in vec2 v_uv;
flat in int v_level;
in vec3 v_light;
in float v_alpha;
in vec3 v_color;  // ambient
in vec3 v_lit;    // diffuse and specular before attenuation
uniform sampler2D u_hair;
out vec4 o_color;
void main() {
  ivec2 size = textureSize(u_hair, v_level);
  float a = texelFetch(u_hair, min(ivec2(v_uv * vec2(size)), size - 1), v_level).a * v_alpha;
  if (a < 2e-3) discard;
  o_color = vec4(v_color + v_lit * transmittance(v_light), min(a, 1.0));
}
)";

const char* kBodyVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model, u_view_proj, u_light_coords;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_light;
void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = mat3(u_model) * a_normal;
  // looked up a little off the surface, so the skin does not shadow itself
  v_light = (u_light_coords * vec4(w.xyz + 0.002 * normalize(v_normal), 1.0)).xyz;
  gl_Position = u_view_proj * w;
}
)";

const char* kBodyFSBody = R"(
in vec3 v_world;
in vec3 v_normal;
in vec3 v_light;
uniform vec3 u_eye, u_light, u_skin;
out vec4 o_color;
void main() {
  vec3 N = normalize(v_normal);
  vec3 L = normalize(u_light);
  vec3 E = normalize(u_eye - v_world);
  vec3 H = normalize(L + E);
  float light = transmittance(v_light);
  float lambert = max(0.0, dot(N, L));
  float spec = pow(max(0.0, dot(N, H)), 24.0) * 0.15;
  vec3 c = u_skin * (0.28 + 0.72 * lambert * light) + vec3(spec * light);
  o_color = vec4(c, 1.0);
}
)";

// Debug views: points coloured by a value, and lines.
const char* kDebugVS = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_value;
uniform mat4 u_view_proj;
uniform float u_point_size;
out float v_value;
void main() {
  v_value = a_value;
  gl_PointSize = u_point_size;
  gl_Position = u_view_proj * vec4(a_pos, 1.0);
}
)";
const char* kDebugFS = R"(#version 330 core
in float v_value;
uniform vec2 u_range;
uniform vec3 u_flat;
uniform int u_use_flat;
out vec4 o_color;
void main() {
  if (u_use_flat == 1) { o_color = vec4(u_flat, 1.0); return; }
  float t = clamp((v_value - u_range.x) / max(u_range.y - u_range.x, 1e-9), 0.0, 1.0);
  // blue -> cyan -> yellow -> red
  vec3 c = t < 0.5 ? mix(vec3(0.1, 0.2, 0.9), vec3(0.1, 0.9, 0.9), t * 2.0)
                   : mix(vec3(0.95, 0.9, 0.1), vec3(0.9, 0.1, 0.1), t * 2.0 - 1.0);
  o_color = vec4(c, 1.0);
}
)";

GLuint compile(GLenum type, const std::string& src) {
  const GLuint s = glCreateShader(type);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw RenderError(std::string("shader does not compile: ") + log);
  }
  return s;
}

GLuint program(const std::string& vs, const std::string& fs) {
  const GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw RenderError(std::string("shader program does not link: ") + log);
  }
  return p;
}

GLint loc(GLuint p, const char* name) { return glGetUniformLocation(p, name); }
void setMat(GLuint p, const char* n, const glm::mat4& m) { glUniformMatrix4fv(loc(p, n), 1, GL_FALSE, glm::value_ptr(m)); }
void setVec(GLuint p, const char* n, const glm::vec3& v) { glUniform3fv(loc(p, n), 1, glm::value_ptr(v)); }
void setF(GLuint p, const char* n, float v) { glUniform1f(loc(p, n), v); }
void setI(GLuint p, const char* n, int v) { glUniform1i(loc(p, n), v); }

struct Palette {
  glm::vec3 color, spec;
};
Palette palette(HairColor c) {
  switch (c) {
    case HairColor::Black: return {{0.05f, 0.045f, 0.04f}, {0.35f, 0.33f, 0.32f}};
    case HairColor::Brown: return {{0.32f, 0.19f, 0.10f}, {0.45f, 0.38f, 0.30f}};
    case HairColor::Blonde: return {{0.85f, 0.68f, 0.42f}, {0.6f, 0.55f, 0.45f}};
    case HairColor::Red: return {{0.55f, 0.16f, 0.06f}, {0.55f, 0.4f, 0.3f}};
  }
  return {{0.3f, 0.2f, 0.1f}, {0.4f, 0.4f, 0.4f}};
}

struct BodyMesh {
  GLuint vao = 0, vbo = 0, ibo = 0;
  GLsizei count = 0;
};

}  // namespace

// ---- camera -------------------------------------------------------------------
Camera Camera::preset(const std::string& name) {
  Camera c;
  if (name == "front") c.yaw_deg = 0;
  else if (name == "side") c.yaw_deg = 90;
  else if (name == "back") c.yaw_deg = 180;
  else if (name == "three-quarter") {
    c.yaw_deg = 35;
    c.pitch_deg = 12;
  } else
    throw RenderError("unknown camera preset \"" + name + "\" (use front, side, back or three-quarter)");
  return c;
}

glm::vec3 Camera::eye() const {
  const float yaw = glm::radians(yaw_deg), pitch = glm::radians(pitch_deg);
  return target + distance * glm::vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                       std::cos(yaw) * std::cos(pitch));
}

glm::mat4 Camera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 1, 0)); }

glm::mat4 Camera::projection(float aspect) const {
  return glm::perspective(glm::radians(fov_deg), aspect, near_plane, far_plane);
}

HairColor parseHairColor(const std::string& n) {
  if (n == "black") return HairColor::Black;
  if (n == "brown") return HairColor::Brown;
  if (n == "blonde") return HairColor::Blonde;
  if (n == "red") return HairColor::Red;
  throw RenderError("unknown hair colour \"" + n + "\" (use black, brown, blonde or red)");
}

DebugView parseDebugView(const std::string& n) {
  if (n == "none") return DebugView::None;
  if (n == "density") return DebugView::Density;
  if (n == "speed") return DebugView::Speed;
  if (n == "connections") return DebugView::Connections;
  if (n == "directions") return DebugView::Directions;
  throw RenderError("unknown debug view \"" + n + "\" (use none, density, speed, connections or directions)");
}

// ---- sorting and the texture ---------------------------------------------------
void sortBackToFront(const std::vector<float>& depth, std::vector<std::uint32_t>& order,
                     std::vector<std::uint32_t>& scratch) {
  const std::size_t n = depth.size();
  // Keys that sort ascending for descending depth: map float bits to an
  // order-preserving unsigned integer, then invert.
  std::vector<std::uint32_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t b;
    std::memcpy(&b, &depth[i], 4);
    b = (b & 0x80000000u) ? ~b : (b | 0x80000000u);
    key[i] = ~b;
  }
  order.resize(n);
  scratch.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
  for (int shift = 0; shift < 32; shift += 8) {
    std::array<std::uint32_t, 257> count{};
    for (std::uint32_t i : order) ++count[((key[i] >> shift) & 0xffu) + 1];
    for (int b = 0; b < 256; ++b) count[static_cast<std::size_t>(b) + 1] += count[static_cast<std::size_t>(b)];
    for (std::uint32_t i : order) scratch[count[(key[i] >> shift) & 0xffu]++] = i;
    order.swap(scratch);
  }
}

std::vector<std::uint8_t> makeHairTexture(int width, int height, std::uint64_t seed) {
  std::vector<float> alpha(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0f);
  std::uint64_t state = seed * 0x9e3779b97f4a7c15ULL + 1;
  auto next = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  const int strands = std::max(3, width / 2);
  for (int s = 0; s < strands; ++s) {
    const double x0 = 0.15 * width + 0.7 * width * next();
    const double wave = 0.6 * next(), phase = 6.283 * next();
    const double start = 0.15 * next(), end = 1.0 - 0.15 * next();
    const double strength = 0.7 + 0.3 * next();
    for (int y = 0; y < height; ++y) {
      const double v = (y + 0.5) / height;
      if (v < start || v > end) continue;
      const double along = std::sin(3.14159 * (v - start) / (end - start));  // fade at the ends
      const double cx = x0 + wave * std::sin(phase + 9.0 * v);
      for (int x = 0; x < width; ++x) {
        const double d = (x + 0.5 - cx) / 0.8;
        alpha[static_cast<std::size_t>(y * width + x)] +=
            static_cast<float>(strength * along * std::exp(-0.5 * d * d));
      }
    }
  }
  std::vector<std::uint8_t> rgba(alpha.size() * 4);
  for (std::size_t k = 0; k < alpha.size(); ++k) {
    rgba[4 * k + 0] = rgba[4 * k + 1] = rgba[4 * k + 2] = 255;
    rgba[4 * k + 3] = static_cast<std::uint8_t>(std::lround(255.0 * std::min(1.0f, alpha[k])));
  }
  return rgba;
}

// ---- the renderer ---------------------------------------------------------------
struct Renderer::Impl {
  GLuint hair_prog = 0, opacity_prog = 0, body_prog = 0, debug_prog = 0;
  GLuint hair_tex = 0;
  // Billboards as 4 vertices each (not instances: llvmpipe runs the vertex
  // stage once per instance, which cost more than the fragments at 20k
  // particles), drawn as 2 triangles each from a shared index buffer.
  GLuint quad_vao = 0, quad_vbo = 0, quad_ibo = 0;
  std::size_t quad_capacity = 0;  // billboards the index buffer holds
  GLuint debug_vao = 0, debug_vbo = 0;
  GLuint shadow_fbo = 0;
  GLuint slice_tex = 0;  // 2-D array, 5 layers of RGBA8: the 16 slices
  BodyMesh head, torso;
  std::vector<float> depth, quads, lines;
  std::vector<std::uint32_t> quad_indices;
  std::vector<std::uint32_t> order, scratch;

  ~Impl() {
    glDeleteProgram(hair_prog);
    glDeleteProgram(opacity_prog);
    glDeleteProgram(body_prog);
    glDeleteProgram(debug_prog);
    glDeleteTextures(1, &hair_tex);
    glDeleteTextures(1, &slice_tex);
    glDeleteFramebuffers(1, &shadow_fbo);
    glDeleteVertexArrays(1, &quad_vao);
    glDeleteBuffers(1, &quad_vbo);
    glDeleteBuffers(1, &quad_ibo);
    glDeleteVertexArrays(1, &debug_vao);
    glDeleteBuffers(1, &debug_vbo);
    for (BodyMesh* b : {&head, &torso}) {
      glDeleteVertexArrays(1, &b->vao);
      glDeleteBuffers(1, &b->vbo);
      glDeleteBuffers(1, &b->ibo);
    }
  }

  void upload(BodyMesh& b, const TriangleMesh* mesh) {
    if (!b.vao) {
      glGenVertexArrays(1, &b.vao);
      glGenBuffers(1, &b.vbo);
      glGenBuffers(1, &b.ibo);
    }
    b.count = 0;
    if (!mesh) return;
    const auto normals = vertexNormals(*mesh);
    std::vector<float> data;
    data.reserve(mesh->vertices.size() * 6);
    for (std::size_t v = 0; v < mesh->vertices.size(); ++v)
      data.insert(data.end(), {mesh->vertices[v].x, mesh->vertices[v].y, mesh->vertices[v].z, normals[v].x,
                               normals[v].y, normals[v].z});
    glBindVertexArray(b.vao);
    glBindBuffer(GL_ARRAY_BUFFER, b.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh->triangles.size() * 12),
                 mesh->triangles.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 24, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 24, reinterpret_cast<void*>(12));
    glBindVertexArray(0);
    b.count = static_cast<GLsizei>(mesh->triangles.size() * 3);
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  if (!version) throw RenderError("no current OpenGL context");
  Impl& r = *impl_;
  const std::string frag_head = "#version 330 core\n";
  r.hair_prog = program(std::string("#version 330 core\n#define SHADE 1\nuniform vec3 u_eye;\n") +
                            kHairShade + kBillboardVS,
                        frag_head + kShadowLookup + kHairFSBody);
  r.opacity_prog = program(std::string("#version 330 core\nuniform vec3 u_eye;\n") + kBillboardVS, kOpacityFS);
  r.body_prog = program(kBodyVS, frag_head + kShadowLookup + kBodyFSBody);
  r.debug_prog = program(kDebugVS, kDebugFS);

  // The hair-strand texture, mipmapped (SPEC §7.1).
  const int tw = kStrandWidth, th = kStrandHeight;
  static_assert((1 << kStrandLevels) == kStrandWidth && kStrandHeight >= kStrandWidth);
  const auto pixels = makeHairTexture(tw, th);
  glGenTextures(1, &r.hair_tex);
  glBindTexture(GL_TEXTURE_2D, r.hair_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, tw, th, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

  // Billboard vertices: position, direction, value (the same for the 4
  // corners; the vertex shader takes the corner from gl_VertexID).
  glGenVertexArrays(1, &r.quad_vao);
  glGenBuffers(1, &r.quad_vbo);
  glGenBuffers(1, &r.quad_ibo);
  glBindVertexArray(r.quad_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r.quad_vbo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r.quad_ibo);
  for (GLuint a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 28, nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 28, reinterpret_cast<void*>(12));
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 28, reinterpret_cast<void*>(24));
  glBindVertexArray(0);

  glGenVertexArrays(1, &r.debug_vao);
  glGenBuffers(1, &r.debug_vbo);
  glBindVertexArray(r.debug_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r.debug_vbo);
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 16, nullptr);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 16, reinterpret_cast<void*>(12));
  glBindVertexArray(0);

  // 16 opacity slices in 5 RGBA targets, neighbouring layers sharing a slice (SPEC §7.2).
  glGenFramebuffers(1, &r.shadow_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, r.shadow_fbo);
  glGenTextures(1, &r.slice_tex);
  glBindTexture(GL_TEXTURE_2D_ARRAY, r.slice_tex);
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, kShadowSize, kShadowSize, kSliceLayers, 0, GL_RGBA,
               GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  GLint max_buffers = 0;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_buffers);
  if (max_buffers < kSliceLayers)
    throw RenderError("the OpenGL implementation draws into " + std::to_string(max_buffers) +
                      " targets at once; the opacity maps need " + std::to_string(kSliceLayers));
  GLenum bufs[kSliceLayers];
  for (int k = 0; k < kSliceLayers; ++k) {
    bufs[k] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, bufs[k], r.slice_tex, 0, k);
  }
  glDrawBuffers(kSliceLayers, bufs);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the opacity-map framebuffer is incomplete");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

Renderer::~Renderer() = default;

void Renderer::setBodies(const TriangleMesh* head, const TriangleMesh* torso) {
  impl_->upload(impl_->head, head);
  impl_->upload(impl_->torso, torso);
}

void Renderer::render(const FrameInput& in, const Camera& camera, const RenderSettings& st, int width,
                      int height) {
  Impl& r = *impl_;
  times_ = {};
  const std::size_t n = in.position.size();
  if (in.direction.size() != n) throw RenderError("positions and directions differ in number");
  GLint target_fbo = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &target_fbo);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(1, height));
  const glm::mat4 view = camera.view(), proj = camera.projection(aspect), vp = proj * view;
  const glm::vec3 eye = camera.eye();
  const glm::vec3 light = glm::normalize(st.light_direction);
  const float bw = st.billboard_width * in.spacing, bl = st.billboard_length * in.spacing;

  // ---- the light's frame: orthographic along -light around the hair ----
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : in.position) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (n == 0) lo = hi = camera.target;
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo) + bl;
  const glm::vec3 up = std::abs(light.y) < 0.95f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::mat4 light_view = glm::lookAt(centre + light * (radius + 1.0f), centre, up);
  const glm::mat4 light_proj = glm::ortho(-radius, radius, -radius, radius, 0.01f, 2.0f * radius + 2.0f);
  float zmin = INFINITY, zmax = -INFINITY;
  for (const auto& p : in.position) {
    const float z = -(light_view * glm::vec4(p, 1.0f)).z;
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  if (n == 0) zmin = zmax = 1.0f;
  zmin -= 0.5f * bl;
  zmax += 0.5f * bl;
  const float dz = std::max(1e-4f, (zmax - zmin) / static_cast<float>(kSlices - 1));

  // ---- back-to-front order (SPEC §7.1), O(N) ----
  auto t0 = Clock::now();
  r.depth.resize(n);
  for (std::size_t i = 0; i < n; ++i) r.depth[i] = -(view * glm::vec4(in.position[i], 1.0f)).z;
  sortBackToFront(r.depth, r.order, r.scratch);
  times_.sort = since(t0);

  t0 = Clock::now();
  const auto& quad_values = st.debug == DebugView::Density ? in.density : in.speed;
  r.quads.resize(n * 4 * 7);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = r.order[k];
    const float v[7] = {in.position[i].x,  in.position[i].y,  in.position[i].z, in.direction[i].x,
                        in.direction[i].y, in.direction[i].z,
                        i < quad_values.size() ? quad_values[i] : 0.0f};
    for (int corner = 0; corner < 4; ++corner) std::memcpy(&r.quads[(k * 4 + corner) * 7], v, sizeof v);
  }
  glBindVertexArray(r.quad_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r.quad_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(r.quads.size() * sizeof(float)), r.quads.data(),
               GL_STREAM_DRAW);
  if (r.quad_capacity < n) {
    r.quad_capacity = std::max<std::size_t>(n, 2 * r.quad_capacity);
    r.quad_indices.resize(r.quad_capacity * 6);
    for (std::size_t k = 0; k < r.quad_capacity; ++k) {
      const auto b = static_cast<std::uint32_t>(4 * k);
      const std::uint32_t tri[6] = {b, b + 1, b + 2, b + 2, b + 1, b + 3};  // the strip 0 1 2 3
      std::memcpy(&r.quad_indices[6 * k], tri, sizeof tri);
    }
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(r.quad_indices.size() * sizeof(std::uint32_t)),
                 r.quad_indices.data(), GL_STATIC_DRAW);
  }
  glBindVertexArray(0);
  times_.upload = since(t0);

  auto billboardUniforms = [&](GLuint p) {
    setF(p, "u_width", bw);
    setF(p, "u_length", bl);
    setF(p, "u_max_boost", st.max_opacity_boost);
    setF(p, "u_opacity", st.hair_opacity);
    setF(p, "u_strand_width", static_cast<float>(kStrandWidth));
    setF(p, "u_strand_max_level", static_cast<float>(kStrandLevels));
  };
  // world -> (s, t, depth in slices - offset) for the lookups, and without
  // the offset for the light pass: one affine map (the light is orthographic)
  auto lightCoords = [&](float offset) {
    glm::mat4 a = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.5f, 0.0f)) *
                  glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 0.5f, 1.0f)) * light_proj;
    for (int c = 0; c < 4; ++c) a[c][2] = 0.0f;  // row 2: (-z_view - zmin) / dz - offset
    a[2][2] = -1.0f / dz;
    a[3][2] = -zmin / dz - offset;
    return a * light_view;
  };
  const glm::mat4 lookup_coords = lightCoords(st.shadow_offset), slice_coords = lightCoords(0.0f);
  auto shadowUniforms = [&](GLuint p) {
    setMat(p, "u_light_coords", lookup_coords);
    setF(p, "u_kappa", st.kappa);
    setI(p, "u_shadows", st.shadows ? 1 : 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_ARRAY, r.slice_tex);
    setI(p, "u_slices", 1);
    glActiveTexture(GL_TEXTURE0);
  };

  // ---- pass 1: opacity slices from the light (SPEC §7.2) ----
  t0 = Clock::now();
  glBindFramebuffer(GL_FRAMEBUFFER, r.shadow_fbo);
  glViewport(0, 0, kShadowSize, kShadowSize);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  if (st.shadows && n > 0) {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(r.opacity_prog);
    setMat(r.opacity_prog, "u_view_proj", light_proj * light_view);
    setMat(r.opacity_prog, "u_light_coords", slice_coords);
    setVec(r.opacity_prog, "u_proj_dir", -light);
    setI(r.opacity_prog, "u_ortho", 1);
    setF(r.opacity_prog, "u_pixel_scale", static_cast<float>(kShadowSize) / (2.0f * radius));
    billboardUniforms(r.opacity_prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, r.hair_tex);
    setI(r.opacity_prog, "u_hair", 0);
    glBindVertexArray(r.quad_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * n), GL_UNSIGNED_INT, nullptr);
  }
  glFinish();
  times_.light_pass = since(t0);

  // ---- pass 2: the camera ----
  t0 = Clock::now();
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(target_fbo));
  glViewport(0, 0, width, height);
  glClearColor(st.background.r, st.background.g, st.background.b, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  // bodies
  glUseProgram(r.body_prog);
  setMat(r.body_prog, "u_view_proj", vp);
  setVec(r.body_prog, "u_eye", eye);
  setVec(r.body_prog, "u_light", light);
  setVec(r.body_prog, "u_skin", glm::vec3(0.86f, 0.68f, 0.58f));
  shadowUniforms(r.body_prog);
  for (const auto& [mesh, model] : {std::pair{&r.head, in.head_pose}, std::pair{&r.torso, glm::mat4(1.0f)}}) {
    if (mesh->count == 0) continue;
    setMat(r.body_prog, "u_model", model);
    glBindVertexArray(mesh->vao);
    glDrawElements(GL_TRIANGLES, mesh->count, GL_UNSIGNED_INT, nullptr);
  }
  if (st.debug == DebugView::None) {
    // hair: blended back to front, tested against the bodies' depth
    glEnable(GL_BLEND);
    // "over" for colour; the framebuffer's alpha stays opaque
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glDepthMask(GL_FALSE);
    glUseProgram(r.hair_prog);
    setMat(r.hair_prog, "u_view_proj", vp);
    setVec(r.hair_prog, "u_eye", eye);
    setI(r.hair_prog, "u_ortho", 0);
    setF(r.hair_prog, "u_pixel_scale",
         static_cast<float>(height) / (2.0f * std::tan(0.5f * glm::radians(camera.fov_deg))));
    billboardUniforms(r.hair_prog);
    const Palette pal = palette(st.color);
    setVec(r.hair_prog, "u_light", light);
    setVec(r.hair_prog, "u_color", pal.color);
    setVec(r.hair_prog, "u_spec_color", pal.spec);
    setF(r.hair_prog, "u_kd", 1.0f);
    setF(r.hair_prog, "u_ks", 0.6f);
    setF(r.hair_prog, "u_shine", 40.0f);
    setF(r.hair_prog, "u_reflect", 1.0f);
    setF(r.hair_prog, "u_transmit", 0.45f);
    setF(r.hair_prog, "u_ambient", 0.22f);
    shadowUniforms(r.hair_prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, r.hair_tex);
    setI(r.hair_prog, "u_hair", 0);
    glBindVertexArray(r.quad_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * n), GL_UNSIGNED_INT, nullptr);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  } else {
    // debug views
    glUseProgram(r.debug_prog);
    setMat(r.debug_prog, "u_view_proj", vp);
    r.lines.clear();
    GLenum mode = GL_POINTS;
    if (st.debug == DebugView::Density || st.debug == DebugView::Speed) {
      const auto& values = st.debug == DebugView::Density ? in.density : in.speed;
      float vmin = INFINITY, vmax = -INFINITY;
      for (std::size_t i = 0; i < n; ++i) {
        const float v = i < values.size() ? values[i] : 0.0f;
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
        r.lines.insert(r.lines.end(), {in.position[i].x, in.position[i].y, in.position[i].z, v});
      }
      glUniform2f(loc(r.debug_prog, "u_range"), vmin, vmax);
      setI(r.debug_prog, "u_use_flat", 0);
      setF(r.debug_prog, "u_point_size", 3.0f);
      glEnable(GL_PROGRAM_POINT_SIZE);
    } else if (st.debug == DebugView::Connections) {
      for (std::size_t k = 0; k + 1 < in.connections.size(); k += 2) {
        const glm::vec3 a = in.position[in.connections[k]], b = in.position[in.connections[k + 1]];
        r.lines.insert(r.lines.end(), {a.x, a.y, a.z, 0.0f, b.x, b.y, b.z, 0.0f});
      }
      setI(r.debug_prog, "u_use_flat", 1);
      setVec(r.debug_prog, "u_flat", glm::vec3(0.15f, 0.35f, 0.8f));
      mode = GL_LINES;
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 a = in.position[i], b = a + 1.5f * in.spacing * in.direction[i];
        r.lines.insert(r.lines.end(), {a.x, a.y, a.z, 0.0f, b.x, b.y, b.z, 0.0f});
      }
      setI(r.debug_prog, "u_use_flat", 1);
      setVec(r.debug_prog, "u_flat", glm::vec3(0.7f, 0.2f, 0.1f));
      mode = GL_LINES;
    }
    glBindVertexArray(r.debug_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r.debug_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(r.lines.size() * sizeof(float)), r.lines.data(),
                 GL_STREAM_DRAW);
    glDrawArrays(mode, 0, static_cast<GLsizei>(r.lines.size() / 4));
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glFinish();
  times_.camera_pass = since(t0);
}

}  // namespace loosehair::render
