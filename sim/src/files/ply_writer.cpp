#include "loosehair/ply_writer.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/solver.hpp"

#include <bit>
#include <cstring>
#include <vector>

namespace loosehair {

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian machine");

namespace {

void writeWhole(const std::string& path, const std::string& header, const std::vector<unsigned char>& body) {
  writeFileAtomically(path, {header, std::string_view(reinterpret_cast<const char*>(body.data()), body.size())});
}

}  // namespace

void writeAirPly(const std::string& path, const Solver& solver) {
  std::vector<glm::vec3> x, v;
  solver.worldAirPositions(x);
  solver.worldAirVelocities(v);
  const auto density = solver.airDensity();
  const std::size_t n = x.size();
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment loosehair air, time " +
                       std::to_string(solver.time()) + " s\nelement vertex " + std::to_string(n) + "\n";
  for (const char* name : {"x", "y", "z", "vx", "vy", "vz", "density"})
    header += std::string("property float ") + name + "\n";
  header += "end_header\n";
  constexpr std::size_t kRecord = 7 * sizeof(float);
  std::vector<unsigned char> body(n * kRecord);
  for (std::size_t a = 0; a < n; ++a) {
    const float f[7] = {x[a].x, x[a].y, x[a].z, v[a].x, v[a].y, v[a].z, a < density.size() ? density[a] : 0.0f};
    std::memcpy(body.data() + a * kRecord, f, sizeof f);
  }
  writeWhole(path, header, body);
}

void writeParticlePly(const std::string& path, const Solver& solver) {
  std::vector<glm::vec3> x, t, v, r;
  solver.worldPositions(x);
  solver.worldDirections(t);
  solver.worldVelocities(v);
  solver.worldRootPoints(r);
  const Particles& p = solver.particles();
  const auto density = solver.density();
  const std::size_t n = p.size();

  std::string header = "ply\nformat binary_little_endian 1.0\ncomment loosehair frame, time " +
                       std::to_string(solver.time()) + " s\nelement vertex " + std::to_string(n) + "\n";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "vx", "vy", "vz", "u", "v", "s", "rx", "ry", "rz"})
    header += std::string("property float ") + name + "\n";
  header += "property uchar root\nproperty float density\nend_header\n";

  constexpr std::size_t kRecord = 15 * sizeof(float) + 1 + sizeof(float);
  std::vector<unsigned char> body(n * kRecord);
  for (std::size_t i = 0; i < n; ++i) {
    unsigned char* rec = body.data() + i * kRecord;
    const float f[15] = {x[i].x, x[i].y,    x[i].z,    t[i].x,          t[i].y, t[i].z, v[i].x, v[i].y,
                         v[i].z, p.uv[i].x, p.uv[i].y, p.arc_length[i], r[i].x, r[i].y, r[i].z};
    std::memcpy(rec, f, sizeof f);
    rec[sizeof f] = p.is_root[i];
    const float d = i < density.size() ? density[i] : 0.0f;
    std::memcpy(rec + sizeof f + 1, &d, sizeof d);
  }

  writeWhole(path, header, body);
}

}  // namespace loosehair
