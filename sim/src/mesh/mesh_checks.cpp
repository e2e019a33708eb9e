// checkMesh (loosehair/mesh.hpp): what the simulator asks of a body mesh
// (finite, indexed, no degenerate triangles, a closed, consistently
// oriented surface that encloses a volume), mending what can be mended
// (holes closed with fans, an inside-out mesh turned).
#include "loosehair/mesh.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace loosehair {
namespace {

std::string vecText(glm::vec3 v) {
  std::ostringstream os;
  os << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return os.str();
}

// Every vertex finite, every corner a vertex.
void checkFiniteAndIndexed(const TriangleMesh& mesh, const std::string& source) {
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const glm::vec3 p = mesh.vertices[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw MeshError(source + ": vertex " + std::to_string(v) + " is not finite " + vecText(p));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] >= mesh.vertices.size())
        throw MeshError(source + ": triangle " + std::to_string(t) + " refers to vertex " +
                        std::to_string(mesh.triangles[t][k]) + " of " + std::to_string(mesh.vertices.size()));
}

// Degenerate triangles (repeated corners or, numerically, no area) are
// dropped; more than a tenth of them is refused.
void dropDegenerateTriangles(TriangleMesh& mesh, float diag, MeshReport& r, const std::string& source) {
  const double min_area = 1e-14 * static_cast<double>(diag) * diag;
  std::vector<glm::u32vec3> good;
  good.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    if (t.x == t.y || t.y == t.z || t.x == t.z) continue;
    const glm::dvec3 a(mesh.vertices[t.x]), b(mesh.vertices[t.y]), c(mesh.vertices[t.z]);
    if (!(0.5 * glm::length(glm::cross(b - a, c - a)) > min_area)) continue;
    good.push_back(t);
  }
  r.degenerate_removed = mesh.triangles.size() - good.size();
  if (good.empty() || r.degenerate_removed * 10 > mesh.triangles.size())
    throw MeshError(source + ": " + std::to_string(r.degenerate_removed) + " of " +
                    std::to_string(mesh.triangles.size()) + " triangles are degenerate (no area or repeated corners)");
  mesh.triangles = std::move(good);
}

// Drops unreferenced vertices.
void dropUnusedVertices(TriangleMesh& mesh) {
  std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  std::vector<glm::vec3> kept;
  for (auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      auto& v = t[k];
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(mesh.vertices[v]);
      }
      v = remap[v];
    }
  mesh.vertices = std::move(kept);
}

// The edges' census: boundary, non-manifold and misoriented edges counted
// in `r` (too many of the latter two refused); the holes' rims as a map
// from -> to, and a vertex on two rims (`pinched`) if there is one.
struct EdgeCensus {
  std::size_t unique_edges = 0;
  std::unordered_map<std::uint32_t, std::uint32_t> next;  // hole edges, from -> to
  std::uint32_t pinched = UINT32_MAX;                     // a vertex on two rims
};
EdgeCensus countEdges(const TriangleMesh& mesh, MeshReport& r, const std::string& source) {
  EdgeCensus census;
  std::size_t& unique_edges = census.unique_edges;
  std::unordered_map<std::uint32_t, std::uint32_t>& next = census.next;
  std::uint32_t& pinched = census.pinched;
  // Edges: (low, high) with +1 for low->high in a triangle, -1 otherwise.
  struct HalfEdge {
    std::uint64_t key;
    int dir;
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      edges.push_back({key, a < b ? 1 : -1});
    }
  std::sort(edges.begin(), edges.end(),
            [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key || (x.key == y.key && x.dir < y.dir); });
  for (std::size_t a = 0; a < edges.size();) {
    std::size_t b = a;
    int sum = 0;
    while (b < edges.size() && edges[b].key == edges[a].key) sum += edges[b++].dir;
    const std::size_t count = b - a;
    ++unique_edges;
    if (count == 1) {
      ++r.boundary_edges;
      const auto lo_v = static_cast<std::uint32_t>(edges[a].key >> 32);
      const auto hi_v = static_cast<std::uint32_t>(edges[a].key & 0xffffffffu);
      // the triangle runs lo->hi when dir > 0; the hole runs the other way
      const std::uint32_t from = edges[a].dir > 0 ? hi_v : lo_v, to = edges[a].dir > 0 ? lo_v : hi_v;
      if (!next.emplace(from, to).second && pinched == UINT32_MAX) pinched = from;
    } else if (count > 2)
      ++r.nonmanifold_edges;
    else if (sum != 0)
      ++r.misoriented_edges;
    a = b;
  }
  if (r.nonmanifold_edges * 100 > unique_edges)
    throw MeshError(source + ": the mesh is not a surface: " + std::to_string(r.nonmanifold_edges) + " of " +
                    std::to_string(unique_edges) + " edges belong to three or more triangles");
  if (r.misoriented_edges * 100 > unique_edges)
    throw MeshError(source + ": the triangles are not consistently oriented: " + std::to_string(r.misoriented_edges) +
                    " of " + std::to_string(unique_edges) +
                    " edges are traversed the same way by both their triangles");
  return census;
}

