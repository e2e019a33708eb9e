#include "init/mesh_scalp.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace loosehair {
namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; }
std::uint64_t undirectedKey(std::uint32_t a, std::uint32_t b) { return edgeKey(std::min(a, b), std::max(a, b)); }

double meanEdgeLength(const TriangleMesh& m) {
  double sum = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) sum += glm::length(m.corner(t, k) - m.corner(t, (k + 1) % 3));
  return sum / (3.0 * static_cast<double>(std::max<std::size_t>(1, m.triangles.size())));
}

// Splits every triangle into four (flat), until the mean edge is short
// enough for the trimming curves to follow edges closely.
TriangleMesh refined(const TriangleMesh& in, double max_mean_edge) {
  TriangleMesh m = in;
  for (int round = 0; round < 6 && meanEdgeLength(m) > max_mean_edge; ++round) {
    std::unordered_map<std::uint64_t, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = undirectedKey(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back(0.5f * (m.vertices[a] + m.vertices[b]));
      const auto idx = static_cast<std::uint32_t>(m.vertices.size() - 1);
      mid.emplace(key, idx);
      return idx;
    };
    std::vector<glm::u32vec3> g;
    g.reserve(4 * m.triangles.size());
    for (const auto& t : m.triangles) {
      const std::uint32_t a = midpoint(t.x, t.y), b = midpoint(t.y, t.z), c = midpoint(t.z, t.x);
      g.emplace_back(t.x, a, c);
      g.emplace_back(t.y, b, a);
      g.emplace_back(t.z, c, b);
      g.emplace_back(a, b, c);
    }
    m.triangles = std::move(g);
  }
  return m;
}

// Vertex adjacency (CSR) with edge lengths.
struct Graph {
  std::vector<std::uint32_t> start, next;
  std::vector<float> length;
  explicit Graph(const TriangleMesh& m) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> e;
    e.reserve(6 * m.triangles.size());
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) {
        e.emplace_back(t[k], t[(k + 1) % 3]);
        e.emplace_back(t[(k + 1) % 3], t[k]);
      }
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    start.assign(m.vertices.size() + 1, 0);
    for (const auto& [a, b] : e) ++start[a + 1];
    for (std::size_t v = 0; v < m.vertices.size(); ++v) start[v + 1] += start[v];
    next.resize(e.size());
    length.resize(e.size());
    for (std::size_t k = 0; k < e.size(); ++k) {
      next[k] = e[k].second;
      length[k] = glm::length(m.vertices[e[k].first] - m.vertices[e[k].second]);
    }
  }
  // Shortest edge path from a to b (both included).
  std::vector<std::uint32_t> path(std::uint32_t a, std::uint32_t b, std::vector<float>& dist,
                                  std::vector<std::uint32_t>& prev) const {
    if (a == b) return {a};
    std::vector<std::uint32_t> touched;
    using Item = std::pair<float, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    dist[a] = 0;
    touched.push_back(a);
    q.emplace(0.0f, a);
    bool found = false;
    while (!q.empty()) {
      auto [d, v] = q.top();
      q.pop();
      if (d > dist[v]) continue;
      if (v == b) {
        found = true;
        break;
      }
      for (std::uint32_t k = start[v]; k < start[v + 1]; ++k) {
        const std::uint32_t w = next[k];
        const float nd = d + length[k];
        if (nd < dist[w]) {
          if (dist[w] == std::numeric_limits<float>::infinity()) touched.push_back(w);
          dist[w] = nd;
          prev[w] = v;
          q.emplace(nd, w);
        }
      }
    }
    std::vector<std::uint32_t> out;
    if (found) {
      for (std::uint32_t v = b; v != a; v = prev[v]) out.push_back(v);
      out.push_back(a);
      std::reverse(out.begin(), out.end());
    }
    for (std::uint32_t v : touched) dist[v] = std::numeric_limits<float>::infinity();
    return out;
  }
};

std::string show(glm::vec3 p) {
  std::ostringstream os;
  os << "[" << p.x << ", " << p.y << ", " << p.z << "]";
  return os.str();
}

