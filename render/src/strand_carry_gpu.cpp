// Carrying the strands on the GPU (loosehair/render/strand_carry_gpu.hpp).
#include "loosehair/render/strand_carry_gpu.hpp"

#include "gl_handles.hpp"
#include "gl_program.hpp"
#include "strand_pass.hpp"
#include "loosehair/render/renderer.hpp"
#include "loosehair/render/shaders.hpp"

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <cstdint>
#include <span>
#include <unordered_map>

namespace loosehair::render {

namespace {

constexpr GLuint kLocalSize = 64;  // strand_carry.comp's local_size_x
// the storage buffers, by their binding points in strand_carry.comp
enum Buffer : GLuint {
  kMotions,
  kBindIndex,
  kBindWeight,
  kRestPoints,
  kDetail,
  kStrandFirst,
  kOutPoints,
  kScratch,
  kVolumes,
  kBuffers
};
// rounds of (push out, length limit), as the CPU carry's rough rounds
constexpr int kPushRounds = 3;

template <class T>
void storage(GLuint buffer, std::span<const T> data, GLenum usage) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, data.size()) * sizeof(T)),
               data.empty() ? nullptr : data.data(), usage);
}

}  // namespace

bool gpuStrandCarrySupported(std::string* why) {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 43) {
    if (why)
      *why = "OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " has no compute shaders (4.3 does)";
    return false;
  }
  if (!gl::functions.DispatchCompute || !gl::functions.MemoryBarrier) {
    if (why) *why = "this OpenGL does not give glDispatchCompute";
    return false;
  }
  return true;
}

struct GpuStrandCarry::Impl {
  const StrandField* field = nullptr;
  GlProgram program;
  GlBuffer buffers[kBuffers];
  std::size_t strands = 0, points = 0;
  int per_strand = 0;
  float mean_length = 0.0f;
  DistanceVolumeOptions volume_options;
  struct Volume {
    std::shared_ptr<const Body> body;  // kept alive while its volume is
    GLint first = 0;                   // its first value in `values`
    glm::vec3 lower{0.0f};
    float voxel = 0.0f;
    glm::ivec3 dims{0};
  };
  std::unordered_map<const Body*, Volume> volumes;
  std::vector<float> values;  // every volume's, uploaded to buffers[kVolumes]
  double volume_seconds = 0.0;
  std::vector<glm::mat3> rot;
  std::vector<glm::vec3> shift;
  std::vector<glm::vec4> motion;

  // the volume of `body`, sampled the first time it comes (`added` set)
  const Volume& volumeOf(const std::shared_ptr<const Body>& body, int threads, bool& added) {
    auto it = volumes.find(body.get());
    if (it != volumes.end()) return it->second;
    const auto t0 = std::chrono::steady_clock::now();
    DistanceVolume v;
    try {
      v = sampleDistanceVolume(*body, volume_options, threads);
    } catch (const std::invalid_argument& e) {
      throw RenderError(std::string("strands on the GPU: ") + e.what());
    }
    if (values.size() + v.values.size() > static_cast<std::size_t>(INT32_MAX))
      throw RenderError("strands on the GPU: the bodies' distance volumes are too large");
    Volume out;
    out.body = body;
    out.first = static_cast<GLint>(values.size());
    out.lower = v.lower;
    out.voxel = v.voxel;
    out.dims = v.dims;
    values.insert(values.end(), v.values.begin(), v.values.end());
    added = true;
    volume_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return volumes.emplace(body.get(), out).first->second;
  }
};

GpuStrandCarry::GpuStrandCarry(const StrandField& field, const DistanceVolumeOptions& volumes)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!gpuStrandCarrySupported(&why)) throw RenderError("strands on the GPU: " + why);
  Impl& r = *impl_;
  r.field = &field;
  r.volume_options = volumes;
  r.program.reset(computeProgram("#version 430 core\n#define MAX_BODIES " + std::to_string(kMaxBodies) + "\n" +
                                 shaders::strand_carry_comp));
  for (GlBuffer& b : r.buffers) b = GlBuffer::make();
  const StrandSet& rest = field.rest();
  r.strands = rest.size();
  r.points = rest.points.size();
  StrandPass::checkPointCount(r.points);
  r.per_strand = r.strands > 0 ? static_cast<int>(rest.first[1] - rest.first[0]) : 0;
  for (std::size_t s = 0; s < r.strands; ++s)
    if (static_cast<int>(rest.first[s + 1] - rest.first[s]) != r.per_strand) r.per_strand = 0;
  const std::span<const float> seg = field.restSegmentLengths();
  double total = 0.0;
  std::vector<glm::vec4> rest4(r.points), detail4(r.points);
  const std::span<const glm::vec3> detail = field.restDetail();
  for (std::size_t q = 0; q < r.points; ++q) {
    rest4[q] = glm::vec4(rest.points[q], seg[q]);
    detail4[q] = glm::vec4(detail[q], 0.0f);
    total += seg[q];
  }
  r.mean_length = r.strands > 0 ? static_cast<float>(total / static_cast<double>(r.strands)) : 0.0f;
  storage(r.buffers[kBindIndex].get(), field.bindIndices(), GL_STATIC_DRAW);
  storage(r.buffers[kBindWeight].get(), field.bindWeights(), GL_STATIC_DRAW);
  storage<glm::vec4>(r.buffers[kRestPoints].get(), rest4, GL_STATIC_DRAW);
  storage<glm::vec4>(r.buffers[kDetail].get(), detail4, GL_STATIC_DRAW);
  storage<std::uint32_t>(r.buffers[kStrandFirst].get(), rest.first, GL_STATIC_DRAW);
  storage<glm::vec4>(r.buffers[kOutPoints].get(), std::vector<glm::vec4>(r.points, glm::vec4(0.0f)), GL_DYNAMIC_COPY);
  storage<float>(r.buffers[kVolumes].get(), r.values, GL_STATIC_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r.buffers[kScratch].get());
  glBufferData(GL_SHADER_STORAGE_BUFFER,
               static_cast<GLsizeiptr>(std::max<std::size_t>(1, 2 * r.points) * sizeof(glm::vec4)), nullptr,
               GL_DYNAMIC_COPY);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

