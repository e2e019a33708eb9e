// Style files (JSON, data/styles/README.md): reading with every field
// checked and named in errors, and writing numbers that read back
// bit-exactly (17 significant digits of the float's exact double value).
#include "files/json_fields.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/style.hpp"

#include <algorithm>
#include <filesystem>

namespace loosehair {
namespace {

using namespace detail;

[[noreturn]] void raiseStyle(const std::string& message) { throw StyleError(message); }

glm::vec2 readUv(Fields& f, const json& q, const std::string& field) {
  if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
    f.fail(field, "must be a point [u, v], got " + show(q));
  const double u = q[0].get<double>(), v = q[1].get<double>();
  if (!std::isfinite(u) || !std::isfinite(v) || u < 0 || u > 1 || v < 0 || v > 1)
    f.fail(field, "lies off the scalp: (u, v) must be in [0, 1]^2, got " + show(q));
  return {static_cast<float>(u), static_cast<float>(v)};
}

WispRegion readRegion(Fields f) {
  WispRegion r;
  if (f.has("triangles")) {
    const json& t = f.at("triangles");
    if (!t.is_array()) f.fail("triangles", "must be an array of scalp triangle indices");
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (!t[k].is_number_integer() || t[k].get<std::int64_t>() < 0 || t[k].get<std::int64_t>() > UINT32_MAX)
        f.fail("triangles[" + std::to_string(k) + "]", "must be a scalp triangle index, got " + show(t[k]));
      r.triangles.push_back(static_cast<std::uint32_t>(t[k].get<std::int64_t>()));
    }
    std::sort(r.triangles.begin(), r.triangles.end());
    r.triangles.erase(std::unique(r.triangles.begin(), r.triangles.end()), r.triangles.end());
  }
  if (f.has("uv_rect")) {
    const json& q = f.at("uv_rect");
    if (!q.is_array() || q.size() != 4) f.fail("uv_rect", "must be [u0, v0, u1, v1], got " + show(q));
    const glm::vec2 a = readUv(f, json::array({q[0], q[1]}), "uv_rect");
    const glm::vec2 b = readUv(f, json::array({q[2], q[3]}), "uv_rect");
    if (!(b.x > a.x && b.y > a.y)) f.fail("uv_rect", "must have u1 > u0 and v1 > v0, got " + show(q));
    r.polygons.push_back({a, {b.x, a.y}, b, {a.x, b.y}});
  }
  if (f.has("uv_polygons")) {
    const json& list = f.at("uv_polygons");
    if (!list.is_array()) f.fail("uv_polygons", "must be an array of polygons [[u, v], ...]");
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string field = "uv_polygons[" + std::to_string(k) + "]";
      if (!list[k].is_array() || list[k].size() < 3) f.fail(field, "must be a polygon of at least 3 points [u, v]");
      std::vector<glm::vec2> poly;
      for (std::size_t j = 0; j < list[k].size(); ++j)
        poly.push_back(readUv(f, list[k][j], field + "[" + std::to_string(j) + "]"));
      r.polygons.push_back(std::move(poly));
    }
  }
  if (r.empty()) f.fail("", "needs \"triangles\", \"uv_rect\" or \"uv_polygons\"");
  f.finish();
  return r;
}