const char* kCurveName[4] = {"front", "right", "back", "left"};

}  // namespace

std::vector<glm::vec3> catmullRom(const std::vector<glm::vec3>& p, int per_segment) {
  std::vector<glm::vec3> out;
  if (p.size() < 2) return p;
  per_segment = std::max(1, per_segment);
  const std::size_t n = p.size();
  auto at = [&](std::ptrdiff_t i) {
    if (i < 0) return 2.0f * p[0] - p[1];
    if (i >= static_cast<std::ptrdiff_t>(n)) return 2.0f * p[n - 1] - p[n - 2];
    return p[static_cast<std::size_t>(i)];
  };
  for (std::size_t s = 0; s + 1 < n; ++s) {
    const auto i = static_cast<std::ptrdiff_t>(s);
    const glm::vec3 p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
    for (int k = 0; k < per_segment; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(per_segment);
      const float t2 = t * t, t3 = t2 * t;
      out.push_back(0.5f * (2.0f * p1 + (p2 - p0) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                            (3.0f * p1 - p0 - 3.0f * p2 + p3) * t3));
    }
  }
  out.push_back(p.back());
  return out;
}

glm::vec3 projectToSurface(const Body& body, glm::vec3 p) {
  for (int it = 0; it < 6; ++it) {
    float phi;
    glm::vec3 n;
    body.signedDistance(&p, 1, &phi, &n);
    p -= phi * n;
    if (std::abs(phi) < 1e-6f) break;
  }
  return p;
}

ScalpCurves automaticScalpCurves(const TriangleMesh& head, const Body& sdf) {
  // The head: scanning down from the top, everything above the neck, found
  // where the width falls below 70% of its maximum after a descent of at
  // least 60% of that maximum (so the narrowing crown does not count).
  float ymin = INFINITY, ymax = -INFINITY;
  for (const auto& v : head.vertices) {
    ymin = std::min(ymin, v.y);
    ymax = std::max(ymax, v.y);
  }
  constexpr int kSlices = 200;
  const float dy = (ymax - ymin) / kSlices;
  std::vector<float> lo(kSlices, INFINITY), hi(kSlices, -INFINITY);
  for (const auto& v : head.vertices) {
    const int s = std::clamp(static_cast<int>((ymax - v.y) / dy), 0, kSlices - 1);
    lo[static_cast<std::size_t>(s)] = std::min(lo[static_cast<std::size_t>(s)], v.x);
    hi[static_cast<std::size_t>(s)] = std::max(hi[static_cast<std::size_t>(s)], v.x);
  }
  float wmax = 0, bottom = ymin;
  for (int s = 0; s < kSlices; ++s) {
    const float w = hi[static_cast<std::size_t>(s)] - lo[static_cast<std::size_t>(s)];
    if (!(w > 0.0f)) continue;
    wmax = std::max(wmax, w);
    const float y = ymax - (static_cast<float>(s) + 0.5f) * dy;
    if (ymax - y > 0.6f * wmax && w < 0.7f * wmax) {
      bottom = y;
      break;
    }
  }
  // The cranium: the top 45% of the head.
  const float cut = ymax - 0.45f * (ymax - bottom);
  glm::vec3 clo(INFINITY), chi(-INFINITY);
  for (const auto& v : head.vertices)
    if (v.y >= cut) {
      clo = glm::min(clo, v);
      chi = glm::max(chi, v);
    }
  const float radius = 0.5f * (chi.x - clo.x);
  const glm::vec3 centre(0.5f * (clo.x + chi.x), ymax - 1.15f * radius, 0.5f * (clo.z + chi.z));

  // The surface point in a direction (azimuth from the face towards the
  // right ear, elevation above the horizontal), by marching out from the
  // centre to the last crossing.
  auto surface = [&](float azimuth_deg, float elevation_deg) {
    const float a = glm::radians(azimuth_deg), e = glm::radians(elevation_deg);
    const glm::vec3 d(std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e));
    const float reach = 3.0f * radius, step = radius / 64.0f;
    float last_inside = 0.0f;
    for (float r = 0.0f; r <= reach; r += step) {
      const glm::vec3 p = centre + r * d;
      float phi;
      glm::vec3 n;
      sdf.signedDistance(&p, 1, &phi, &n);
      if (phi < 0.0f) last_inside = r;
    }
    return projectToSurface(sdf, centre + (last_inside + 0.5f * step) * d);
  };
  using AE = std::pair<float, float>;
  const std::vector<AE> front = {{-55, 22}, {-28, 30}, {0, 32}, {28, 30}, {55, 22}};
  const std::vector<AE> right = {{55, 22}, {75, 12}, {95, 2}, {115, -10}, {135, -28}, {155, -44}};
  const std::vector<AE> back = {{155, -44}, {168, -50}, {180, -52}, {-168, -50}, {-155, -44}};
  ScalpCurves c;
  for (const auto& [a, e] : front) c.control[0].push_back(surface(a, e));
  for (const auto& [a, e] : right) c.control[1].push_back(surface(a, e));
  for (const auto& [a, e] : back) c.control[2].push_back(surface(a, e));
  for (auto it = right.rbegin(); it != right.rend(); ++it) c.control[3].push_back(surface(-it->first, it->second));
  return c;
}

