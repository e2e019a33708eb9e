#include "loosehair/mesh.hpp"

#include "loosehair/file_io.hpp"
#include "mesh/mesh_file_checks.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace loosehair {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// ---- OpenMesh formats ---------------------------------------------------------
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

TriangleMesh fromOpenMesh(const OMesh& om) {
  TriangleMesh mesh;
  mesh.vertices.reserve(om.n_vertices());
  for (auto v : om.vertices()) {
    const auto& p = om.point(v);
    mesh.vertices.emplace_back(p[0], p[1], p[2]);
  }
  mesh.triangles.reserve(om.n_faces());
  for (auto f : om.faces()) {
    std::array<std::uint32_t, 3> idx{};
    int k = 0;
    for (auto v : om.fv_range(f)) {
      if (k < 3) idx[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(v.idx());
      ++k;
    }
    if (k == 3) mesh.triangles.emplace_back(idx[0], idx[1], idx[2]);
  }
  return mesh;
}

void toOpenMesh(const TriangleMesh& mesh, OMesh& om) {
  std::vector<OMesh::VertexHandle> vh;
  vh.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) vh.push_back(om.add_vertex(OMesh::Point(v.x, v.y, v.z)));
  for (const auto& t : mesh.triangles) om.add_face(vh[t.x], vh[t.y], vh[t.z]);
}

// OpenMesh reports on streams of its own, line by line (up to tens of
// thousands of lines for a broken file): they are silenced while it reads,
// and what it would have said is checked here instead.
class QuietOpenMesh {
 public:
  QuietOpenMesh() {
    ::omerr().disable();
    ::omlog().disable();
    ::omout().disable();
  }
  ~QuietOpenMesh() {
    ::omerr().enable();
    ::omlog().enable();
    ::omout().enable();
  }
  QuietOpenMesh(const QuietOpenMesh&) = delete;
  QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;
};

// OBJ, PLY, OFF and STL: read whole, checked (mesh_file_checks.hpp); PLY and
// OFF come out of the checks themselves, OBJ and STL go on to OpenMesh.
TriangleMesh readPolygonFile(const std::string& path, const std::string& ext, std::size_t max_faces) {
  std::string bytes;
  try {
    bytes = readRegularFile(path, kMaxMeshFileBytes);
  } catch (const FileError& e) {
    throw MeshError(e.what());
  }
  MeshFileCounts counts = checkMeshFile(path, bytes, ext, max_faces);
  if (counts.has_mesh) return std::move(counts.mesh);  // PLY and OFF: read by the check itself
  OMesh om;
  OpenMesh::IO::Options opt;
  // Binary variants, told from the content (a stream reader cannot look):
  // a PLY header naming a binary format, an STL whose triangle count fits
  // its size (checkMeshFile refuses any other non-ASCII STL).
  if ((ext == ".ply" &&
       bytes.substr(0, std::min<std::size_t>(bytes.size(), 512)).find("format binary") != std::string::npos) ||
      (ext == ".stl" && isBinaryStl(bytes)))
    opt += OpenMesh::IO::Options::Binary;
  bool ok = false;
  {
    const QuietOpenMesh quiet;
    std::istringstream in(bytes);
    try {
      ok = OpenMesh::IO::read_mesh(om, in, ext.substr(1), opt);
    } catch (const std::bad_alloc&) {
      throw MeshError(path + ": the mesh is too large to read");
    }
  }
  if (!ok) throw MeshError(path + ": not a valid " + ext + " mesh (the reader could not make sense of it)");
  // (more is fine: OpenMesh duplicates vertices where faces meet badly)
  if (counts.vertices > 0 && om.n_vertices() < counts.vertices)
    throw MeshError(path + ": the file defines " + std::to_string(counts.vertices) + " vertices but " +
                    std::to_string(om.n_vertices()) + " could be read (a malformed vertex?)");
  return fromOpenMesh(om);
}

// ---- glTF / GLB -------------------------------------------------------------------
glm::mat4 nodeMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[static_cast<std::size_t>(4 * c + r)];
    return glm::mat4(m);
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (node.translation.size() == 3)
    t = glm::translate(glm::dmat4(1.0), glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    r = glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return glm::mat4(t * r * s);
}

