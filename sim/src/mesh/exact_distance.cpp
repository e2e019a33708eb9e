// Exact distance from points to a closed triangle mesh (method.md §5 body
// collisions): the nearest triangle from a bounding-volume hierarchy,
// searched nearest box first inside a ball that seed triangles (the grid's
// nearest triangles) make small, and the sign from the angle-weighted
// pseudo-normal of the nearest feature (Baerentzen and Aanaes 2005), exact
// for a closed, consistently oriented mesh. (With Eigen's KdBVH, which
// allocates its stack and visits boxes in no order, the contact stages of
// hang.json took twice as long: docs/performance.md.) A ball small enough
// (a point resting on the body, seeded with its last nearest triangle) is
// searched in the few lists of a uniform grid of triangles instead
// (triangle_cells.hpp), and triangles whose plane or bounding sphere is
// beyond the ball are skipped: both only leave out triangles that cannot
// win, so the answer is the hierarchy's, bit for bit.
#include "mesh/exact_distance.hpp"

#include "mesh/triangle_cells.hpp"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace loosehair {

namespace {

// The feature of a triangle a point is nearest to.
enum Feature : std::uint8_t { kFace, kVertexA, kVertexB, kVertexC, kEdgeAB, kEdgeBC, kEdgeCA };

// The point of triangle (a, b, c) nearest to p and the feature it lies on:
// the Voronoi regions of the vertices, then of the edges, then the face.
glm::vec3 nearestOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                            Feature& feature) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) {
    feature = kVertexA;
    return a;
  }
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) {
    feature = kVertexB;
    return b;
  }
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    feature = kEdgeAB;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) {
    feature = kVertexC;
    return c;
  }
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    feature = kEdgeCA;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    feature = kEdgeBC;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const float denom = va + vb + vc;
  if (!(std::fabs(denom) > 0.0f)) {  // a sliver: the nearest of its edges' points
    feature = kEdgeAB;
    return a;
  }
  feature = kFace;
  const float v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

// Squared distance from p to the box [lo, hi] (0 inside).
inline float boxDistance2(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 d = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
  return glm::dot(d, d);
}

}  // namespace

struct ExactDistance::Tree {
  void init(const TriangleMesh& part);
  std::vector<std::uint32_t> global;  // per triangle: its id in the whole mesh
  std::vector<glm::vec3> vertices;
  std::vector<glm::u32vec3> triangles;
  std::vector<glm::vec3> face_normal;    // unit
  std::vector<glm::vec3> edge_normal;    // 3 a triangle (ab, bc, ca): sum of the faces at the edge
  std::vector<glm::vec3> vertex_normal;  // angle-weighted sum of the faces at the vertex

  glm::vec3 pseudoNormal(std::uint32_t t, Feature f) const {
    switch (f) {
      case kFace:
        return face_normal[t];
      case kVertexA:
        return vertex_normal[triangles[t].x];
      case kVertexB:
        return vertex_normal[triangles[t].y];
      case kVertexC:
        return vertex_normal[triangles[t].z];
      case kEdgeAB:
        return edge_normal[3 * t + 0];
      case kEdgeBC:
        return edge_normal[3 * t + 1];
      case kEdgeCA:
        return edge_normal[3 * t + 2];
    }
    return face_normal[t];
  }

  // The hierarchy: nodes in depth-first order (an inner node's first child
  // follows it, `second` is the other); a leaf holds `count` triangles of
  // `order` from `first`.
  struct Node {
    glm::vec3 lo, hi;
    std::uint32_t first_or_second = 0;
    std::uint32_t count = 0;  // 0: inner node
  };
  static constexpr std::uint32_t kLeaf = 8;
  std::vector<Node> nodes;
  std::vector<std::uint32_t> order;  // triangle ids in leaf order
  // Each triangle's bounding sphere (centre, radius) and plane (unit
  // normal n through corner a: n.(p - a) is the distance from the plane):
  // the distances from the sphere and from the plane are lower bounds of
  // the distance from the triangle, so a triangle either of them puts
  // farther than the ball (by more than `tolerance`, which covers the
  // rounding) cannot be the nearest and is not tested. The plane rejects
  // what lies beside a curved surface, the sphere what lies along a flat
  // one. A triangle's tests and corners are one record of one cache line,
  // in leaf order (a cell's or a leaf's triangles are then a few
  // neighbouring lines); its id is in `order`, read only for a triangle
  // the tests let through (records of 72 bytes, with the id and the
  // plane's offset, straddled two lines).
  struct alignas(64) Leaf {
    glm::vec3 centre;
    float radius;
    glm::vec3 n, a, b, c;
  };
  static_assert(sizeof(Leaf) == 64);
  std::vector<Leaf> leaves;
  std::vector<std::uint32_t> rank;  // per triangle id: its record in leaves
  float tolerance = 0.0f;
  // The triangles (by leaf order) of each cell: a small ball is searched
  // there rather than down the hierarchy.
  TriangleCells cells;
  static constexpr std::size_t kMaxCells = std::size_t{1} << 20;