namespace {

// The scalp's errors name the file and say what is wrong with the curves.
struct ScalpFail {
  const std::string& source;
  [[noreturn]] void operator()(const std::string& problem) const { throw MeshError(source + ": scalp: " + problem); }
};

// Corners: where consecutive curves meet (each curve's end and the next
// one's start, which must be close).
std::array<glm::vec3, 4> curveCorners(const ScalpCurves& curves, float size, const ScalpFail& fail) {
  std::array<glm::vec3, 4> corner;
  for (int k = 0; k < 4; ++k) {
    const glm::vec3 end = curves.control[static_cast<std::size_t>(k)].back();
    const glm::vec3 start = curves.control[static_cast<std::size_t>((k + 1) % 4)].front();
    if (glm::length(end - start) > 0.05f * size)
      fail(std::string(kCurveName[k]) + " curve ends at " + show(end) + " but the " + kCurveName[(k + 1) % 4] +
           " curve starts at " + show(start) + "; consecutive curves must meet");
    corner[static_cast<std::size_t>((k + 1) % 4)] = 0.5f * (end + start);
  }

  return corner;
}

// Dense samples of the closed curve on the surface, with the corners marked.
struct CurveSamples {
  std::vector<glm::vec3> samples;
  std::array<std::size_t, 4> corner_sample{};
};
CurveSamples curveSamples(const ScalpCurves& curves, const std::array<glm::vec3, 4>& corner, const Body& sdf,
                          double edge) {
  CurveSamples out;
  std::vector<glm::vec3>& samples = out.samples;
  std::array<std::size_t, 4>& corner_sample = out.corner_sample;
  for (int k = 0; k < 4; ++k) {
    std::vector<glm::vec3> ctrl = curves.control[static_cast<std::size_t>(k)];
    ctrl.front() = corner[static_cast<std::size_t>(k)];
    ctrl.back() = corner[static_cast<std::size_t>((k + 1) % 4)];
    for (auto& c : ctrl) c = projectToSurface(sdf, c);
    float span = 0;
    for (std::size_t i = 0; i + 1 < ctrl.size(); ++i) span = std::max(span, glm::length(ctrl[i + 1] - ctrl[i]));
    const int per = std::clamp(static_cast<int>(std::ceil(span / (0.5 * edge))), 2, 4000);
    std::vector<glm::vec3> pts = catmullRom(ctrl, per);
    corner_sample[static_cast<std::size_t>(k)] = samples.size();
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) samples.push_back(projectToSurface(sdf, pts[i]));
  }
  return out;
}

