#include "loosehair/strand_files.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/style.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace loosehair {
namespace {

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

[[noreturn]] void fail(const std::string& path, const std::string& why) { throw FileError(path + ": " + why); }

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

std::string text3(glm::vec3 p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", p.x, p.y, p.z);
  return buf;
}

}  // namespace

std::string polylineFileBytes(const Polylines& s, const std::string& path) {
  const std::string ext = extension(path);
  const std::size_t n = s.size();
  std::string out;
  if (ext == ".obj") {
    out = "# loosehair strands: " + std::to_string(n) + " polylines, head frame, metres\n";
    for (const glm::vec3& p : s.points) {
      out += "v ";
      out += text3(p);
      out += '\n';
    }
    for (std::size_t k = 0; k < n; ++k) {
      out += "l";
      for (std::uint32_t j = s.first[k]; j < s.first[k + 1]; ++j) {
        out += ' ';
        out += std::to_string(j + 1);
      }
      out += "\n";
    }
  } else if (ext == ".ply") {
    std::size_t edges = 0;
    for (std::size_t k = 0; k < n; ++k) edges += s.first[k + 1] - s.first[k] - 1;
    out =
        "ply\nformat binary_little_endian 1.0\ncomment loosehair strands, head frame, metres\n"
        "element vertex " +
        std::to_string(s.points.size()) + "\nproperty float x\nproperty float y\nproperty float z\nelement edge " +
        std::to_string(edges) + "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    for (const glm::vec3& p : s.points) {
      put(out, p.x);
      put(out, p.y);
      put(out, p.z);
    }
    for (std::size_t k = 0; k < n; ++k)
      for (std::uint32_t j = s.first[k]; j + 1 < s.first[k + 1]; ++j) {
        put(out, static_cast<std::int32_t>(j));
        put(out, static_cast<std::int32_t>(j + 1));
      }
  } else if (ext == ".hair") {
    out.append("HAIR", 4);
    put(out, static_cast<std::uint32_t>(n));
    put(out, static_cast<std::uint32_t>(s.points.size()));
    put(out, static_cast<std::uint32_t>(0x3));       // segments and points arrays
    put(out, static_cast<std::uint32_t>(0));         // default segments
    put(out, 1e-4f);                                 // default thickness
    put(out, 0.0f);                                  // default transparency
    put(out, 0.3f), put(out, 0.2f), put(out, 0.1f);  // default colour
    char info[88] = {};
    std::snprintf(info, sizeof info, "loosehair strands, head frame, metres, +Y up");
    out.append(info, sizeof info);
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t segs = s.first[k + 1] - s.first[k] - 1;
      if (segs > 65535) fail(path, "strand " + std::to_string(k) + " has more than 65536 points, too many for .hair");
      put(out, static_cast<std::uint16_t>(segs));
    }
    for (const glm::vec3& p : s.points) {
      put(out, p.x);
      put(out, p.y);
      put(out, p.z);
    }
  } else {
    fail(path, "unknown strand file type '" + ext + "' (use .obj, .ply or .hair)");
  }
  return out;
}

void writePolylines(const Polylines& s, const std::string& path) {
  const std::string out = polylineFileBytes(s, path);
  writeFileAtomically(path, {out});
}

void writeStrands(const StrandSet& strands, const std::string& path) {
  Polylines p;
  p.points = strands.points;
  p.first = strands.first;
  writePolylines(p, path);
}

namespace {

template <class T>
T get(const std::string& b, std::size_t& at, const std::string& path) {
  if (at + sizeof(T) > b.size()) fail(path, "the file ends early (truncated)");
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

void checkPoint(glm::vec3 p, const std::string& path, std::size_t index) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || std::abs(p.x) > 1e4f ||
      std::abs(p.y) > 1e4f || std::abs(p.z) > 1e4f)
    fail(path, "point " + std::to_string(index) + " is not a finite coordinate within 10 km");
}