// Reads element `k` of an accessor as up to 3 components of type double.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int index, const std::string& path) : path_(path) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
      throw MeshError(path + ": an accessor index is out of range");
    acc_ = &model.accessors[static_cast<std::size_t>(index)];
    if (acc_->bufferView < 0) throw MeshError(path + ": sparse or empty accessors are not supported");
    if (static_cast<std::size_t>(acc_->bufferView) >= model.bufferViews.size())
      throw MeshError(path + ": accessor " + std::to_string(index) + " names buffer view " +
                      std::to_string(acc_->bufferView) + " of " + std::to_string(model.bufferViews.size()));
    const auto& view = model.bufferViews[static_cast<std::size_t>(acc_->bufferView)];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size())
      throw MeshError(path + ": buffer view " + std::to_string(acc_->bufferView) + " names buffer " +
                      std::to_string(view.buffer) + " of " + std::to_string(model.buffers.size()));
    const auto& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
    comps_ = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc_->type));
    comp_size_ = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc_->componentType));
    if (comps_ <= 0 || comp_size_ <= 0) throw MeshError(path + ": an accessor has an unknown type");
    stride_ = acc_->ByteStride(view);
    if (stride_ <= 0) throw MeshError(path + ": an accessor has an invalid byte stride");
    const std::size_t size = buffer.data.size();
    // every sum below within the buffer's size, so none can wrap around
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset ||
        acc_->byteOffset > size - view.byteOffset ||
        (acc_->count > 0 && acc_->count - 1 > size / static_cast<std::size_t>(stride_)))
      throw MeshError(path + ": an accessor reads past the end of its buffer");
    const std::size_t begin = view.byteOffset + acc_->byteOffset;
    const std::size_t need = acc_->count == 0 ? 0
                                              : begin + (acc_->count - 1) * static_cast<std::size_t>(stride_) +
                                                    static_cast<std::size_t>(comps_ * comp_size_);
    if (need > buffer.data.size() || view.byteOffset + view.byteLength > buffer.data.size())
      throw MeshError(path + ": an accessor reads past the end of its buffer");
    data_ = buffer.data.data() + begin;
  }
  std::size_t count() const { return acc_->count; }
  int components() const { return comps_; }
  double get(std::size_t k, int c) const {
    const unsigned char* p = data_ + k * static_cast<std::size_t>(stride_) + static_cast<std::size_t>(c * comp_size_);
    switch (acc_->componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t u;
        std::memcpy(&u, p, 4);
        return u;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t u;
        std::memcpy(&u, p, 2);
        return u;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return *p;
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t u;
        std::memcpy(&u, p, 2);
        return u;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return static_cast<signed char>(*p);
      default:
        throw MeshError(path_ + ": an accessor has an unsupported component type");
    }
  }

 private:
  const tinygltf::Accessor* acc_ = nullptr;
  const unsigned char* data_ = nullptr;
  int comps_ = 0, comp_size_ = 0, stride_ = 0;
  std::string path_;
};

void appendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim, const glm::mat4& xf,
                     const std::string& path, TriangleMesh& out) {
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
    return;  // points and lines carry no surface
  auto it = prim.attributes.find("POSITION");
  if (it == prim.attributes.end()) throw MeshError(path + ": a primitive has no POSITION attribute");
  AccessorReader pos(model, it->second, path);
  if (pos.components() != 3) throw MeshError(path + ": POSITION must be a VEC3 accessor");
  const auto base = static_cast<std::uint32_t>(out.vertices.size());
  for (std::size_t k = 0; k < pos.count(); ++k) {
    const glm::vec4 p(static_cast<float>(pos.get(k, 0)), static_cast<float>(pos.get(k, 1)),
                      static_cast<float>(pos.get(k, 2)), 1.0f);
    out.vertices.emplace_back(xf * p);
  }
  std::vector<std::uint32_t> idx;
  if (prim.indices >= 0) {
    AccessorReader ind(model, prim.indices, path);
    idx.resize(ind.count());
    for (std::size_t k = 0; k < ind.count(); ++k) {
      const double v = ind.get(k, 0);
      if (v < 0 || v >= static_cast<double>(pos.count()))
        throw MeshError(path + ": an index (" + std::to_string(static_cast<long long>(v)) +
                        ") is out of range of its " + std::to_string(pos.count()) + " vertices");
      idx[k] = static_cast<std::uint32_t>(v);
    }
  } else {
    idx.resize(pos.count());
    std::iota(idx.begin(), idx.end(), 0u);
  }
  const bool mirrored = glm::determinant(glm::mat3(xf)) < 0.0f;
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (mirrored) std::swap(b, c);
    out.triangles.emplace_back(base + a, base + b, base + c);
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (std::size_t k = 0; k + 2 < idx.size(); k += 3) add(idx[k], idx[k + 1], idx[k + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t k = 0; k + 2 < idx.size(); ++k) {
      if (k % 2 == 0)
        add(idx[k], idx[k + 1], idx[k + 2]);
      else
        add(idx[k + 1], idx[k], idx[k + 2]);
    }
  } else {
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) add(idx[0], idx[k], idx[k + 1]);
  }
}