  void build() {
    const std::size_t nt = triangles.size();
    order.resize(nt);
    std::iota(order.begin(), order.end(), 0u);
    std::vector<glm::vec3> centre(nt);
    for (std::size_t k = 0; k < nt; ++k)
      centre[k] = (vertices[triangles[k].x] + vertices[triangles[k].y] + vertices[triangles[k].z]) / 3.0f;
    nodes.reserve(2 * nt / kLeaf + 2);
    split(0, static_cast<std::uint32_t>(nt), centre);
    std::vector<glm::vec3> corners(3 * nt);
    for (std::size_t k = 0; k < nt; ++k)
      for (int i = 0; i < 3; ++i) corners[3 * k + static_cast<std::size_t>(i)] = vertices[triangles[order[k]][i]];
    leaves.resize(nt);
    rank.resize(nt);
    for (std::size_t k = 0; k < nt; ++k) {
      const std::uint32_t t = order[k];
      const glm::vec3 a = vertices[triangles[t].x], b = vertices[triangles[t].y], c = vertices[triangles[t].z];
      const glm::vec3 n = face_normal[t], m = (a + b + c) / 3.0f;
      leaves[k].centre = m;
      leaves[k].radius = std::max({glm::length(a - m), glm::length(b - m), glm::length(c - m)});
      leaves[k].n = n;
      leaves[k].a = a;
      leaves[k].b = b;
      leaves[k].c = c;
      rank[t] = static_cast<std::uint32_t>(k);
    }
    // rounding of coordinates of size `extent` in the plane distance and in
    // nearestOnTriangle: a few units in the last place of float each
    const glm::vec3 ext = nodes.empty() ? glm::vec3(0.0f) : glm::max(glm::abs(nodes[0].lo), glm::abs(nodes[0].hi));
    tolerance = 1e-5f * std::max({ext.x, ext.y, ext.z, 1e-3f});
    cells.build(corners, tolerance, kMaxCells);
  }
  void split(std::uint32_t first, std::uint32_t last, const std::vector<glm::vec3>& centre) {
    const auto self = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    glm::vec3 lo(INFINITY), hi(-INFINITY), clo(INFINITY), chi(-INFINITY);
    for (std::uint32_t k = first; k < last; ++k) {
      for (int i = 0; i < 3; ++i) {
        lo = glm::min(lo, vertices[triangles[order[k]][i]]);
        hi = glm::max(hi, vertices[triangles[order[k]][i]]);
      }
      clo = glm::min(clo, centre[order[k]]);
      chi = glm::max(chi, centre[order[k]]);
    }
    nodes[self].lo = lo;
    nodes[self].hi = hi;
    if (last - first <= kLeaf) {
      nodes[self].first_or_second = first;
      nodes[self].count = last - first;
      return;
    }
    const glm::vec3 ext = chi - clo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const std::uint32_t mid = first + (last - first) / 2;
    std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + last,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centre[a][axis] < centre[b][axis] || (centre[a][axis] == centre[b][axis] && a < b);
                     });
    split(first, mid, centre);
    nodes[self].first_or_second = static_cast<std::uint32_t>(nodes.size());
    split(mid, last, centre);
  }

  // The nearest triangle to p within sqrt(r2), if nearer than `best` so far
  // (ties: the lower triangle id).
  struct Nearest {
    glm::vec3 p;
    float r2;
    float reach = -1.0f;  // the ball's radius plus the tolerance (< 0: not yet taken from r2)
    std::uint32_t best = UINT32_MAX;
    glm::vec3 point{0.0f};
    Feature feature = kFace;
    // The triangle of record l (its id: `id`) nearer than the best so far?
    void offer(const Leaf& l, std::uint32_t id) {
      Feature f;
      const glm::vec3 q = nearestOnTriangle(p, l.a, l.b, l.c, f);
      const glm::vec3 d = p - q;
      const float d2 = glm::dot(d, d);
      if (d2 < r2 || (d2 == r2 && id < best)) {
        r2 = d2;
        best = id;
        point = q;
        feature = f;
        reach = -1.0f;  // to be set from r2 by the tree
      }
    }
    // Whether a triangle with this record's sphere and plane can be within
    // the ball.
    bool near(const Leaf& l, float tolerance) {
      if (reach < 0.0f) reach = std::sqrt(r2) + tolerance;
      const glm::vec3 d = p - l.centre;
      const float out = reach + l.radius;
      if (glm::dot(d, d) > out * out) return false;
      return !(std::fabs(glm::dot(l.n, p - l.a)) > reach);
    }
  };
  // the triangle of record k (leaf order) to the search, if its plane and
  // sphere let it be nearer than the ball
  void offerLeaf(Nearest& q, std::uint32_t k) const {
    const Leaf& l = leaves[k];
    if (q.near(l, tolerance)) q.offer(l, order[k]);
  }
  void offer(Nearest& q, std::uint32_t t) const { offerLeaf(q, rank[t]); }  // by triangle id
  // The search of a ball within the cells' reach (the reach and the
  // ball's rounding allowed for): every triangle that can be nearer than
  // the ball's edge is offered, as by search(), so the answer is the same.
  bool searchCells(Nearest& q) const {
    if (q.reach < 0.0f) q.reach = std::sqrt(q.r2) + tolerance;
    if (!(q.reach <= cells.reach())) return false;
    cells.forEachNear(q.p, q.reach, [&](std::uint32_t k) { offerLeaf(q, k); });
    return true;
  }
  void search(Nearest& q) const {
    std::uint32_t stack[64];
    int top = 0;
    if (nodes.empty() || boxDistance2(q.p, nodes[0].lo, nodes[0].hi) > q.r2) return;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes[stack[--top]];
      if (boxDistance2(q.p, node.lo, node.hi) > q.r2) continue;  // the ball shrank
      if (node.count > 0) {
        for (std::uint32_t k = node.first_or_second; k < node.first_or_second + node.count; ++k) offerLeaf(q, k);
        continue;
      }
      const std::uint32_t a = static_cast<std::uint32_t>(&node - nodes.data()) + 1, b = node.first_or_second;
      const float da = boxDistance2(q.p, nodes[a].lo, nodes[a].hi);
      const float db = boxDistance2(q.p, nodes[b].lo, nodes[b].hi);
      // the nearer child is searched first: pushed last. A median split
      // is at most log2(triangles) deep and the stack holds at most one
      // node a level more than that: 64 are never reached.
      const std::uint32_t near = da <= db ? a : b, far = da <= db ? b : a;
      if (std::max(da, db) <= q.r2) stack[top++] = far;
      if (std::min(da, db) <= q.r2) stack[top++] = near;
    }
  }
};