// Polylines from edges (i, i+1 chains); each maximal chain is a strand.
Polylines chain(const std::vector<glm::vec3>& pts, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& edges,
                const std::string& path) {
  const std::size_t n = pts.size();
  std::vector<std::int64_t> next(n, -1), prev(n, -1);
  for (auto [a, b] : edges) {
    if (a >= n || b >= n)
      fail(path, "an edge refers to vertex " + std::to_string(std::max(a, b)) + " of " + std::to_string(n));
    if (next[a] != -1 || prev[b] != -1)
      fail(path, "the edges do not form simple polylines (a vertex with two successors)");
    next[a] = b;
    prev[b] = a;
  }
  Polylines out;
  std::vector<std::uint8_t> seen(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (prev[v] != -1 || next[v] == -1) continue;
    for (std::int64_t c = static_cast<std::int64_t>(v); c != -1; c = next[static_cast<std::size_t>(c)]) {
      if (seen[static_cast<std::size_t>(c)]) fail(path, "the edges form a loop");
      seen[static_cast<std::size_t>(c)] = 1;
      out.points.push_back(pts[static_cast<std::size_t>(c)]);
    }
    out.first.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  return out;
}

}  // namespace

namespace {

// cyHair's .hair: a 128-byte header, segment counts, points.
Polylines readHairStrands(const std::string& b, const std::string& path) {
  Polylines out;
  std::size_t at = 0;
  if (b.size() < 128 || b.compare(0, 4, "HAIR") != 0) fail(path, "not a .hair file (no HAIR header)");
  at = 4;
  const auto strands = get<std::uint32_t>(b, at, path), points = get<std::uint32_t>(b, at, path);
  const auto flags = get<std::uint32_t>(b, at, path), default_segments = get<std::uint32_t>(b, at, path);
  at = 128;
  if (!(flags & 0x2)) fail(path, "the file has no points array");
  if (strands == 0 || strands > 50'000'000u || points > 500'000'000u) fail(path, "implausible strand or point count");
  // what the header promises must be in the file before anything is made
  const std::uint64_t promised = 128 + ((flags & 0x1) ? 2ULL * strands : 0) + 12ULL * points;
  if (promised > b.size())
    fail(path, "the header promises " + std::to_string(strands) + " strands and " + std::to_string(points) +
                   " points (" + std::to_string(promised) + " bytes) and the file has " + std::to_string(b.size()) +
                   " bytes (truncated)");
  std::vector<std::uint32_t> segs(strands, default_segments);
  if (flags & 0x1)
    for (auto& s : segs) s = get<std::uint16_t>(b, at, path);
  std::uint64_t total = 0;
  for (auto s : segs) total += s + 1ULL;
  if (total != points)
    fail(path, "the segment counts add up to " + std::to_string(total) + " points, the header says " +
                   std::to_string(points));
  for (std::uint32_t k = 0; k < points; ++k) {
    glm::vec3 p;
    p.x = get<float>(b, at, path);
    p.y = get<float>(b, at, path);
    p.z = get<float>(b, at, path);
    checkPoint(p, path, k);
    out.points.push_back(p);
  }
  std::uint32_t f = 0;
  for (auto s : segs) out.first.push_back(f += s + 1);
  return out;
}

// OBJ: vertices and "l" lines (negative indices from the end).
Polylines readObjStrands(const std::string& b, const std::string& path) {
  Polylines out;
  std::istringstream in(b);
  std::string line;
  std::vector<glm::vec3> v;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      glm::vec3 p;
      if (!(ls >> p.x >> p.y >> p.z)) fail(path, "line " + std::to_string(line_no) + ": a vertex needs x y z");
      checkPoint(p, path, v.size());
      v.push_back(p);
    } else if (tag == "l") {
      std::string tok;
      std::vector<glm::vec3> strand;
      while (ls >> tok) {
        long long i = 0;
        try {
          i = std::stoll(tok);
        } catch (const std::exception&) {
          fail(path, "line " + std::to_string(line_no) + ": '" + tok + "' is not a vertex index");
        }
        if (i < 0) i = static_cast<long long>(v.size()) + i + 1;
        if (i < 1 || i > static_cast<long long>(v.size()))
          fail(path, "line " + std::to_string(line_no) + ": vertex " + tok + " does not exist");
        strand.push_back(v[static_cast<std::size_t>(i - 1)]);
      }
      if (strand.size() < 2) continue;
      out.points.insert(out.points.end(), strand.begin(), strand.end());
      out.first.push_back(static_cast<std::uint32_t>(out.points.size()));
    }
  }
  return out;
}