TriangleMesh readGltf(const std::string& path, bool binary) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    std::string msg = err.empty() ? "cannot read the file" : err;
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
    throw MeshError(path + ": cannot read glTF: " + msg);
  }
  TriangleMesh out;
  // Walk the default scene (or every root node) applying node transforms.
  std::vector<std::pair<int, glm::mat4>> stack;
  if (!model.scenes.empty()) {
    const int si = model.defaultScene >= 0 ? model.defaultScene : 0;
    for (int n : model.scenes[static_cast<std::size_t>(si)].nodes) stack.emplace_back(n, glm::mat4(1.0f));
  } else {
    for (std::size_t n = 0; n < model.nodes.size(); ++n) stack.emplace_back(static_cast<int>(n), glm::mat4(1.0f));
  }
  // glTF nodes form a forest: a node reached twice is in a cycle or has two
  // parents, either way not a valid file (and a cycle would never end).
  std::vector<char> reached(model.nodes.size(), 0);
  while (!stack.empty()) {
    auto [ni, parent] = stack.back();
    stack.pop_back();
    if (ni < 0 || static_cast<std::size_t>(ni) >= model.nodes.size())
      throw MeshError(path + ": node index " + std::to_string(ni) + " is out of range (" +
                      std::to_string(model.nodes.size()) + " nodes)");
    if (reached[static_cast<std::size_t>(ni)]++)
      throw MeshError(path + ": node " + std::to_string(ni) +
                      " is reached twice: the node hierarchy has a cycle or a node with two parents");
    const auto& node = model.nodes[static_cast<std::size_t>(ni)];
    const glm::mat4 xf = parent * nodeMatrix(node);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size())
        throw MeshError(path + ": a mesh index is out of range");
      for (const auto& prim : model.meshes[static_cast<std::size_t>(node.mesh)].primitives)
        appendPrimitive(model, prim, xf, path, out);
    }
    for (int c : node.children) stack.emplace_back(c, xf);
  }
  return out;
}

// Merges vertices with bit-identical positions (glTF and STL split vertices
// at seams; the simulator needs the surface's connectivity).
void weld(TriangleMesh& mesh) {
  struct Key {
    std::uint32_t a, b, c;
    bool operator==(const Key& o) const { return a == o.a && b == o.b && c == o.c; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (static_cast<std::size_t>(k.a) * 73856093u) ^ (static_cast<std::size_t>(k.b) * 19349663u) ^
             (static_cast<std::size_t>(k.c) * 83492791u);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> index;
  index.reserve(mesh.vertices.size());
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  std::vector<glm::vec3> kept;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    glm::vec3 p = mesh.vertices[v] + glm::vec3(0.0f);  // -0 becomes +0
    Key k{};
    std::memcpy(&k.a, &p.x, 4);
    std::memcpy(&k.b, &p.y, 4);
    std::memcpy(&k.c, &p.z, 4);
    auto [it, fresh] = index.emplace(k, static_cast<std::uint32_t>(kept.size()));
    if (fresh) kept.push_back(mesh.vertices[v]);
    remap[v] = it->second;
  }
  for (auto& t : mesh.triangles) t = glm::u32vec3(remap[t.x], remap[t.y], remap[t.z]);
  mesh.vertices = std::move(kept);
}

}  // namespace

Axis parseAxis(const std::string& text) {
  const std::string t = lower(text);
  if (t == "+x" || t == "x") return Axis::PosX;
  if (t == "-x") return Axis::NegX;
  if (t == "+y" || t == "y") return Axis::PosY;
  if (t == "-y") return Axis::NegY;
  if (t == "+z" || t == "z") return Axis::PosZ;
  if (t == "-z") return Axis::NegZ;
  throw std::invalid_argument("must be one of \"+x\", \"-x\", \"+y\", \"-y\", \"+z\", \"-z\", got \"" + text + "\"");
}

