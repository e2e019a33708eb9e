#include "mesh_file_checks.hpp"

#include "loosehair/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string_view>

namespace loosehair {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) { throw MeshError(path + ": " + why); }

std::string_view nextLine(const std::string& bytes, std::size_t& at) {
  const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
  std::string_view line(bytes.data() + at, end - at);
  at = end + 1;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

std::string shown(std::string_view s) {
  std::string t(s.substr(0, 40));
  if (s.size() > 40) t += "...";
  return t;
}

// A count from a header: a whole number in [0, limit].
std::size_t count(const std::string& path, const std::string& what, const std::string& token,
                  std::size_t limit) {
  if (token.empty() || !std::all_of(token.begin(), token.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
    fail(path, "the header's count of " + what + " is \"" + shown(token) + "\", not a whole number >= 0");
  errno = 0;
  const unsigned long long v = std::strtoull(token.c_str(), nullptr, 10);
  if (errno != 0 || v > limit)
    fail(path, "the header claims " + token + " " + what + ", more than a file of this size can hold");
  return static_cast<std::size_t>(v);
}

MeshFileCounts checkPly(const std::string& path, const std::string& bytes) {
  std::size_t at = 0;
  if (nextLine(bytes, at) != "ply") fail(path, "not a PLY file (it does not start with \"ply\")");
  MeshFileCounts c;
  // every vertex needs three numbers and every face a count and three
  // indices: at least a byte each, two in ASCII
  const std::size_t size = bytes.size();
  bool ended = false;
  while (at < size) {
    const std::string line(nextLine(bytes, at));
    std::istringstream in(line);
    std::string word, name, n;
    in >> word;
    if (word == "end_header") {
      ended = true;
      break;
    }
    if (word != "element") continue;
    in >> name >> n;
    if (name == "vertex") c.vertices = count(path, "vertices", n, size / 3);
    else if (name == "face") c.faces = count(path, "faces", n, size / 4);
    else (void)count(path, name, n, size);
  }
  if (!ended) fail(path, "the PLY header has no end_header line");
  return c;
}

MeshFileCounts checkOff(const std::string& path, const std::string& bytes) {
  std::size_t at = 0;
  std::string_view first = nextLine(bytes, at);
  while (!first.empty() && std::isspace(static_cast<unsigned char>(first.front()))) first.remove_prefix(1);
  if (first.substr(0, 3).find("OFF") == std::string_view::npos && first.find("OFF") == std::string_view::npos)
    fail(path, "not an OFF file (its first line does not name OFF)");
  // the counts: on the first line after "OFF", or on the next line that is
  // not a comment
  std::string counts(first.substr(first.find("OFF") + 3));
  while (counts.find_first_not_of(" \t") == std::string::npos && at < bytes.size()) {
    std::string_view line = nextLine(bytes, at);
    if (!line.empty() && line.front() == '#') continue;
    counts = std::string(line);
  }
  std::istringstream in(counts);
  std::string nv, nf;
  in >> nv >> nf;
  MeshFileCounts c;
  c.vertices = count(path, "vertices", nv, bytes.size() / 3);
  c.faces = count(path, "faces", nf, bytes.size() / 4);
  return c;
}

// OBJ: "v x y z" and "f a b c ..." (a as i, i/t, i//n or i/t/n; negative
// indices count back from the last vertex).
MeshFileCounts checkObj(const std::string& path, const std::string& bytes) {
  MeshFileCounts c;
  std::size_t at = 0, line_no = 0;
  while (at < bytes.size()) {
    const std::string_view line = nextLine(bytes, at);
    ++line_no;
    std::size_t p = 0;
    while (p < line.size() && (line[p] == ' ' || line[p] == '\t')) ++p;
    if (line.size() < p + 2 || (line[p + 1] != ' ' && line[p + 1] != '\t')) continue;
    const char kind = line[p];
    if (kind != 'v' && kind != 'f') continue;
    const std::string rest(line.substr(p + 2));
    const std::string where = "line " + std::to_string(line_no) + ": ";
    if (kind == 'v') {
      const char* s = rest.c_str();
      for (int k = 0; k < 3; ++k) {
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(s, &end);
        if (end == s) fail(path, where + "vertex " + std::to_string(c.vertices + 1) +
                                     " needs three numbers: \"" + shown(line) + "\"");
        if (!std::isfinite(d) || (errno == ERANGE && std::abs(d) > 1.0))
          fail(path, where + "vertex " + std::to_string(c.vertices + 1) + " has a coordinate that is not a finite number: \"" +
                         shown(line) + "\"");
        s = end;
      }
      ++c.vertices;
    } else {
      std::istringstream in(rest);
      std::string ref;
      int corners = 0;
      while (in >> ref) {
        const std::string index = ref.substr(0, ref.find('/'));
        char* end = nullptr;
        errno = 0;
        const long long i = std::strtoll(index.c_str(), &end, 10);
        if (index.empty() || *end != '\0' || errno != 0)
          fail(path, where + "face " + std::to_string(c.faces + 1) + ": \"" + shown(ref) +
                         "\" is not a vertex index");
        const long long resolved = i < 0 ? static_cast<long long>(c.vertices) + 1 + i : i;
        if (resolved < 1 || resolved > static_cast<long long>(c.vertices))
          fail(path, where + "face " + std::to_string(c.faces + 1) + " refers to vertex " + index + ", but " +
                         std::to_string(c.vertices) + " vertices are defined before it");
        ++corners;
      }
      if (corners < 3)
        fail(path, where + "face " + std::to_string(c.faces + 1) + " has " + std::to_string(corners) +
                       " corners, fewer than 3");
      ++c.faces;
    }
  }
  return c;
}

}  // namespace

bool isBinaryStl(const std::string& bytes) {
  if (bytes.size() < 84) return false;
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  return 84 + 50 * static_cast<std::uint64_t>(n) == bytes.size();
}

MeshFileCounts checkMeshFile(const std::string& path, const std::string& bytes, const std::string& ext) {
  if (ext == ".ply") return checkPly(path, bytes);
  if (ext == ".off") return checkOff(path, bytes);
  if (ext == ".obj") return checkObj(path, bytes);
  if (ext == ".stl" && !isBinaryStl(bytes)) {
    std::size_t at = 0;
    while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    if (bytes.compare(at, 5, "solid") != 0)
      fail(path, "not a valid STL file: neither ASCII (\"solid ...\") nor binary (its triangle count does "
                 "not match its size of " + std::to_string(bytes.size()) + " bytes)");
  }
  return {};
}

}  // namespace loosehair