GpuStrandCarry::~GpuStrandCarry() = default;

void GpuStrandCarry::carry(std::span<const glm::vec3> positions, std::span<const glm::vec3> directions,
                           const std::vector<BodyPlacement>& bodies, const glm::mat4& head_to_world, int threads,
                           std::size_t stride) {
  stride = std::max<std::size_t>(1, stride);
  Impl& r = *impl_;
  if (bodies.size() > static_cast<std::size_t>(kMaxBodies))
    throw RenderError("strands on the GPU: " + std::to_string(bodies.size()) + " bodies, more than " +
                      std::to_string(kMaxBodies));
  std::vector<const Impl::Volume*> volume(bodies.size());
  bool added = false;
  for (std::size_t b = 0; b < bodies.size(); ++b) volume[b] = &r.volumeOf(bodies[b].body, threads, added);
  if (added) storage<float>(r.buffers[kVolumes].get(), r.values, GL_STATIC_DRAW);
  r.field->particleMotions(positions, directions, r.rot, r.shift, threads);
  r.motion.resize(3 * r.rot.size());
  for (std::size_t i = 0; i < r.rot.size(); ++i)
    for (int c = 0; c < 3; ++c) r.motion[3 * i + static_cast<std::size_t>(c)] = glm::vec4(r.rot[i][c], r.shift[i][c]);
  storage<glm::vec4>(r.buffers[kMotions].get(), r.motion, GL_STREAM_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);

  const GLuint p = r.program.get();
  glUseProgram(p);
  glUniform1ui(loc(p, "u_strands"), static_cast<GLuint>(r.strands));
  glUniform1ui(loc(p, "u_stride"), static_cast<GLuint>(std::min<std::size_t>(stride, r.strands + 1)));
  setI(p, "u_carriers", r.field->carriersPerPoint());
  setF(p, "u_clearance", r.field->options().clearance);
  setF(p, "u_tolerance", r.field->options().length_tolerance);
  setMat(p, "u_head", head_to_world);
  const std::span<const float> taps = StrandField::smoothingTaps();
  setI(p, "u_smooth_half", StrandField::smoothingHalfWidth());
  glUniform1fv(loc(p, "u_smooth_taps"), static_cast<GLsizei>(std::min<std::size_t>(8, taps.size())), taps.data());
  setI(p, "u_rounds", kPushRounds);
  setI(p, "u_bodies", static_cast<int>(bodies.size()));
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Impl::Volume& v = *volume[b];
    char name[64];
    auto uniform = [&](const char* base) {
      std::snprintf(name, sizeof name, "%s[%zu]", base, b);
      return loc(p, name);
    };
    // grid coordinates: (m p + d - lower) / voxel
    glm::mat4 to(glm::mat3(bodies[b].m) / v.voxel);
    to[3] = glm::vec4((bodies[b].d - v.lower) / v.voxel, 1.0f);
    glUniformMatrix4fv(uniform("u_to_grid"), 1, GL_FALSE, glm::value_ptr(to));
    glUniform1i(uniform("u_volume_first"), v.first);
    glUniform3i(uniform("u_volume_dims"), v.dims.x, v.dims.y, v.dims.z);
    const glm::mat3 g = glm::transpose(bodies[b].m) * (1.0f / v.voxel);
    glUniformMatrix3fv(uniform("u_gradient_to_head"), 1, GL_FALSE, glm::value_ptr(g));
  }
  for (GLuint i = 0; i < kBuffers; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, r.buffers[i].get());
  const std::size_t carried = (r.strands + stride - 1) / stride;
  const GLuint groups = static_cast<GLuint>((carried + kLocalSize - 1) / kLocalSize);
  if (groups > 0) glDispatchCompute(groups, 1, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  for (GLuint i = 0; i < kBuffers; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, 0);
  glUseProgram(0);
}

unsigned GpuStrandCarry::buffer() const { return impl_->buffers[kOutPoints].get(); }
std::size_t GpuStrandCarry::points() const { return impl_->points; }
int GpuStrandCarry::pointsPerStrand() const { return impl_->per_strand; }
float GpuStrandCarry::meanLength() const { return impl_->mean_length; }
double GpuStrandCarry::volumeSeconds() const { return impl_->volume_seconds; }
void GpuStrandCarry::wait() const { glFinish(); }

void GpuStrandCarry::readBack(std::vector<glm::vec3>& out) const {
  std::vector<glm::vec4> v(impl_->points);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, impl_->buffers[kOutPoints].get());
  if (!v.empty())
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(v.size() * sizeof(glm::vec4)), v.data());
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  out.resize(v.size());
  for (std::size_t q = 0; q < v.size(); ++q) out[q] = glm::vec3(v[q]);
}

}  // namespace loosehair::render
