// Strands as polylines in files, chosen by extension (method.md §6.2 export and
// import): Wavefront OBJ (`v` and `l` elements), PLY (vertex and edge
// elements) and the binary `.hair` format of Cem Yuksel's cyHair (a 128-byte
// header, a 16-bit segment count per strand, then float x y z points).
// Coordinates are the head frame in metres (+Y up, face towards +Z).
#pragma once

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace loosehair {

struct StrandSet;

/// Polylines read from a file: strand k is points[first[k], first[k+1]).
struct Polylines {
  std::vector<glm::vec3> points;
  std::vector<std::uint32_t> first{0};
  std::size_t size() const { return first.size() - 1; }
};

/// Writes the strands to `path` (.obj, .ply or .hair), the whole file or
/// nothing. Throws FileError naming the file (an unknown extension, a
/// strand of more than 65536 points for .hair, a failed write).
void writeStrands(const StrandSet& strands, const std::string& path);
void writePolylines(const Polylines& lines, const std::string& path);
/// The bytes writePolylines writes to `path` (its format by extension).
std::string polylineFileBytes(const Polylines& lines, const std::string& path);

/// Reads polylines from a .obj (its `l` elements), .ply (vertex x y z and
/// edge vertex1 vertex2, ASCII or binary little-endian) or .hair file.
/// Throws FileError naming the file and what is wrong with it.
Polylines readPolylines(const std::string& path);

}  // namespace loosehair