// The holes' rims as closed loops of vertices, in a fixed order.
std::vector<std::vector<std::uint32_t>> holeLoops(const std::unordered_map<std::uint32_t, std::uint32_t>& next,
                                                  const std::string& source) {
  std::vector<std::vector<std::uint32_t>> loops;
  std::vector<std::uint32_t> starts;
  for (const auto& [from, to] : next) starts.push_back(from);
  std::sort(starts.begin(), starts.end());  // deterministic order of the loops
  std::unordered_set<std::uint32_t> done;
  for (std::uint32_t start : starts) {
    if (done.count(start)) continue;
    std::vector<std::uint32_t> loop;
    std::uint32_t v = start;
    do {
      loop.push_back(v);
      done.insert(v);
      auto it = next.find(v);
      if (it == next.end() || loop.size() > next.size())
        throw MeshError(source + ": a hole's boundary does not close on itself");
      v = it->second;
    } while (v != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Holes: traced, then a few openings that
// each close with a flat fan (a head cut off at the neck, a bust cut flat
// under the chest or at the arms) are closed, whatever their size; so are
// many small gaps (a scan's) while they hold at most 2% of the edges.
// Anything more is a surface that does not say where its inside is.
void closeHoles(TriangleMesh& mesh, const EdgeCensus& census, MeshReport& r, const std::string& source) {
  const std::size_t unique_edges = census.unique_edges;
  const std::uint32_t pinched = census.pinched;
  const bool small_gaps = r.boundary_edges * 50 <= unique_edges;
  auto refuse = [&](const std::string& holes) {
    char share[96];
    std::snprintf(share, sizeof share, ", %zu of %zu edges (%.1f%%) on their rims", r.boundary_edges, unique_edges,
                  100.0 * static_cast<double>(r.boundary_edges) / static_cast<double>(unique_edges));
    throw MeshError(source + ": the mesh is not closed: " + holes + share +
                    "; holes are closed automatically when there are at most 4 openings that each close "
                    "with a flat fan (a head cut at the neck, a bust cut under the chest or at the arms) or "
                    "when at most 2% of the edges lie on them (a scan's small gaps): close the other holes "
                    "in a modeller");
  };
  if (pinched != UINT32_MAX) {
    if (!small_gaps) refuse("holes that touch each other");
    throw MeshError(source + ": a hole cannot be closed: vertex " + std::to_string(pinched) +
                    " lies on the rims of two holes (parts that touch at a vertex, such as eyes or "
                    "teeth modelled as open shells against the face); remove those parts or close "
                    "them in a modeller");
  }
  const std::vector<std::vector<std::uint32_t>> loops = holeLoops(census.next, source);
  // A loop's fan is flat enough when no triangle of it folds back against
  // the loop's area vector (seen along it, the rim goes once around the centroid).
  std::vector<glm::dvec3> centres;
  std::size_t folded = 0;
  for (const auto& loop : loops) {
    glm::dvec3 c(0.0);
    for (std::uint32_t q : loop) c += glm::dvec3(mesh.vertices[q]);
    c /= static_cast<double>(loop.size());
    centres.push_back(c);
    std::vector<glm::dvec3> fan(loop.size());
    glm::dvec3 area(0.0);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      fan[k] = glm::cross(glm::dvec3(mesh.vertices[loop[k]]) - c,
                          glm::dvec3(mesh.vertices[loop[(k + 1) % loop.size()]]) - c);
      area += fan[k];
    }
    bool flat = glm::length(area) > 0.0;
    for (const auto& f : fan) flat = flat && glm::dot(f, area) > 0.0;
    if (!flat) ++folded;
  }
  constexpr std::size_t kFewOpenings = 4;
  const bool few_openings = loops.size() <= kFewOpenings && folded == 0;
  if (!few_openings && !small_gaps)
    refuse(std::to_string(loops.size()) + " hole(s), " + std::to_string(folded) +
           " of them not flat enough to close with a fan");

  // Close the holes: a fan from each loop's centroid, wound to match its
  // neighbours. A body must enclose a volume, and the signed-distance bake
  // floods the outside, so an open mesh would read as outside everywhere.
  for (std::size_t h = 0; h < loops.size(); ++h) {
    const auto& loop = loops[h];
    const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.emplace_back(centres[h]);
    for (std::size_t k = 0; k < loop.size(); ++k)
      mesh.triangles.emplace_back(loop[k], loop[(k + 1) % loop.size()], centre);
    ++r.holes_filled;
  }
}

// The enclosed volume about the box's centre; a mesh turned inside out is
// turned back; almost none is refused.
double orientedVolume(TriangleMesh& mesh, glm::vec3 lo, glm::vec3 hi, MeshReport& r, const std::string& source) {
  const glm::vec3 ext = hi - lo;
  double vol = 0;
  const glm::dvec3 c0 = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 a = glm::dvec3(mesh.vertices[t.x]) - c0, b = glm::dvec3(mesh.vertices[t.y]) - c0,
                     c = glm::dvec3(mesh.vertices[t.z]) - c0;
    vol += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  if (vol < 0) {
    for (auto& t : mesh.triangles) std::swap(t.y, t.z);
    vol = -vol;
    r.flipped = true;
  }
  const double box = static_cast<double>(ext.x) * ext.y * ext.z;
  if (!(vol > 1e-4 * box))
    throw MeshError(source + ": the mesh encloses almost no volume (" + std::to_string(vol) +
                    " m^3 in a bounding box of " + std::to_string(box) + " m^3)");
  return vol;
}

}  // namespace

MeshReport checkMesh(TriangleMesh& mesh, const std::string& source) {
  MeshReport r;
  if (mesh.triangles.empty() || mesh.vertices.empty()) throw MeshError(source + ": the mesh has no triangles");
  checkFiniteAndIndexed(mesh, source);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, mesh.vertices[t[k]]);
      hi = glm::max(hi, mesh.vertices[t[k]]);
    }
  const glm::vec3 ext = hi - lo;
  const float diag = glm::length(ext);
  if (!(diag > 0.0f) || std::min({ext.x, ext.y, ext.z}) <= 1e-6f * diag)
    throw MeshError(source + ": the mesh is flat or a point (bounding box " + vecText(lo) + " to " + vecText(hi) +
                    "); a body must enclose a volume");

  dropDegenerateTriangles(mesh, diag, r, source);
  dropUnusedVertices(mesh);
  const EdgeCensus census = countEdges(mesh, r, source);
  closeHoles(mesh, census, r, source);
  r.components = meshParts(mesh).count();
  r.volume = orientedVolume(mesh, lo, hi, r, source);
  r.vertices = mesh.vertices.size();
  r.triangles = mesh.triangles.size();
  r.lower = lo;
  r.upper = hi;
  return r;
}

}  // namespace loosehair
