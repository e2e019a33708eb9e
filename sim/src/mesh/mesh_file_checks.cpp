#include "mesh/mesh_file_checks.hpp"

#include "loosehair/file_io.hpp"
#include "loosehair/mesh.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

namespace loosehair {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) { throw MeshError(path + ": " + why); }

std::string_view nextLine(const std::string& bytes, std::size_t& at) {
  const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
  std::string_view line(bytes.data() + at, end - at);
  at = std::min(end + 1, bytes.size());  // never past the end (a last line without a newline)
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

std::string numberText(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string shown(std::string_view s) {
  std::string t(s.substr(0, 40));
  if (s.size() > 40) t += "...";
  return t;
}

// A count from a header: a whole number in [0, limit].
std::size_t count(const std::string& path, const std::string& what, const std::string& token, std::size_t limit) {
  if (token.empty() ||
      !std::all_of(token.begin(), token.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
    fail(path, "the header's count of " + what + " is \"" + shown(token) + "\", not a whole number >= 0");
  errno = 0;
  const unsigned long long v = std::strtoull(token.c_str(), nullptr, 10);
  if (errno != 0 || v > limit)
    fail(path, "the header claims " + token + " " + what + ", more than a file of this size can hold");
  return static_cast<std::size_t>(v);
}

// PLY: the header's elements and properties, then a walk over the body
// (ASCII tokens or binary bytes) that checks every element is there, every
// list count fits in what is left of the file (a huge count made OpenMesh
// allocate for minutes), and vertex coordinates are finite numbers.
struct PlyProperty {
  std::string name;
  bool list = false;
  int count_bytes = 0, value_bytes = 0;  // binary sizes (count: lists only)
  bool value_float = false, value_signed = false;
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

int plyTypeBytes(const std::string& path, const std::string& type, bool* is_float, bool* is_signed = nullptr) {
  static const struct {
    const char* name;
    int bytes;
    bool floating;
  } kTypes[] = {{"char", 1, false},  {"uchar", 1, false},  {"short", 2, false},  {"ushort", 2, false},
                {"int", 4, false},   {"uint", 4, false},   {"float", 4, true},   {"double", 8, true},
                {"int8", 1, false},  {"uint8", 1, false},  {"int16", 2, false},  {"uint16", 2, false},
                {"int32", 4, false}, {"uint32", 4, false}, {"float32", 4, true}, {"float64", 8, true}};
  for (const auto& t : kTypes)
    if (type == t.name) {
      if (is_float) *is_float = t.floating;
      if (is_signed) *is_signed = t.floating || type.rfind("u", 0) != 0;
      return t.bytes;
    }
  fail(path, "the PLY header names an unknown type \"" + shown(type) + "\"");
}

// A PLY header: its elements with their properties, and the format; `at`
// ends past the end_header line.
struct PlyHeader {
  std::vector<PlyElement> elements;
  std::string format;
};
PlyHeader readPlyHeader(const std::string& path, const std::string& bytes, std::size_t& at) {
  PlyHeader h;
  std::vector<PlyElement>& elements = h.elements;
  std::string& format = h.format;
  const std::size_t size = bytes.size();
  bool ended = false;
  while (at < size) {
    const std::string line(nextLine(bytes, at));
    std::istringstream in(line);
    std::string word;
    in >> word;
    if (word == "end_header") {
      ended = true;
      break;
    }
    if (word == "format") {
      std::string version, extra;
      in >> format >> version;
      if (version != "1.0" || (in >> extra))
        fail(path, "the PLY format line \"" + shown(line) + "\" does not end in version 1.0");
    } else if (word == "element") {
      std::string name, n;
      in >> name >> n;
      const std::string plural = name == "vertex" ? "vertices" : name == "face" ? "faces" : name + " elements";
      elements.push_back({name, count(path, plural, n, size), {}});
    } else if (word == "property") {
      if (elements.empty()) fail(path, "the PLY header has a property before any element");
      PlyProperty prop;
      std::string type;
      in >> type;
      if (type == "list") {
        std::string count_type, value_type;
        in >> count_type >> value_type >> prop.name;
        prop.list = true;
        prop.count_bytes = plyTypeBytes(path, count_type, nullptr);
        prop.value_bytes = plyTypeBytes(path, value_type, &prop.value_float, &prop.value_signed);
      } else {
        in >> prop.name;
        prop.value_bytes = plyTypeBytes(path, type, &prop.value_float, &prop.value_signed);
      }
      std::string extra;
      if (prop.name.empty() || (in >> extra)) fail(path, "the PLY property line \"" + shown(line) + "\" is malformed");
      elements.back().properties.push_back(prop);
    } else if (word != "comment" && word != "obj_info" && !word.empty()) {
      fail(path, "the PLY header has a line \"" + shown(line) + "\" that is not an element, property or comment");
    }
  }
  if (!ended) fail(path, "the PLY header has no end_header line");
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    fail(path, "the PLY format \"" + shown(format) + "\" is not ascii or binary");
  return h;
}

// The vertex and face elements checked (x, y, z; a corner list; the face
// limit), their counts; and no element claiming more than the file holds.
MeshFileCounts checkPlyElements(const std::vector<PlyElement>& elements, const std::string& path, std::size_t size,
                                std::size_t at, std::size_t max_faces) {
  MeshFileCounts c;
  for (const PlyElement& e : elements) {
    auto has = [&](const char* name, bool list) {
      for (const PlyProperty& p : e.properties)
        if (p.name == name && p.list == list) return true;
      return false;
    };
    if (e.name == "vertex") {
      c.vertices = e.count;
      if (!has("x", false) || !has("y", false) || !has("z", false))
        fail(path, "the PLY vertex element lacks one of the properties x, y and z");
      for (const PlyProperty& p : e.properties)
        if (p.list) fail(path, "the PLY vertex element has a list property (" + shown(p.name) + ")");
    }
    if (e.name == "face") {
      c.faces = e.count;
      checkFaceCount(path, c.faces, max_faces);
      if (!has("vertex_indices", true) && !has("vertex_index", true))
        fail(path, "the PLY face element has no vertex_indices list");
    }
  }
  // cheap bounds first: every element takes at least a byte a property
  for (const PlyElement& e : elements)
    if (e.count > 0 && e.properties.size() > 0 && e.count > (size - at) / e.properties.size())
      fail(path, "the header claims " + std::to_string(e.count) + " " +
                     (e.name == "vertex" ? std::string("vertices")
                      : e.name == "face" ? std::string("faces")
                                         : shown(e.name) + " elements") +
                     ", more than a file of this size can hold");
  return c;
}

// Reads the values of a PLY body, ASCII or binary, each error naming the
// element it is in.
class PlyBody {
 public:
  PlyBody(const std::string& file, const std::string& data, std::size_t start, const std::string& format)
      : path(file),
        bytes(data),
        size(data.size()),
        at(start),
        ascii(format == "ascii"),
        big(format == "binary_big_endian") {}
  /// One value of property p (its list's count when `count`), as a double.
  double value(const PlyElement& e, std::size_t k, const PlyProperty& p, bool count) {
    if (ascii) {
      const std::string t = token(e, k);
      char* end = nullptr;
      const double d = std::strtod(t.c_str(), &end);
      if (*end != '\0') fail(path, where(e, k) + ": \"" + shown(t) + "\" is not a number");
      return d;
    }
    return count ? binary(e, k, p.count_bytes, false, false)
                 : binary(e, k, p.value_bytes, p.value_float, p.value_signed);
  }
  std::string where(const PlyElement& e, std::size_t k) const { return shown(e.name) + " " + std::to_string(k); }
  std::size_t left() const { return size - at; }
  bool ascii_format() const { return ascii; }

 private:
  std::string token(const PlyElement& e, std::size_t k) {
    while (at < size && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    const std::size_t b = at;
    while (at < size && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    if (b == at) fail(path, "the file ends inside " + where(e, k));
    return bytes.substr(b, at - b);
  }
  double binary(const PlyElement& e, std::size_t k, int nbytes, bool floating, bool is_signed) {
    if (size - at < static_cast<std::size_t>(nbytes)) fail(path, "the file ends inside " + where(e, k));
    unsigned char b[8] = {};
    for (int i = 0; i < nbytes; ++i)
      b[i] = static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(big ? nbytes - 1 - i : i)]);
    at += static_cast<std::size_t>(nbytes);
    if (floating) {
      if (nbytes == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
    std::uint64_t u = 0;
    for (int i = nbytes - 1; i >= 0; --i) u = (u << 8) | b[i];
    if (is_signed && nbytes < 8 && (u >> (8 * nbytes - 1)) != 0) u |= ~std::uint64_t{0} << (8 * nbytes);
    return is_signed ? static_cast<double>(static_cast<std::int64_t>(u)) : static_cast<double>(u);
  }
  const std::string& path;
  const std::string& bytes;
  const std::size_t size;
  std::size_t at;
  const bool ascii, big;
};

MeshFileCounts checkPly(const std::string& path, const std::string& bytes, std::size_t max_faces) {
  std::size_t at = 0;
  if (nextLine(bytes, at) != "ply") fail(path, "not a PLY file (it does not start with \"ply\")");
  const PlyHeader header = readPlyHeader(path, bytes, at);
  const std::vector<PlyElement>& elements = header.elements;
  MeshFileCounts c = checkPlyElements(elements, path, bytes.size(), at, max_faces);
  PlyBody body(path, bytes, at, header.format);
  const bool ascii = body.ascii_format();
  auto where = [&](const PlyElement& e, std::size_t k) { return body.where(e, k); };
  auto value = [&](const PlyElement& e, std::size_t k, const PlyProperty& p, bool count) {
    return body.value(e, k, p, count);
  };
  for (const PlyElement& e : elements) {
    const bool vertex = e.name == "vertex", face = e.name == "face";
    for (std::size_t k = 0; k < e.count; ++k) {
      glm::vec3 xyz(0.0f);
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          const double d = value(e, k, p, false);
          if (vertex && (p.name == "x" || p.name == "y" || p.name == "z")) {
            if (!std::isfinite(d) || std::abs(d) > 1e30)
              fail(path, where(e, k) + ": " + p.name + " is not a finite number");
            xyz[p.name[0] - 'x'] = static_cast<float>(d);
          }
          continue;
        }
        const double nd = value(e, k, p, true);
        const std::size_t per = ascii ? 2 : static_cast<std::size_t>(p.value_bytes);
        if (!(nd >= 0) || nd != std::floor(nd) || nd > static_cast<double>(body.left() / per))
          fail(path, where(e, k) + ": the list " + shown(p.name) + " claims " + numberText(nd) +
                         " values, more than the rest of the file holds");
        const auto n = static_cast<std::size_t>(nd);
        const bool corners = face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (corners && n < 3) fail(path, where(e, k) + " has " + std::to_string(n) + " corners, fewer than 3");
        std::vector<std::uint32_t> idx;
        for (std::size_t v = 0; v < n; ++v) {
          const double d = value(e, k, p, false);
          if (!corners) continue;
          if (!(d >= 0) || d >= static_cast<double>(c.vertices) || d != std::floor(d))
            fail(path, where(e, k) + " refers to vertex " + numberText(d) + " of " + std::to_string(c.vertices));
          idx.push_back(static_cast<std::uint32_t>(d));
        }
        for (std::size_t v = 1; v + 1 < idx.size(); ++v) c.mesh.triangles.emplace_back(idx[0], idx[v], idx[v + 1]);
      }
      if (vertex) c.mesh.vertices.push_back(xyz);
    }
  }
  c.has_mesh = true;
  return c;
}

// OFF (and its COFF/NOFF/STOFF variants): the counts, then one vertex a
// line (three finite coordinates first) and one face a line (a corner
// count and that many indices of defined vertices first). OpenMesh's reader
// ran for minutes on some malformed faces.
MeshFileCounts checkOff(const std::string& path, const std::string& bytes, std::size_t max_faces) {
  std::size_t at = 0, line_no = 0;
  // the next line that is neither blank nor a comment
  auto content = [&]() -> std::string {
    while (at < bytes.size()) {
      std::string line(nextLine(bytes, at));
      ++line_no;
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      if (line.find_first_not_of(" \t") != std::string::npos) return line;
    }
    return {};
  };
  std::string first = content();
  const std::size_t off = first.find("OFF");
  if (off == std::string::npos) fail(path, "not an OFF file (its first line does not name OFF)");
  if (first.find("BINARY") != std::string::npos) fail(path, "binary OFF files are not read; use ASCII OFF, PLY or OBJ");
  std::string counts = first.substr(off + 3);
  if (counts.find_first_not_of(" \t") == std::string::npos) counts = content();
  std::istringstream in(counts);
  std::string nv, nf;
  in >> nv >> nf;
  MeshFileCounts c;
  c.vertices = count(path, "vertices", nv, bytes.size() / 6);
  c.faces = count(path, "faces", nf, bytes.size() / 8);
  checkFaceCount(path, c.faces, max_faces);
  const std::string at_line = "line ";
  for (std::size_t v = 0; v < c.vertices; ++v) {
    const std::string line = content();
    const std::string where = at_line + std::to_string(line_no) + ": vertex " + std::to_string(v) + " ";
    if (line.empty()) fail(path, "the file ends after " + std::to_string(v) + " of " + nv + " vertices");
    const char* s0 = line.c_str();
    glm::vec3 xyz(0.0f);
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const double d = std::strtod(s0, &end);
      if (end == s0) fail(path, where + "needs three numbers: \"" + shown(line) + "\"");
      if (!std::isfinite(d) || std::abs(d) > 1e30)
        fail(path, where + "has a coordinate that is not a finite number: \"" + shown(line) + "\"");
      xyz[k] = static_cast<float>(d);
      s0 = end;
    }
    c.mesh.vertices.push_back(xyz);
  }
  for (std::size_t f = 0; f < c.faces; ++f) {
    const std::string line = content();
    const std::string where = at_line + std::to_string(line_no) + ": face " + std::to_string(f) + " ";
    if (line.empty()) fail(path, "the file ends after " + std::to_string(f) + " of " + nf + " faces");
    std::istringstream fin(line);
    long long n = -1;
    if (!(fin >> n) || n < 3 || n > 1000000)
      fail(path, where + "needs a corner count of at least 3: \"" + shown(line) + "\"");
    std::vector<std::uint32_t> idx;
    for (long long k = 0; k < n; ++k) {
      long long i = -1;
      if (!(fin >> i)) fail(path, where + "has fewer than " + std::to_string(n) + " corners: \"" + shown(line) + "\"");
      if (i < 0 || i >= static_cast<long long>(c.vertices))
        fail(path, where + "refers to vertex " + std::to_string(i) + " of " + std::to_string(c.vertices));
      idx.push_back(static_cast<std::uint32_t>(i));
    }
    for (std::size_t v = 1; v + 1 < idx.size(); ++v) c.mesh.triangles.emplace_back(idx[0], idx[v], idx[v + 1]);
  }
  c.has_mesh = true;
  return c;
}

// OBJ: "v x y z" and "f a b c ..." (a as i, i/t, i//n or i/t/n; negative
// indices count back from the last vertex).
MeshFileCounts checkObj(const std::string& path, const std::string& bytes, std::size_t max_faces) {
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
        if (end == s)
          fail(path,
               where + "vertex " + std::to_string(c.vertices + 1) + " needs three numbers: \"" + shown(line) + "\"");
        if (!std::isfinite(d) || (errno == ERANGE && std::abs(d) > 1.0))
          fail(path, where + "vertex " + std::to_string(c.vertices + 1) +
                         " has a coordinate that is not a finite number: \"" + shown(line) + "\"");
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
          fail(path, where + "face " + std::to_string(c.faces + 1) + ": \"" + shown(ref) + "\" is not a vertex index");
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
      checkFaceCount(path, c.faces, max_faces, true);
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

void checkFaceCount(const std::string& path, std::size_t faces, std::size_t max_faces, bool counting) {
  if (faces > max_faces)
    throw MeshTooLargeError(path + ": the mesh holds " +
                            (counting ? "more than " + std::to_string(max_faces) : std::to_string(faces)) +
                            " faces, above the limit of " + std::to_string(max_faces));
}

void checkGltfFaceCount(const std::string& path, bool binary, std::size_t max_faces) {
  if (max_faces == SIZE_MAX) return;
  std::string text;
  if (binary) {
    // 12 bytes of header, then the JSON chunk: its length, "JSON", the text
    std::ifstream in(path, std::ios::binary);
    unsigned char head[20];
    if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return;
    auto u32 = [&](int at) {
      return static_cast<std::uint32_t>(head[at]) | static_cast<std::uint32_t>(head[at + 1]) << 8 |
             static_cast<std::uint32_t>(head[at + 2]) << 16 | static_cast<std::uint32_t>(head[at + 3]) << 24;
    };
    if (std::memcmp(head, "glTF", 4) != 0 || std::memcmp(head + 16, "JSON", 4) != 0) return;
    const std::uint32_t length = u32(12);
    if (length > kMaxMeshFileBytes) return;
    text.resize(length);
    if (!in.read(text.data(), length)) return;
  } else {
    try {
      text = readRegularFile(path, kMaxMeshFileBytes);
    } catch (const FileError&) {
      return;  // the reader names it
    }
  }
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return;
  auto array = [](const nlohmann::json& j, const char* key) -> const nlohmann::json* {
    const auto it = j.find(key);
    return it != j.end() && it->is_array() ? &*it : nullptr;
  };
  auto index = [](const nlohmann::json& j, const char* key, std::size_t size) -> std::size_t {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_number_integer()) return SIZE_MAX;
    const auto v = it->get<long long>();
    return v >= 0 && static_cast<unsigned long long>(v) < size ? static_cast<std::size_t>(v) : SIZE_MAX;
  };
  const nlohmann::json* nodes = array(doc, "nodes");
  const nlohmann::json* meshes = array(doc, "meshes");
  const nlohmann::json* accessors = array(doc, "accessors");
  if (!nodes || !meshes || !accessors) return;
  auto count = [&](std::size_t a) -> std::size_t {
    if (a == SIZE_MAX || !(*accessors)[a].is_object()) return 0;
    const auto it = (*accessors)[a].find("count");
    return it != (*accessors)[a].end() && it->is_number_unsigned() ? it->get<std::size_t>() : 0;
  };
  // the nodes the reader walks: the default scene's roots (or every node)
  std::vector<std::size_t> stack;
  const nlohmann::json* scenes = array(doc, "scenes");
  if (scenes && !scenes->empty()) {
    std::size_t si = index(doc, "scene", scenes->size());
    if (si == SIZE_MAX) si = 0;
    if ((*scenes)[si].is_object())
      if (const nlohmann::json* roots = array((*scenes)[si], "nodes"))
        for (const auto& n : *roots)
          if (n.is_number_unsigned() && n.get<std::size_t>() < nodes->size()) stack.push_back(n.get<std::size_t>());
  } else {
    for (std::size_t n = 0; n < nodes->size(); ++n) stack.push_back(n);
  }
  std::vector<char> seen(nodes->size(), 0);
  std::size_t triangles = 0;
  while (!stack.empty()) {
    const std::size_t n = stack.back();
    stack.pop_back();
    if (seen[n]++ || !(*nodes)[n].is_object()) continue;
    const nlohmann::json& node = (*nodes)[n];
    if (const nlohmann::json* children = array(node, "children"))
      for (const auto& c : *children)
        if (c.is_number_unsigned() && c.get<std::size_t>() < nodes->size()) stack.push_back(c.get<std::size_t>());
    const std::size_t m = index(node, "mesh", meshes->size());
    if (m == SIZE_MAX || !(*meshes)[m].is_object()) continue;
    const nlohmann::json* prims = array((*meshes)[m], "primitives");
    if (!prims) continue;
    for (const auto& prim : *prims) {
      if (!prim.is_object()) continue;
      const auto mode_it = prim.find("mode");
      const long long mode = mode_it != prim.end() && mode_it->is_number_integer() ? mode_it->get<long long>() : 4;
      std::size_t corners = count(index(prim, "indices", accessors->size()));
      if (!prim.contains("indices")) {
        const auto attributes = prim.find("attributes");
        if (attributes != prim.end() && attributes->is_object())
          corners = count(index(*attributes, "POSITION", accessors->size()));
      }
      const std::size_t t = mode == 4 ? corners / 3 : (mode == 5 || mode == 6) && corners > 2 ? corners - 2 : 0;
      triangles = t > SIZE_MAX - triangles ? SIZE_MAX : triangles + t;
    }
  }
  checkFaceCount(path, triangles, max_faces);
}

MeshFileCounts checkMeshFile(const std::string& path, const std::string& bytes, const std::string& ext,
                             std::size_t max_faces) {
  if (ext == ".ply") return checkPly(path, bytes, max_faces);
  if (ext == ".off") return checkOff(path, bytes, max_faces);
  if (ext == ".obj") return checkObj(path, bytes, max_faces);
  if (ext != ".stl") return {};
  if (isBinaryStl(bytes)) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    checkFaceCount(path, n, max_faces);
  } else {
    std::size_t at = 0;
    while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    if (bytes.compare(at, 5, "solid") != 0)
      fail(path,
           "not a valid STL file: neither ASCII (\"solid ...\") nor binary (its triangle count does "
           "not match its size of " +
               std::to_string(bytes.size()) + " bytes)");
    // no count in the file: its facets, each closed by "endfacet"
    std::size_t facets = 0;
    for (std::size_t k = bytes.find("endfacet", at); k != std::string::npos; k = bytes.find("endfacet", k + 8))
      ++facets;
    checkFaceCount(path, facets, max_faces);
  }
  return {};
}

}  // namespace loosehair