// Nearest mesh vertex of each sample (brute force: few samples), on the
// part with the most triangles: the scalp is one connected piece of the
// head, and helper parts (eyes, a hat) may lie nearer.
std::vector<std::uint32_t> nearestVertices(const TriangleMesh& head, const std::vector<glm::vec3>& samples) {
  std::vector<std::uint8_t> on_head(head.vertices.size(), 0);
  {
    const MeshParts parts = meshParts(head);
    const std::uint32_t largest = parts.largest();
    for (std::size_t t = 0; t < head.triangles.size(); ++t)
      if (parts.of_triangle[t] == largest)
        for (int i = 0; i < 3; ++i) on_head[head.triangles[t][i]] = 1;
  }
  std::vector<std::uint32_t> near(samples.size());
  for (std::size_t s = 0; s < samples.size(); ++s) {
    float best = INFINITY;
    for (std::size_t v = 0; v < head.vertices.size(); ++v) {
      if (!on_head[v]) continue;
      const glm::vec3 d = head.vertices[v] - samples[s];
      const float d2 = glm::dot(d, d);
      if (d2 < best) {
        best = d2;
        near[s] = static_cast<std::uint32_t>(v);
      }
    }
  }

  return near;
}

// The closed loop of mesh edges through the samples' vertices, pinches (a
// vertex visited twice closes a small side loop) removed.
std::vector<std::uint32_t> trimmingLoop(const TriangleMesh& head, const std::vector<std::uint32_t>& near,
                                        const ScalpFail& fail) {
  const Graph graph(head);
  std::vector<float> dist(head.vertices.size(), std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> prev(head.vertices.size(), 0);
  std::vector<std::uint32_t> loop;
  for (std::size_t s = 0; s < near.size(); ++s) {
    const std::uint32_t a = near[s], b = near[(s + 1) % near.size()];
    auto piece = graph.path(a, b, dist, prev);
    if (piece.empty()) fail("the hairline crosses a gap in the head's surface (the mesh is not connected along it)");
    for (std::size_t i = 0; i + 1 < piece.size(); ++i)
      if (loop.empty() || loop.back() != piece[i]) loop.push_back(piece[i]);
  }
  // Remove pinches: a vertex visited twice closes a small side loop.
  {
    std::vector<std::uint32_t> clean;
    std::unordered_map<std::uint32_t, std::size_t> where;
    for (std::uint32_t v : loop) {
      auto it = where.find(v);
      if (it != where.end()) {
        for (std::size_t k = it->second + 1; k < clean.size(); ++k) where.erase(clean[k]);
        clean.resize(it->second + 1);
        continue;
      }
      where.emplace(v, clean.size());
      clean.push_back(v);
    }
    loop = std::move(clean);
  }
  return loop;
}

// The corners on the loop (the nearest loop vertex where a pinch removed
// one), the loop turned to start at the first; checks that the curves run
// front, right, back, left. Writes the corners' vertices.
std::array<std::size_t, 4> cornersOnLoop(const TriangleMesh& head, std::vector<std::uint32_t>& loop,
                                         std::array<std::uint32_t, 4>& corner_vertex, const ScalpFail& fail) {
  std::array<std::size_t, 4> corner_at{};
  for (int k = 0; k < 4; ++k) {
    float best = INFINITY;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const float d = glm::length(head.vertices[loop[i]] - head.vertices[corner_vertex[static_cast<std::size_t>(k)]]);
      if (d < best) {
        best = d;
        corner_at[static_cast<std::size_t>(k)] = i;
      }
    }
  }
  std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(corner_at[0]), loop.end());
  for (int k = 3; k >= 0; --k)
    corner_at[static_cast<std::size_t>(k)] =
        (corner_at[static_cast<std::size_t>(k)] + loop.size() - corner_at[0]) % loop.size();
  if (!(corner_at[1] > 0 && corner_at[2] > corner_at[1] && corner_at[3] > corner_at[2]))
    fail("the four curves must run front, right, back, left around the scalp");
  for (int k = 0; k < 4; ++k) corner_vertex[static_cast<std::size_t>(k)] = loop[corner_at[static_cast<std::size_t>(k)]];

  return corner_at;
}