Wisp readWisp(Fields f, std::size_t index) {
  Wisp w;
  w.name = f.text("name", "wisp " + std::to_string(index));
  if (!f.has("region")) f.fail("region", "is required");
  w.region = readRegion(f.child("region"));
  if (!f.has("key_strand")) f.fail("key_strand", "is required: the key strand's control points, root first");
  w.key_strand = readPoints(f, "key_strand", 2, kMaxStyleCoordinate);
  for (std::size_t k = 1; k < w.key_strand.size(); ++k)
    if (glm::length(w.key_strand[k] - w.key_strand[k - 1]) < kMinControlPointGap)
      f.fail("key_strand[" + std::to_string(k) + "]", "repeats the previous control point");
  WispParams& p = w.params;
  p.density = f.real("density", p.density, 0.0, 1e4, true);
  p.strands = static_cast<int>(f.integer("strands", p.strands, 0, 10000000));
  p.offset_radius = f.real("offset_radius", p.offset_radius, 0.0, 1.0);
  p.length_variation = f.real("length_variation", p.length_variation, 0.0, 0.9);
  p.curl_radius = f.real("curl_radius", p.curl_radius, 0.0, 0.2);
  p.curl_period = f.real("curl_period", p.curl_period, 1e-3, 1.0);
  // absent: 0, the translated copies styles grew before the field existed
  p.blend = f.real("blend", 0.0, 0.0, 1.0);
  p.edge_ramp = f.real("edge_ramp", p.edge_ramp, 0.0, 0.05);
  p.seed = static_cast<std::uint64_t>(f.integer("seed", static_cast<std::int64_t>(p.seed), 0, INT64_MAX));
  f.finish();
  return w;
}

HairTie readTie(Fields f, std::size_t index) {
  HairTie t;
  t.name = f.text("name", "tie " + std::to_string(index));
  if (!f.has("center")) f.fail("center", "is required: the ring's centre in the head frame");
  t.center = glm::vec3(f.vec3("center", glm::dvec3(0.0), 100.0));
  const glm::dvec3 axis = f.vec3("axis", glm::dvec3(t.axis), 1e6);
  if (!(glm::length(axis) > 1e-9)) f.fail("axis", "must be a non-zero direction");
  // kept as written when it is a unit vector already, so save then load is exact
  t.axis = std::abs(glm::length(axis) - 1.0) < 1e-6 ? glm::vec3(axis) : glm::vec3(glm::normalize(axis));
  t.radius = f.real("radius", t.radius, 1e-3, 0.2);
  t.width = f.real("width", t.width, 1e-3, 0.2);
  t.hold = f.real("hold", t.hold, 0.0, 50.0);
  f.finish();
  return t;
}

json vec(glm::vec3 v) { return json::array({v.x, v.y, v.z}); }

}  // namespace

bool Style::operator==(const Style& o) const {
  return name == o.name && head.sameAs(o.head) && colour == o.colour && shape_keeping == o.shape_keeping &&
         wisps == o.wisps && ties == o.ties;
}

Style parseStyle(const std::string& text, const std::string& source) {
  checkJson(text, source, [](const std::string& message) { throw StyleError(message); });
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw StyleError(source + ": invalid JSON: " + clipped(e.what(), 200));
  }
  Style s;
  s.source = source;
  Fields top(root, "", source, raiseStyle);
  s.name = top.text("name", "style");
  readHeadParts(top, s.head);
  if (top.has("colour")) {
    const glm::dvec3 c = top.vec3("colour", glm::dvec3(s.colour), 1.0);
    if (c.x < 0 || c.y < 0 || c.z < 0)
      top.fail("colour", "must be linear RGB in [0, 1], got " + show(top.at("colour")));
    s.colour = glm::vec3(c);
  }
  s.shape_keeping = top.real("shape_keeping", s.shape_keeping, 0.0, 100.0);
  if (!top.has("wisps")) top.fail("wisps", "is required: the list of wisps");
  const json& wisps = top.at("wisps");
  if (!wisps.is_array() || wisps.empty()) top.fail("wisps", "must be a non-empty array of wisps");
  for (std::size_t k = 0; k < wisps.size(); ++k)
    s.wisps.push_back(readWisp(Fields(wisps[k], "wisps[" + std::to_string(k) + "]", source, raiseStyle), k));
  if (top.has("ties")) {
    const json& ties = top.at("ties");
    if (!ties.is_array()) top.fail("ties", "must be an array of ties");
    for (std::size_t k = 0; k < ties.size(); ++k)
      s.ties.push_back(readTie(Fields(ties[k], "ties[" + std::to_string(k) + "]", source, raiseStyle), k));
  }
  top.finish();
  return s;
}