// PLY: float x, y, z vertices and int vertex1, vertex2 edges, ASCII or
// binary little-endian; the edges chained into strands.
Polylines readPlyStrands(const std::string& b, const std::string& path) {
  const std::size_t end = b.find("end_header");
  if (b.compare(0, 3, "ply") != 0 || end == std::string::npos) fail(path, "not a PLY file");
  // the data start on the line after end_header
  std::size_t after = end + std::strlen("end_header");
  if (after < b.size() && b[after] == '\r') ++after;
  if (end == 0 || b[end - 1] != '\n' || after >= b.size() || b[after] != '\n')
    fail(path, "the header's last line must be \"end_header\" followed by a newline");
  std::istringstream hdr(b.substr(0, end));
  std::string word, format, element;
  std::size_t nv = 0, ne = 0;
  std::vector<std::string> vprops, eprops;
  std::string line;
  while (std::getline(hdr, line)) {
    std::istringstream ls(line);
    ls >> word;
    if (word == "format")
      ls >> format;
    else if (word == "element") {
      std::size_t count = 0;
      ls >> element >> count;
      if (element == "vertex")
        nv = count;
      else if (element == "edge")
        ne = count;
      else if (count > 0)
        fail(path, "element '" + element + "' is not read (only vertex and edge)");
    } else if (word == "property") {
      std::string type, name;
      ls >> type >> name;
      if (type == "list") fail(path, "list properties are not read in strand files");
      (element == "vertex" ? vprops : eprops).push_back(type + " " + name);
    }
  }
  if (vprops.size() != 3 || vprops[0] != "float x" || vprops[1] != "float y" || vprops[2] != "float z")
    fail(path, "vertices must have exactly float x, y, z");
  if (eprops.size() != 2 || (eprops[0] != "int vertex1" && eprops[0] != "int32 vertex1") ||
      (eprops[1] != "int vertex2" && eprops[1] != "int32 vertex2"))
    fail(path, "edges must have exactly int vertex1, vertex2");
  if (nv > 500'000'000u || ne > 500'000'000u) fail(path, "implausible vertex or edge count");
  std::size_t at = after + 1;
  // what the header promises must fit in what follows it (binary: 12 bytes
  // a vertex and 8 an edge; text: at least "0 0 0" and "0 0", each with a
  // separator) before anything is made
  const bool binary = format == "binary_little_endian";
  const std::uint64_t need = binary ? 12ULL * nv + 8ULL * ne : 6ULL * nv + 4ULL * ne;
  if (need > b.size() - at + (binary ? 0 : 1))  // (text: the last separator may be missing)
    fail(path, "the header promises " + std::to_string(nv) + " vertices and " + std::to_string(ne) +
                   " edges, more than the " + std::to_string(b.size() - at) + " bytes after it hold (truncated)");
  std::vector<glm::vec3> v(nv);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges(ne);
  if (format == "binary_little_endian") {
    for (std::size_t k = 0; k < nv; ++k) {
      v[k].x = get<float>(b, at, path);
      v[k].y = get<float>(b, at, path);
      v[k].z = get<float>(b, at, path);
      checkPoint(v[k], path, k);
    }
    for (auto& e : edges) {
      const auto a = get<std::int32_t>(b, at, path), c = get<std::int32_t>(b, at, path);
      if (a < 0 || c < 0) fail(path, "a negative vertex index in an edge");
      e = {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(c)};
    }
  } else if (format == "ascii") {
    std::istringstream body(b.substr(at));
    for (std::size_t k = 0; k < nv; ++k) {
      if (!(body >> v[k].x >> v[k].y >> v[k].z)) fail(path, "the vertex list ends early");
      checkPoint(v[k], path, k);
    }
    for (auto& e : edges) {
      long long a, c;
      if (!(body >> a >> c) || a < 0 || c < 0 || a > UINT32_MAX || c > UINT32_MAX) fail(path, "a bad edge");
      e = {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(c)};
    }
  } else {
    fail(path, "PLY format '" + format + "' is not read (ascii or binary_little_endian)");
  }
  return chain(v, edges, path);
}

}  // namespace

Polylines readPolylines(const std::string& path) {
  const std::string ext = extension(path);
  const std::string b = readRegularFile(path, kMaxMeshFileBytes);
  Polylines out;
  if (ext == ".hair")
    out = readHairStrands(b, path);
  else if (ext == ".obj")
    out = readObjStrands(b, path);
  else if (ext == ".ply")
    out = readPlyStrands(b, path);
  else
    fail(path, "unknown strand file type '" + ext + "' (use .obj, .ply or .hair)");
  if (out.size() == 0) fail(path, "holds no strands of two or more points");
  return out;
}

}  // namespace loosehair
