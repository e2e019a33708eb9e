// Triangle meshes for heads and bodies (method.md §5 body collisions, §6.1 scalp):
// loading (OBJ, PLY, OFF, STL through OpenMesh; glTF and GLB through
// tinygltf), conversion to the simulator's frame (metres, +Y up, face
// towards +Z) and checks that reject meshes the simulator cannot use.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace loosehair {

/// A mesh that cannot be used. what() names the file and the problem.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A mesh refused for holding more faces than MeshLoadOptions::max_faces.
class MeshTooLargeError : public MeshError {
 public:
  using MeshError::MeshError;
};

struct TriangleMesh {
  std::vector<glm::vec3> vertices;
  std::vector<glm::u32vec3> triangles;  // counter-clockwise seen from outside

  std::size_t size() const { return triangles.size(); }
  glm::vec3 corner(std::size_t t, int k) const { return vertices[triangles[t][k]]; }
};

/// A signed coordinate axis, as written in scene files: "+x", "-y", ...
enum class Axis { PosX, NegX, PosY, NegY, PosZ, NegZ };
/// Parses "+x", "x", "-y", ... (case-insensitive); throws std::invalid_argument.
Axis parseAxis(const std::string& text);
glm::vec3 axisVector(Axis a);

struct MeshLoadOptions {
  /// Multiplies the file's coordinates to get metres (e.g. 0.01 for cm).
  float scale = 1.0f;
  /// The file's up and front (face) axes; they become +Y and +Z.
  Axis up = Axis::PosY;
  Axis front = Axis::PosZ;
  /// Added after scaling and turning (m).
  glm::vec3 offset{0.0f};
  /// Drop the open parts other than the largest (open shells for eyes,
  /// teeth or helper geometry, which enclose no volume and whose rims cannot
  /// be closed); closed parts and the largest part are kept.
  bool drop_open_parts = true;
  /// Refuse a mesh of more faces than this (MeshTooLargeError). PLY, OFF and
  /// binary STL files are refused from their headers' counts, OBJ files while
  /// their faces are checked, before any mesh is built; glTF and ASCII STL
  /// after they are read. The triangles of the loaded mesh (polygons split
  /// into fans) are held to it too.
  std::size_t max_faces = SIZE_MAX;
};

/// What checkMesh found.
struct MeshReport {
  std::size_t vertices = 0, triangles = 0;
  std::size_t degenerate_removed = 0;  // zero-area or repeated-index triangles dropped
  std::size_t boundary_edges = 0;      // edges with one triangle (holes), before filling
  std::size_t holes_filled = 0;        // boundary loops closed by a fan of triangles
  std::size_t nonmanifold_edges = 0;   // edges with three or more triangles
  std::size_t misoriented_edges = 0;   // edges whose two triangles disagree in orientation
  std::size_t components = 0;          // connected pieces (after dropping)
  std::size_t parts_dropped = 0;       // open parts besides the largest, dropped
  std::size_t triangles_dropped = 0;   // their triangles
  double volume = 0;                   // enclosed volume (m^3), after reorientation
  bool flipped = false;                // the whole mesh was turned inside out and fixed
  glm::vec3 lower{0.0f}, upper{0.0f};  // bounding box (m)
  /// The input was closed (after checkMesh the mesh always is: holes are filled).
  bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};

/// Reads a mesh by its extension (.obj .ply .off .stl .gltf .glb), turns
/// polygons into triangles, welds vertices at equal positions, converts to
/// the simulator's frame and runs checkMesh. Throws MeshError.
TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options = {}, MeshReport* report = nullptr);

/// Cleans and checks a mesh in place: drops degenerate triangles and
/// unreferenced vertices, closes holes with a fan of triangles from each
/// hole's centroid, turns an inside-out mesh right way out. Holes are
/// closed when there are at most 4 and each fan is flat (a head cut off at
/// the neck, a bust cut flat), or when they hold at most 2% of the edges (a
/// scan's gaps). Throws MeshError (message starting with `source`) if it is
/// empty, has non-finite coordinates, is flat, is mostly degenerate, has
/// more than 1% non-manifold or misoriented edges, or holes it cannot close.
MeshReport checkMesh(TriangleMesh& mesh, const std::string& source);

/// The connected pieces of a mesh (triangles that share a vertex are in one).
struct MeshParts {
  std::vector<std::uint32_t> of_triangle;  // per triangle: its part, numbered by first triangle
  std::vector<std::size_t> triangles;      // per part: how many triangles
  std::size_t count() const { return triangles.size(); }
  std::uint32_t largest() const;  // the part with the most triangles (ties: the lower number)
};
/// The vertex indices must be in range.
MeshParts meshParts(const TriangleMesh& mesh);

/// Drops the parts (connected pieces) that are open, other than the one with
/// the most triangles (MeshLoadOptions::drop_open_parts); counts what went.
void dropOpenMinorParts(TriangleMesh& mesh, std::size_t& parts_dropped, std::size_t& triangles_dropped);

/// Writes a binary little-endian PLY through OpenMesh (the whole file or
/// nothing): float x y z vertices, triangle faces. Throws MeshError.
void writeBinaryPly(const TriangleMesh& mesh, const std::string& path);

/// Writes a Wavefront OBJ (the whole file or nothing). Throws MeshError.
void writeObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment = "");

/// A copy with at most about `target_triangles` triangles, made by OpenMesh's
/// quadric-error edge-collapse decimater (no normal flips). For drawing:
/// collisions use the full mesh. Returns the mesh unchanged if it is small.
TriangleMesh decimate(const TriangleMesh& mesh, std::size_t target_triangles);

/// Area-weighted vertex normals (unit).
std::vector<glm::vec3> vertexNormals(const TriangleMesh& mesh);

}  // namespace loosehair