double checkWispValue(const std::string& field, double value, const std::string& source) {
  if (!std::isfinite(value)) throw StyleError(source + ": " + field + ": must be a finite number, got " + num(value));
  // the field of a wisp that is otherwise as small as a style file allows
  json wisp = {{"region", {{"uv_rect", {0.0, 0.0, 1.0, 1.0}}}},
               {"key_strand", json::array({json::array({0.0, 0.0, 0.0}), json::array({0.0, 0.1, 0.0})})}};
  wisp[field] = value;
  const Wisp w = readWisp(Fields(wisp, "", source, raiseStyle), 0);
  if (field == "density") return w.params.density;
  if (field == "strands") return w.params.strands;
  if (field == "offset_radius") return w.params.offset_radius;
  if (field == "length_variation") return w.params.length_variation;
  if (field == "curl_radius") return w.params.curl_radius;
  if (field == "curl_period") return w.params.curl_period;
  if (field == "blend") return w.params.blend;
  if (field == "edge_ramp") return w.params.edge_ramp;
  if (field == "seed") return static_cast<double>(w.params.seed);
  throw StyleError(source + ": " + field + ": not a wisp parameter that takes one number");
}

Style loadStyle(const std::string& path) {
  std::string text;
  try {
    text = readRegularFile(path, kMaxTextFileBytes);
  } catch (const FileError& e) {
    throw StyleError(std::string(e.what()) + " (the style file)");
  }
  return parseStyle(text, path);
}

std::string styleText(const Style& s, const std::string& path) {
  const std::string folder =
      path.empty() ? std::string()
                   : std::filesystem::absolute(std::filesystem::path(path)).parent_path().lexically_normal().string();
  HeadDesc head = s.head;
  if (!folder.empty()) {
    auto absolute = [](std::string& p) {
      if (!p.empty()) p = std::filesystem::absolute(p).lexically_normal().string();
    };
    absolute(head.head_mesh.path);
    absolute(head.torso_mesh.path);
  }
  json out = json::object();
  out["name"] = s.name;
  json parts = writeHeadParts(head, folder);
  for (auto it = parts.begin(); it != parts.end(); ++it) out[it.key()] = it.value();
  out["colour"] = vec(s.colour);
  out["shape_keeping"] = s.shape_keeping;
  json wisps = json::array();
  for (const Wisp& w : s.wisps) {
    json region = json::object();
    if (!w.region.triangles.empty()) region["triangles"] = w.region.triangles;
    if (!w.region.polygons.empty()) {
      json polys = json::array();
      for (const auto& poly : w.region.polygons) {
        json pts = json::array();
        for (const glm::vec2 q : poly) pts.push_back(json::array({q.x, q.y}));
        polys.push_back(pts);
      }
      region["uv_polygons"] = polys;
    }
    json key = json::array();
    for (const glm::vec3& c : w.key_strand) key.push_back(vec(c));
    const WispParams& p = w.params;
    wisps.push_back({{"name", w.name},
                     {"region", region},
                     {"key_strand", key},
                     {"density", p.density},
                     {"strands", p.strands},
                     {"offset_radius", p.offset_radius},
                     {"length_variation", p.length_variation},
                     {"curl_radius", p.curl_radius},
                     {"curl_period", p.curl_period},
                     {"blend", p.blend},
                     {"edge_ramp", p.edge_ramp},
                     {"seed", p.seed}});
  }
  out["wisps"] = wisps;
  if (!s.ties.empty()) {
    json ties = json::array();
    for (const HairTie& t : s.ties)
      ties.push_back({{"name", t.name},
                      {"center", vec(t.center)},
                      {"axis", vec(t.axis)},
                      {"radius", t.radius},
                      {"width", t.width},
                      {"hold", t.hold}});
    out["ties"] = ties;
  }
  return out.dump(1) + "\n";
}

void saveStyle(const Style& style, const std::string& path) {
  const std::string text = styleText(style, path);
  try {
    writeFileAtomically(path, {text});
  } catch (const FileError& e) {
    throw StyleError(e.what());
  }
}

}  // namespace loosehair
