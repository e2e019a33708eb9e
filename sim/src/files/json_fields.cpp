#include "files/json_fields.hpp"

#include "loosehair/mesh.hpp"

#include <filesystem>

namespace loosehair {

namespace {
// The same file, however the path was spelled ("scenes/../meshes/h.ply" from
// a scene, "/abs/data/meshes/h.ply" from a style elsewhere).
bool sameFile(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ea, eb;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ea),
                              cb = std::filesystem::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}
}  // namespace

bool HeadDesc::sameAs(const HeadDesc& o) const {
  auto sameMesh = [](const MeshSpec& a, const MeshSpec& b) {
    return sameFile(a.path, b.path) && a.load.scale == b.load.scale && a.load.up == b.load.up &&
           a.load.front == b.load.front && a.load.offset == b.load.offset &&
           a.load.drop_open_parts == b.load.drop_open_parts && a.sdf_voxel == b.sdf_voxel;
  };
  if (head_kind != o.head_kind || scalp_kind != o.scalp_kind || has_torso != o.has_torso) return false;
  if (head_kind == HeadKind::Sphere && (head_center != o.head_center || head_radius != o.head_radius)) return false;
  if (head_kind == HeadKind::Mesh && !sameMesh(head_mesh, o.head_mesh)) return false;
  if (has_torso && !sameMesh(torso_mesh, o.torso_mesh)) return false;
  if (scalp_kind == ScalpKind::SphereCap && cap_angle_deg != o.cap_angle_deg) return false;
  if (scalp_kind == ScalpKind::Curves && scalp_curves != o.scalp_curves) return false;
  return true;
}

namespace detail {

void readHeadParts(Fields& top, HeadDesc& h) {
  if (!top.has("head")) top.fail("head", "is required");
  {
    Fields head = top.child("head");
    const std::string type = head.text("type", "sphere");
    if (type == "sphere") {
      h.head_kind = HeadKind::Sphere;
      h.head_center = glm::vec3(head.vec3("center", glm::dvec3(0.0), 100.0));
      h.head_radius = head.real("radius", h.head_radius, 0.0, 10.0, true);
      h.scalp_kind = ScalpKind::SphereCap;
    } else if (type == "mesh") {
      h.head_kind = HeadKind::Mesh;
      readMeshSpec(head, h.head_mesh);
      h.scalp_kind = ScalpKind::Auto;
    } else {
      head.fail("type", "must be \"sphere\" or \"mesh\", got \"" + type + "\"");
    }
    head.finish();
  }
  if (top.has("torso")) {
    Fields torso = top.child("torso");
    readMeshSpec(torso, h.torso_mesh);
    h.has_torso = true;
    torso.finish();
  }
  if (top.has("scalp")) {
    Fields scalp = top.child("scalp");
    const bool mesh = h.head_kind == HeadKind::Mesh;
    const std::string type = scalp.text("type", mesh ? "auto" : "sphere-cap");
    if (type == "sphere-cap") {
      if (mesh) scalp.fail("type", "\"sphere-cap\" needs a sphere head; use \"auto\" or \"curves\" on a mesh");
      h.scalp_kind = ScalpKind::SphereCap;
      h.cap_angle_deg = scalp.real("cap_angle_deg", h.cap_angle_deg, 0.0, 180.0, true);
    } else if (type == "auto" || type == "curves") {
      if (!mesh) scalp.fail("type", "\"" + type + "\" needs a mesh head; a sphere head takes \"sphere-cap\"");
      h.scalp_kind = type == "auto" ? ScalpKind::Auto : ScalpKind::Curves;
      if (type == "curves") {
        const char* names[4] = {"front", "right", "back", "left"};
        for (int k = 0; k < 4; ++k) {
          if (!scalp.has(names[k])) scalp.fail(names[k], "is required: control points of the curve");
          h.scalp_curves[static_cast<std::size_t>(k)] = readPoints(scalp, names[k], 2);
        }
      }
    } else {
      scalp.fail("type", "must be \"sphere-cap\", \"auto\" or \"curves\", got \"" + type + "\"");
    }
    scalp.finish();
  }
}

namespace {

const char* axisName(Axis a) {
  switch (a) {
    case Axis::PosX:
      return "+x";
    case Axis::NegX:
      return "-x";
    case Axis::PosY:
      return "+y";
    case Axis::NegY:
      return "-y";
    case Axis::PosZ:
      return "+z";
    case Axis::NegZ:
      return "-z";
  }
  return "+y";
}

json vec(glm::vec3 v) { return json::array({v.x, v.y, v.z}); }

json meshJson(const MeshSpec& m, const std::string& folder) {
  json j;
  const std::filesystem::path path(m.path);
  j["mesh"] = folder.empty() ? m.path : path.lexically_relative(folder).generic_string();
  if (j["mesh"].get<std::string>().empty()) j["mesh"] = m.path;
  if (m.load.scale != 1.0f) j["scale"] = m.load.scale;
  if (m.load.up != Axis::PosY) j["up"] = axisName(m.load.up);
  if (m.load.front != Axis::PosZ) j["front"] = axisName(m.load.front);
  if (m.load.offset != glm::vec3(0.0f)) j["offset"] = vec(m.load.offset);
  if (m.sdf_voxel > 0.0f) j["sdf_voxel"] = m.sdf_voxel;
  return j;
}

}  // namespace

json writeHeadParts(const HeadDesc& h, const std::string& folder) {
  json out = json::object();
  if (h.head_kind == HeadKind::Sphere) {
    out["head"] = {{"type", "sphere"}, {"center", vec(h.head_center)}, {"radius", h.head_radius}};
  } else {
    json head = meshJson(h.head_mesh, folder);
    head["type"] = "mesh";
    out["head"] = head;
  }
  if (h.has_torso) out["torso"] = meshJson(h.torso_mesh, folder);
  json scalp;
  switch (h.scalp_kind) {
    case ScalpKind::SphereCap:
      scalp = {{"type", "sphere-cap"}, {"cap_angle_deg", h.cap_angle_deg}};
      break;
    case ScalpKind::Auto:
      scalp = {{"type", "auto"}};
      break;
    case ScalpKind::Curves: {
      scalp = {{"type", "curves"}};
      const char* names[4] = {"front", "right", "back", "left"};
      for (int k = 0; k < 4; ++k) {
        json pts = json::array();
        for (const glm::vec3& q : h.scalp_curves[static_cast<std::size_t>(k)]) pts.push_back(vec(q));
        scalp[names[k]] = pts;
      }
      break;
    }
  }
  out["scalp"] = scalp;
  return out;
}

}  // namespace detail
}  // namespace loosehair