void ExactDistance::Tree::init(const TriangleMesh& mesh) {
  Tree& t = *this;
  t.vertices = mesh.vertices;
  t.triangles = mesh.triangles;
  const std::size_t nt = t.triangles.size();
  t.face_normal.resize(nt);
  t.vertex_normal.assign(t.vertices.size(), glm::vec3(0.0f));
  for (std::size_t k = 0; k < nt; ++k) {
    const glm::u32vec3 tri = t.triangles[k];
    const glm::vec3 a = t.vertices[tri.x], b = t.vertices[tri.y], c = t.vertices[tri.z];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    t.face_normal[k] = len > 0.0f ? n / len : glm::vec3(0.0f);
    const glm::vec3 corner[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
      const glm::vec3 e1 = corner[(i + 1) % 3] - corner[i], e2 = corner[(i + 2) % 3] - corner[i];
      const float l1 = glm::length(e1), l2 = glm::length(e2);
      if (!(l1 > 0.0f && l2 > 0.0f)) continue;
      const float angle = std::acos(std::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0f, 1.0f));
      t.vertex_normal[tri[i]] += angle * t.face_normal[k];
    }
  }
  // Edge pseudo-normals: the sum of the normals of the faces at the edge.
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t slot;  // 3 triangle + edge
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nt);
  for (std::size_t k = 0; k < nt; ++k)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t.triangles[k][i], b = t.triangles[k][(i + 1) % 3];
      uses.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b),
                      static_cast<std::uint32_t>(3 * k + static_cast<std::size_t>(i))});
    }
  std::sort(uses.begin(), uses.end(),
            [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key || (x.key == y.key && x.slot < y.slot); });
  t.edge_normal.assign(3 * nt, glm::vec3(0.0f));
  for (std::size_t a = 0; a < uses.size();) {
    std::size_t b = a;
    glm::vec3 sum(0.0f);
    while (b < uses.size() && uses[b].key == uses[a].key) sum += t.face_normal[uses[b++].slot / 3];
    for (std::size_t k = a; k < b; ++k) t.edge_normal[uses[k].slot] = sum;
    a = b;
  }
  t.build();
}