glm::vec3 axisVector(Axis a) {
  switch (a) {
    case Axis::PosX:
      return {1, 0, 0};
    case Axis::NegX:
      return {-1, 0, 0};
    case Axis::PosY:
      return {0, 1, 0};
    case Axis::NegY:
      return {0, -1, 0};
    case Axis::PosZ:
      return {0, 0, 1};
    case Axis::NegZ:
      return {0, 0, -1};
  }
  return {0, 1, 0};
}

TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options, MeshReport* report) {
  if (!(options.scale > 0.0f) || !std::isfinite(options.scale))
    throw MeshError(path + ": scale must be a positive number, got " + std::to_string(options.scale));
  const glm::vec3 up = axisVector(options.up), front = axisVector(options.front);
  if (std::abs(glm::dot(up, front)) > 0.5f) throw MeshError(path + ": the up and front axes must be different axes");
  try {
    (void)checkRegularFile(path, kMaxMeshFileBytes);
  } catch (const FileError& e) {
    throw MeshError(std::string(e.what()) + " (a mesh)");
  }
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  TriangleMesh mesh;
  if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl")
    mesh = readPolygonFile(path, ext, options.max_faces);
  else if (ext == ".gltf" || ext == ".glb") {
    checkGltfFaceCount(path, ext == ".glb", options.max_faces);
    mesh = readGltf(path, ext == ".glb");
  } else
    throw MeshError(
        path + ": " +
        (ext.empty() ? std::string("the file name has no extension") : "unknown mesh format \"" + ext + "\"") +
        " (use .obj, .ply, .off, .stl, .gltf or .glb)");
  // polygons became fans of triangles, and the files' counts were claims
  checkFaceCount(path, mesh.triangles.size(), options.max_faces);
  weld(mesh);
  // File frame -> simulator frame: up -> +Y, front -> +Z, right = up x front -> +X.
  const glm::vec3 right = glm::cross(up, front);
  for (auto& p : mesh.vertices) {
    const glm::vec3 q(glm::dot(p, right), glm::dot(p, up), glm::dot(p, front));
    p = options.scale * q + options.offset;
  }
  std::size_t parts_dropped = 0, triangles_dropped = 0;
  if (options.drop_open_parts) dropOpenMinorParts(mesh, parts_dropped, triangles_dropped);
  MeshReport r = checkMesh(mesh, path);
  r.parts_dropped = parts_dropped;
  r.triangles_dropped = triangles_dropped;
  if (report) *report = r;
  return mesh;
}

MeshParts meshParts(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : mesh.triangles) {
    parent[find(t.y)] = find(t.x);
    parent[find(t.z)] = find(t.x);
  }
  MeshParts parts;
  std::vector<std::uint32_t> label(mesh.vertices.size(), UINT32_MAX);
  parts.of_triangle.resize(mesh.triangles.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const std::uint32_t root = find(mesh.triangles[k].x);
    if (label[root] == UINT32_MAX) {
      label[root] = static_cast<std::uint32_t>(parts.triangles.size());
      parts.triangles.push_back(0);
    }
    parts.of_triangle[k] = label[root];
    ++parts.triangles[label[root]];
  }
  return parts;
}

std::uint32_t MeshParts::largest() const {
  std::uint32_t best = 0;
  for (std::uint32_t k = 1; k < triangles.size(); ++k)
    if (triangles[k] > triangles[best]) best = k;
  return best;
}