// The faces on the left of the loop (the scalp, seen from outside), by a
// flood that does not cross the loop; `face_of` maps each directed edge to
// its face.
std::vector<char> floodScalp(const TriangleMesh& head, const std::vector<std::uint32_t>& loop,
                             std::unordered_map<std::uint64_t, std::uint32_t>& face_of, const ScalpFail& fail) {
  face_of.reserve(3 * head.triangles.size());
  for (std::uint32_t f = 0; f < head.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) face_of.emplace(edgeKey(head.triangles[f][k], head.triangles[f][(k + 1) % 3]), f);
  std::unordered_set<std::uint64_t> cut;
  for (std::size_t i = 0; i < loop.size(); ++i) cut.insert(undirectedKey(loop[i], loop[(i + 1) % loop.size()]));
  auto seed = face_of.find(edgeKey(loop[0], loop[1]));
  if (seed == face_of.end()) fail("the trimming loop does not follow the mesh");
  std::vector<char> in(head.triangles.size(), 0);
  std::vector<std::uint32_t> stack{seed->second};
  in[seed->second] = 1;
  while (!stack.empty()) {
    const std::uint32_t f = stack.back();
    stack.pop_back();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = head.triangles[f][k], b = head.triangles[f][(k + 1) % 3];
      if (cut.count(undirectedKey(a, b))) continue;
      auto it = face_of.find(edgeKey(b, a));
      if (it == face_of.end() || in[it->second]) continue;
      in[it->second] = 1;
      stack.push_back(it->second);
    }
  }
  for (std::size_t i = 0; i < loop.size(); ++i) {
    auto other = face_of.find(edgeKey(loop[(i + 1) % loop.size()], loop[i]));
    if (other != face_of.end() && in[other->second])
      fail("the curves do not separate the scalp from the rest of the head (is the loop closed?)");
  }

  return in;
}

// Trims ears: a region triangle with two edges on the loop (three
// consecutive loop vertices) would map to a line on the square's side.
void trimEars(const TriangleMesh& head, const std::unordered_map<std::uint64_t, std::uint32_t>& face_of,
              const std::array<std::uint32_t, 4>& corner_vertex, std::vector<std::uint32_t>& loop,
              std::vector<char>& in) {
  for (bool changed = true; changed && loop.size() > 8;) {
    changed = false;
    for (std::size_t i = 0; i < loop.size() && loop.size() > 8; ++i) {
      const std::size_t n = loop.size();
      const std::uint32_t a = loop[(i + n - 1) % n], b = loop[i], c = loop[(i + 1) % n];
      auto f = face_of.find(edgeKey(a, b));
      if (f == face_of.end() || !in[f->second]) continue;
      const auto& t = head.triangles[f->second];
      const bool is_ear = (t.x == c || t.y == c || t.z == c);
      if (!is_ear) continue;
      bool is_corner = false;
      for (int k = 0; k < 4; ++k) is_corner |= corner_vertex[static_cast<std::size_t>(k)] == b;
      if (is_corner) continue;
      in[f->second] = 0;
      loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
      changed = true;
    }
  }
}

}  // namespace

MeshScalp::MeshScalp(const TriangleMesh& head_in, const Body& sdf, const ScalpCurves& curves,
                     const std::string& source) {
  const ScalpFail fail{source};
  for (int k = 0; k < 4; ++k)
    if (curves.control[static_cast<std::size_t>(k)].size() < 2)
      fail(std::string(kCurveName[k]) + " curve needs at least two control points");

  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& v : head_in.vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const float size = glm::length(hi - lo);
  const TriangleMesh head = refined(head_in, size / 150.0);
  const std::vector<glm::vec3> vnormal = vertexNormals(head);
  const double edge = meanEdgeLength(head);

  const CurveSamples curve = curveSamples(curves, curveCorners(curves, size, fail), sdf, edge);
  polyline_ = curve.samples;
  const std::vector<std::uint32_t> near = nearestVertices(head, curve.samples);
  std::vector<std::uint32_t> loop = trimmingLoop(head, near, fail);
  if (loop.size() < 8)
    fail("the curves enclose too small a region (" + std::to_string(loop.size()) + " boundary vertices)");
  std::array<std::uint32_t, 4> corner_vertex{};
  for (int k = 0; k < 4; ++k)
    corner_vertex[static_cast<std::size_t>(k)] = near[curve.corner_sample[static_cast<std::size_t>(k)]];
  std::array<std::size_t, 4> corner_at = cornersOnLoop(head, loop, corner_vertex, fail);
  std::unordered_map<std::uint64_t, std::uint32_t> face_of;
  std::vector<char> in = floodScalp(head, loop, face_of, fail);
  trimEars(head, face_of, corner_vertex, loop, in);
  // Corners on the loop again after the trimming.
  for (int k = 0; k < 4; ++k)
    corner_at[static_cast<std::size_t>(k)] = static_cast<std::size_t>(
        std::find(loop.begin(), loop.end(), corner_vertex[static_cast<std::size_t>(k)]) - loop.begin());
  takeSubmesh(head, vnormal, in, loop);
  std::vector<char> fixed = mapBoundary(loop, corner_at);
  mapInterior(fixed, fail);
  buildSampling();
}