ExactDistance::ExactDistance(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw MeshError("exact distance: the mesh has no triangles");
  const MeshParts parts = meshParts(mesh);
  const std::vector<std::uint32_t>& part = parts.of_triangle;
  local_.resize(mesh.triangles.size());
  part_ = part;
  for (std::uint32_t k = 0; k < parts.count(); ++k) {
    TriangleMesh sub;
    std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
    auto tree = std::make_unique<Tree>();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (part[t] != k) continue;
      glm::u32vec3 tri;
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t v = mesh.triangles[t][i];
        if (remap[v] == UINT32_MAX) {
          remap[v] = static_cast<std::uint32_t>(sub.vertices.size());
          sub.vertices.push_back(mesh.vertices[v]);
        }
        tri[i] = remap[v];
      }
      local_[t] = static_cast<std::uint32_t>(sub.triangles.size());
      tree->global.push_back(static_cast<std::uint32_t>(t));
      sub.triangles.push_back(tri);
    }
    tree->init(sub);
    trees_.push_back(std::move(tree));
  }
}

ExactDistance::~ExactDistance() = default;

bool ExactDistance::nearest(const glm::vec3& p, float radius, const std::int32_t* seeds, int count,
                            Nearest& out) const {
  float r2 = radius * radius * 1.0001f;
  if (!(r2 < std::numeric_limits<float>::max())) r2 = std::numeric_limits<float>::infinity();
  bool found = false;
  for (std::size_t k = 0; k < trees_.size(); ++k) {
    const Tree& t = *trees_[k];
    Tree::Nearest q{p, r2};
    for (int s = 0; s < count; ++s) {
      if (!(seeds[s] >= 0 && static_cast<std::size_t>(seeds[s]) < part_.size() &&
            part_[static_cast<std::size_t>(seeds[s])] == k))
        continue;
      // a seed offered again changes nothing: the corners of a cell share
      // their nearest triangles
      if (std::find(seeds, seeds + s, seeds[s]) != seeds + s) continue;
      t.offer(q, local_[static_cast<std::size_t>(seeds[s])]);
      // a ball the cells answer needs no more seeds (the first is the
      // point's own last nearest triangle, usually near enough)
      if (q.best != UINT32_MAX && std::sqrt(q.r2 * 1.0001f) + t.tolerance <= t.cells.reach()) break;
    }
    if (q.best != UINT32_MAX) {
      q.r2 *= 1.0001f;  // room for rounding: the same triangle again
      q.reach = -1.0f;
    }
    if (!t.searchCells(q)) t.search(q);
    if (q.best == UINT32_MAX) continue;
    // Union of the parts: the lowest signed distance of any part (exact
    // outside them all, the depth in the part it is deepest in inside).
    const glm::vec3 d = p - q.point;
    const float dist = std::sqrt(glm::dot(d, d));
    const glm::vec3 pn = t.pseudoNormal(q.best, q.feature);
    const float side = glm::dot(d, pn) < 0.0f ? -1.0f : 1.0f;
    const float signed_distance = side * dist;
    if (found && !(signed_distance < out.signed_distance)) continue;
    found = true;
    out.signed_distance = signed_distance;
    out.triangle = t.global[q.best];
    const float l = glm::length(pn);
    out.normal = dist > 1e-7f ? side * d / dist : (l > 0.0f ? pn / l : t.face_normal[q.best]);
  }
  return found;
}

float ExactDistance::signedDistance(const glm::vec3& p, const std::int32_t* seeds, int count, glm::vec3* normal,
                                    std::uint32_t* triangle) const {
  Nearest near;
  if (!nearest(p, std::numeric_limits<float>::infinity(), seeds, count, near))
    return std::numeric_limits<float>::infinity();
  if (normal) *normal = near.normal;
  if (triangle) *triangle = near.triangle;
  return near.signed_distance;
}

}  // namespace loosehair