void dropOpenMinorParts(TriangleMesh& mesh, std::size_t& parts_dropped, std::size_t& triangles_dropped) {
  parts_dropped = triangles_dropped = 0;
  const std::size_t nv = mesh.vertices.size();
  if (mesh.triangles.empty() || nv == 0) return;
  for (const auto& t : mesh.triangles)
    if (t.x >= nv || t.y >= nv || t.z >= nv) return;  // checkMesh names it
  const MeshParts parts = meshParts(mesh);
  if (parts.count() < 2) return;
  // Boundary edges (used once) of each part.
  std::vector<std::size_t> open_edges(parts.count(), 0);
  std::vector<std::uint64_t> keys;
  keys.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      keys.push_back((static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b));
    }
  std::vector<std::uint32_t> part_of_vertex(nv, 0);
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
    for (int i = 0; i < 3; ++i) part_of_vertex[mesh.triangles[k][i]] = parts.of_triangle[k];
  std::sort(keys.begin(), keys.end());
  for (std::size_t a = 0; a < keys.size();) {
    std::size_t b = a;
    while (b < keys.size() && keys[b] == keys[a]) ++b;
    if (b - a == 1) ++open_edges[part_of_vertex[keys[a] >> 32]];
    a = b;
  }
  // A part with no area is not a shell but broken input: left for
  // checkMesh to reject as degenerate.
  std::vector<std::uint8_t> has_area(parts.count(), 0);
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& t = mesh.triangles[k];
    const glm::dvec3 a(mesh.vertices[t.x]), b(mesh.vertices[t.y]), c(mesh.vertices[t.z]);
    const double area2 = glm::length(glm::cross(b - a, c - a));
    const double scale = glm::dot(b - a, b - a) + glm::dot(c - a, c - a);
    if (area2 > 1e-6 * scale) has_area[parts.of_triangle[k]] = 1;
  }
  const std::uint32_t largest = parts.largest();
  std::vector<std::uint8_t> dropped(parts.count(), 0);
  for (std::uint32_t k = 0; k < parts.count(); ++k) {
    dropped[k] = k != largest && open_edges[k] > 0 && has_area[k];
    if (!dropped[k]) continue;
    ++parts_dropped;
    triangles_dropped += parts.triangles[k];
  }
  std::vector<glm::u32vec3> kept;
  kept.reserve(mesh.triangles.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
    if (!dropped[parts.of_triangle[k]]) kept.push_back(mesh.triangles[k]);
  mesh.triangles = std::move(kept);  // unreferenced vertices: checkMesh drops them
}

void writeObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment) {
  std::string text;
  if (!comment.empty()) {
    std::istringstream lines(comment);
    std::string line;
    while (std::getline(lines, line)) text += "# " + line + '\n';
  }
  char buf[96];
  for (const auto& p : mesh.vertices) {
    std::snprintf(buf, sizeof buf, "v %.6f %.6f %.6f\n", static_cast<double>(p.x), static_cast<double>(p.y),
                  static_cast<double>(p.z));
    text += buf;
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(buf, sizeof buf, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
    text += buf;
  }
  try {
    writeFileAtomically(path, {text});
  } catch (const FileError& e) {
    throw MeshError(e.what());
  }
}

TriangleMesh decimate(const TriangleMesh& mesh, std::size_t target_triangles) {
  if (mesh.triangles.size() <= target_triangles || target_triangles < 4) return mesh;
  OMesh om;
  toOpenMesh(mesh, om);
  om.request_face_normals();
  om.update_face_normals();
  OpenMesh::Decimater::DecimaterT<OMesh> decimater(om);
  OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle no_flips;
  decimater.add(quadric);
  decimater.add(no_flips);
  if (!decimater.initialize()) return mesh;
  decimater.decimate_to_faces(0, target_triangles);
  om.garbage_collection();
  return fromOpenMesh(om);
}

void writeBinaryPly(const TriangleMesh& mesh, const std::string& path) {
  OMesh om;
  toOpenMesh(mesh, om);
  try {
    // OpenMesh writes the temporary (".ply" so that it picks the format);
    // the rename over `path` is checked.
    AtomicFile file(path, ".ply");
    file.finish();
    if (!OpenMesh::IO::write_mesh(om, file.temporary(), OpenMesh::IO::Options::Binary))
      throw MeshError(path + ": cannot write");
    file.commit();
  } catch (const FileError& e) {
    throw MeshError(e.what());
  }
}

std::vector<glm::vec3> vertexNormals(const TriangleMesh& mesh) {
  std::vector<glm::vec3> n(mesh.vertices.size(), glm::vec3(0.0f));
  for (const auto& t : mesh.triangles) {
    const glm::vec3 a = mesh.vertices[t.x], b = mesh.vertices[t.y], c = mesh.vertices[t.z];
    const glm::vec3 fn = glm::cross(b - a, c - a);  // length = 2 area
    n[t.x] += fn;
    n[t.y] += fn;
    n[t.z] += fn;
  }
  for (auto& v : n) {
    const float l = glm::length(v);
    v = l > 0.0f ? v / l : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  return n;
}

}  // namespace loosehair