// The scalp submesh: the flooded faces of `head`, their vertices renumbered;
// the loop as the boundary.
void MeshScalp::takeSubmesh(const TriangleMesh& head, const std::vector<glm::vec3>& vnormal,
                            const std::vector<char>& in, const std::vector<std::uint32_t>& loop) {
  std::vector<std::uint32_t> local(head.vertices.size(), UINT32_MAX);
  for (std::uint32_t f = 0; f < head.triangles.size(); ++f) {
    if (!in[f]) continue;
    glm::u32vec3 t;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& l = local[head.triangles[f][k]];
      if (l == UINT32_MAX) {
        l = static_cast<std::uint32_t>(pos_.size());
        pos_.push_back(head.vertices[head.triangles[f][k]]);
        nrm_.push_back(vnormal[head.triangles[f][k]]);
      }
      t[k] = l;
    }
    tri_.push_back(t);
  }
  for (std::uint32_t v : loop) boundary_.push_back(local[v]);
}

// The boundary on the square's sides by arc length between the corners;
// returns which vertices the map fixes.
std::vector<char> MeshScalp::mapBoundary(const std::vector<std::uint32_t>& loop,
                                         const std::array<std::size_t, 4>& corner_at) {
  const std::size_t nv = pos_.size();
  uv_.assign(nv, glm::vec2(0.0f));
  std::vector<char> fixed(nv, 0);
  const glm::vec2 square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    const std::size_t b = corner_at[static_cast<std::size_t>(k)];
    const std::size_t e = k == 3 ? loop.size() : corner_at[static_cast<std::size_t>(k + 1)];
    double total = 0;
    for (std::size_t i = b; i < e; ++i)
      total += glm::length(pos_[boundary_[(i + 1) % loop.size()]] - pos_[boundary_[i]]);
    double run = 0;
    for (std::size_t i = b; i < e; ++i) {
      const float t = total > 0 ? static_cast<float>(run / total) : 0.0f;
      uv_[boundary_[i]] = square[k] + t * (square[(k + 1) % 4] - square[k]);
      fixed[boundary_[i]] = 1;
      run += glm::length(pos_[boundary_[(i + 1) % loop.size()]] - pos_[boundary_[i]]);
    }
  }

  return fixed;
}

