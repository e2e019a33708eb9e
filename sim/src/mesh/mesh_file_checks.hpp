// Checks of a mesh file's text before a library reads it (mesh.cpp): counts
// in PLY and OFF headers that the file cannot hold (they made the readers
// allocate until memory ran out), and in OBJ files every vertex's numbers
// (non-finite ones, which OpenMesh dropped, shifting later indices) and
// every face's vertex indices (out-of-range ones, which it dropped
// silently). Each problem is a MeshError naming the file, the line or
// element, and the value.
#pragma once

#include "loosehair/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace loosehair {

/// What the file says it holds (0 where unknown), and for PLY and OFF the
/// mesh itself, read here (polygons as fans of triangles): OpenMesh's
/// readers of these formats hung or allocated without bound on malformed
/// files the checks could not rule out one by one.
struct MeshFileCounts {
  std::size_t vertices = 0, faces = 0;
  bool has_mesh = false;
  TriangleMesh mesh;
};

/// A binary STL: 80 bytes of header, a triangle count, and 50 bytes a
/// triangle, exactly filling the file.
bool isBinaryStl(const std::string& bytes);

/// Throws MeshTooLargeError when `faces` is above `max_faces`; `counting`:
/// the faces are being counted (OBJ), so the message says "more than".
void checkFaceCount(const std::string& path, std::size_t faces, std::size_t max_faces, bool counting = false);

/// The triangles a glTF file's default scene holds, from its JSON alone
/// (accessor counts of the triangle primitives of the meshes its nodes
/// reach), before any buffer is read: MeshTooLargeError above `max_faces`.
/// Whatever is malformed is left to the reader to name; so are nodes
/// reached twice, counted once here.
void checkGltfFaceCount(const std::string& path, bool binary, std::size_t max_faces);

/// `ext` is the lower-case extension with its dot (".obj", ".ply", ...).
/// A file of more than `max_faces` faces is refused (MeshTooLargeError) as
/// soon as the count is known: from the header for PLY, OFF and binary STL,
/// from its "endfacet"s for ASCII STL, before the faces are read.
MeshFileCounts checkMeshFile(const std::string& path, const std::string& bytes, const std::string& ext,
                             std::size_t max_faces = SIZE_MAX);

}  // namespace loosehair
