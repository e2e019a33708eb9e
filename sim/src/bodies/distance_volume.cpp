// Sampling a body's signed distance on a grid (loosehair/distance_volume.hpp).
#include "loosehair/distance_volume.hpp"

#include "util/parallel.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {

float DistanceVolume::sample(const glm::vec3& p) const {
  const glm::vec3 g = glm::clamp((p - lower) / voxel, glm::vec3(0.0f), glm::vec3(dims - 1));
  const glm::ivec3 c = glm::min(glm::ivec3(glm::floor(g)), glm::max(dims - 2, glm::ivec3(0)));
  const glm::vec3 f = g - glm::vec3(c);
  auto v = [&](int di, int dj, int dk) {
    return at(std::min(c.x + di, dims.x - 1), std::min(c.y + dj, dims.y - 1), std::min(c.z + dk, dims.z - 1));
  };
  const float x00 = v(0, 0, 0) + f.x * (v(1, 0, 0) - v(0, 0, 0)), x10 = v(0, 1, 0) + f.x * (v(1, 1, 0) - v(0, 1, 0));
  const float x01 = v(0, 0, 1) + f.x * (v(1, 0, 1) - v(0, 0, 1)), x11 = v(0, 1, 1) + f.x * (v(1, 1, 1) - v(0, 1, 1));
  const float y0 = x00 + f.y * (x10 - x00), y1 = x01 + f.y * (x11 - x01);
  return y0 + f.z * (y1 - y0);
}

DistanceVolume sampleDistanceVolume(const Body& body, const DistanceVolumeOptions& options, int threads) {
  if (!(options.voxel > 0.0f) || !std::isfinite(options.voxel))
    throw std::invalid_argument("distance volume: voxel " + std::to_string(options.voxel) + " is not positive");
  if (options.max_points < 8 || options.max_points > 1024)
    throw std::invalid_argument("distance volume: max_points " + std::to_string(options.max_points) +
                                " is outside 8..1024");
  if (!(options.exact_voxels >= 2.0f) || !std::isfinite(options.exact_voxels))
    throw std::invalid_argument("distance volume: exact_voxels " + std::to_string(options.exact_voxels) +
                                " is below 2");
  glm::vec3 lo, hi;
  if (!body.bounds(lo, hi) || !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) ||
      !std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z))
    throw std::invalid_argument("distance volume: the body has no bounding box");
  DistanceVolume v;
  // a margin of the exact band and two voxels, so that every point nearer
  // the surface than the band lies inside the grid
  const glm::vec3 extent = hi - lo;
  const float longest = std::max({extent.x, extent.y, extent.z});
  const float pad = options.exact_voxels + 2.0f;
  v.voxel = std::max(options.voxel, longest / (static_cast<float>(options.max_points) - 1.0f - 2.0f * pad));
  v.exact_band = options.exact_voxels * v.voxel;
  v.lower = lo - pad * v.voxel;
  v.dims = glm::ivec3(glm::ceil((extent + 2.0f * pad * v.voxel) / v.voxel)) + 1;
  v.dims = glm::clamp(v.dims, glm::ivec3(2), glm::ivec3(options.max_points));
  const std::size_t nx = static_cast<std::size_t>(v.dims.x), ny = static_cast<std::size_t>(v.dims.y);
  const std::size_t nz = static_cast<std::size_t>(v.dims.z);
  v.values.resize(nx * ny * nz);
  const float rough_error = body.roughError();
  // one row of x at a time: the body's fast approximation first where it
  // has one, then the exact distance where that may lie within the band
  parallel::forEachDynamic(threads, ny * nz, [&](std::size_t row) {
    const std::size_t j = row % ny, k = row / ny;
    std::vector<glm::vec3> p(nx), n(nx), q;
    std::vector<float> phi(nx), exact;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < nx; ++i)
      p[i] = v.lower + v.voxel * glm::vec3(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k));
    float* out = &v.values[row * nx];
    if (rough_error < 0.0f) {
      body.signedDistanceBelow(p.data(), nx, v.exact_band, out, n.data());
      return;
    }
    body.roughDistanceBelow(p.data(), nx, v.exact_band + rough_error, phi.data(), n.data());
    for (std::size_t i = 0; i < nx; ++i) {
      out[i] = phi[i];
      if (phi[i] < v.exact_band + rough_error && phi[i] > -(v.exact_band + rough_error)) which.push_back(i);
    }
    if (which.empty()) return;
    q.resize(which.size());
    exact.resize(which.size());
    for (std::size_t m = 0; m < which.size(); ++m) q[m] = p[which[m]];
    body.signedDistanceBelow(q.data(), q.size(), v.exact_band, exact.data(), n.data());
    for (std::size_t m = 0; m < which.size(); ++m) out[which[m]] = exact[m];
  });
  for (float value : v.values)
    if (!std::isfinite(value)) throw std::invalid_argument("distance volume: the body gave a non-finite distance");
  return v;
}

}  // namespace loosehair