// The harmonic map (method.md §6.1): sum_j w_ij (x_i - x_j) = 0 at the
// interior vertices, cotangent weights, or Floater's mean-value weights
// where those fold a triangle over.
template <class Fail>
void MeshScalp::mapInterior(const std::vector<char>& fixed, const Fail& fail) {
  const std::size_t nv = pos_.size();
  std::vector<std::uint32_t> row(nv, UINT32_MAX);
  std::uint32_t interior = 0;
  for (std::size_t v = 0; v < nv; ++v)
    if (!fixed[v]) row[v] = interior++;
  auto solve = [&](bool mean_value) {
    std::map<std::uint64_t, double> w;  // directed: weight of j in i's equation
    for (const auto& t : tri_) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t i = t[k], j = t[(k + 1) % 3], l = t[(k + 2) % 3];
        const glm::dvec3 pi(pos_[i]), pj(pos_[j]), pl(pos_[l]);
        if (!mean_value) {
          // cot of the angle at l weighs the opposite edge (i, j) both ways.
          const glm::dvec3 a = pi - pl, b = pj - pl;
          const double cot = glm::dot(a, b) / std::max(1e-30, glm::length(glm::cross(a, b)));
          w[edgeKey(i, j)] += 0.5 * cot;
          w[edgeKey(j, i)] += 0.5 * cot;
        } else {
          // tan(theta/2) at i for its two edges (Floater's mean-value weights).
          const glm::dvec3 a = pj - pi, b = pl - pi;
          const double la = glm::length(a), lb = glm::length(b);
          const double theta = std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
          const double tn = std::tan(0.5 * theta);
          w[edgeKey(i, j)] += tn / la;
          w[edgeKey(i, l)] += tn / lb;
        }
      }
    }
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(interior, 2);
    for (const auto& [key, weight] : w) {
      const auto i = static_cast<std::uint32_t>(key >> 32), j = static_cast<std::uint32_t>(key & 0xffffffffu);
      if (fixed[i]) continue;
      trip.emplace_back(row[i], row[i], weight);
      if (fixed[j]) {
        rhs(row[i], 0) += weight * uv_[j].x;
        rhs(row[i], 1) += weight * uv_[j].y;
      } else {
        trip.emplace_back(row[i], row[j], -weight);
      }
    }
    if (interior == 0) return;
    Eigen::SparseMatrix<double> a(interior, interior);
    a.setFromTriplets(trip.begin(), trip.end());
    Eigen::MatrixXd x;
    if (!mean_value) {
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
      if (ldlt.info() == Eigen::Success) x = ldlt.solve(rhs);
    }
    if (x.size() == 0 || !x.allFinite()) {
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
      lu.analyzePattern(a);
      lu.factorize(a);
      if (lu.info() != Eigen::Success) fail("the harmonic map system is singular");
      x = lu.solve(rhs);
    }
    if (!x.allFinite()) fail("the harmonic map has no finite solution");
    for (std::size_t v = 0; v < nv; ++v)
      if (!fixed[v]) uv_[v] = glm::vec2(static_cast<float>(x(row[v], 0)), static_cast<float>(x(row[v], 1)));
  };
  auto flips = [&]() {
    std::size_t n = 0;
    for (const auto& t : tri_) {
      const glm::dvec2 a(uv_[t.x]), b(uv_[t.y]), c(uv_[t.z]);
      const double cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      n += cross > 0 ? 0 : 1;
    }
    return n;
  };
  solve(false);
  report_.flipped = flips();
  if (report_.flipped > 0) {
    solve(true);
    report_.mean_value_weights = true;
    report_.flipped = flips();
  }
  if (report_.flipped > 0)
    fail(std::to_string(report_.flipped) + " triangles fold over in the (u, v) map; check the curves");
}

// The area table for uniform sampling and the (u, v) buckets for f^-1.
void MeshScalp::buildSampling() {
  const std::size_t nv = pos_.size();
  area_cdf_.resize(tri_.size());
  double total = 0;
  for (std::size_t t = 0; t < tri_.size(); ++t) {
    const glm::dvec3 a(pos_[tri_[t].x]), b(pos_[tri_[t].y]), c(pos_[tri_[t].z]);
    total += 0.5 * glm::length(glm::cross(b - a, c - a));
    area_cdf_[t] = total;
  }
  report_.area = total;
  report_.triangles = tri_.size();
  report_.vertices = nv;
  report_.boundary_vertices = boundary_.size();
  buckets_ = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(tri_.size()))), 1, 1024);
  const auto nb = static_cast<std::size_t>(buckets_) * static_cast<std::size_t>(buckets_);
  std::vector<std::vector<std::uint32_t>> lists(nb);
  auto cell = [&](float x) { return std::clamp(static_cast<int>(x * static_cast<float>(buckets_)), 0, buckets_ - 1); };
  for (std::uint32_t t = 0; t < tri_.size(); ++t) {
    const glm::vec2 a = uv_[tri_[t].x], b = uv_[tri_[t].y], c = uv_[tri_[t].z];
    const glm::vec2 l = glm::min(a, glm::min(b, c)), h = glm::max(a, glm::max(b, c));
    for (int y = cell(l.y); y <= cell(h.y); ++y)
      for (int x = cell(l.x); x <= cell(h.x); ++x) lists[static_cast<std::size_t>(y * buckets_ + x)].push_back(t);
  }
  bucket_start_.assign(nb + 1, 0);
  for (std::size_t b = 0; b < nb; ++b)
    bucket_start_[b + 1] = bucket_start_[b] + static_cast<std::uint32_t>(lists[b].size());
  bucket_items_.reserve(bucket_start_[nb]);
  for (const auto& l : lists) bucket_items_.insert(bucket_items_.end(), l.begin(), l.end());
}

std::uint32_t MeshScalp::locate(glm::vec2 uv, glm::vec3& bary) const {
  uv = glm::clamp(uv, glm::vec2(0.0f), glm::vec2(1.0f));
  const int x = std::clamp(static_cast<int>(uv.x * static_cast<float>(buckets_)), 0, buckets_ - 1);
  const int y = std::clamp(static_cast<int>(uv.y * static_cast<float>(buckets_)), 0, buckets_ - 1);
  const std::size_t b = static_cast<std::size_t>(y * buckets_ + x);
  float best = -INFINITY;
  std::uint32_t best_t = 0;
  glm::vec3 best_bary(1.0f / 3.0f);
  auto test = [&](std::uint32_t t) {
    const glm::vec2 a = uv_[tri_[t].x], e1 = uv_[tri_[t].y] - a, e2 = uv_[tri_[t].z] - a, q = uv - a;
    const float det = e1.x * e2.y - e1.y * e2.x;
    if (!(det > 0.0f)) return false;
    const float l1 = (q.x * e2.y - q.y * e2.x) / det, l2 = (e1.x * q.y - e1.y * q.x) / det;
    const glm::vec3 l(1.0f - l1 - l2, l1, l2);
    const float worst = std::min({l.x, l.y, l.z});
    if (worst > best) {
      best = worst;
      best_t = t;
      best_bary = l;
    }
    return worst >= 0.0f;
  };
  for (std::uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k)
    if (test(bucket_items_[k])) break;
  if (best == -INFINITY)  // an empty bucket (only at the clamped border)
    for (std::uint32_t t = 0; t < tri_.size(); ++t) test(t);
  // Outside every triangle (the border): clamp to the nearest edge.
  bary = glm::max(best_bary, glm::vec3(0.0f));
  bary /= bary.x + bary.y + bary.z;
  return best_t;
}

glm::vec3 MeshScalp::point(glm::vec2 uv) const {
  glm::vec3 l;
  const auto t = tri_[locate(uv, l)];
  return l.x * pos_[t.x] + l.y * pos_[t.y] + l.z * pos_[t.z];
}

glm::vec3 MeshScalp::normal(glm::vec2 uv) const {
  glm::vec3 l;
  const auto t = tri_[locate(uv, l)];
  const glm::vec3 n = l.x * nrm_[t.x] + l.y * nrm_[t.y] + l.z * nrm_[t.z];
  const float len = glm::length(n);
  return len > 0.0f ? n / len : nrm_[t.x];
}

glm::vec2 MeshScalp::sampleByArea(Random& rng) const {
  const double target = rng.uniform() * report_.area;
  const auto it = std::upper_bound(area_cdf_.begin(), area_cdf_.end(), target);
  const std::size_t t = std::min(static_cast<std::size_t>(it - area_cdf_.begin()), tri_.size() - 1);
  const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
  const auto a = static_cast<float>(1.0 - r1), b = static_cast<float>(r1 * (1.0 - r2)), c = static_cast<float>(r1 * r2);
  return a * uv_[tri_[t].x] + b * uv_[tri_[t].y] + c * uv_[tri_[t].z];
}

}  // namespace loosehair
