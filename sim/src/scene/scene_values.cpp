// checkSceneValue: a value entered by hand goes through the scene reader
// itself, as the one field of an otherwise empty scene, so that the panel,
// viewer scripts and scene files share one set of checks (and one wording
// of the errors).
#include "loosehair/param_table.hpp"
#include "loosehair/scene.hpp"
#include "files/json_fields.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace loosehair {

double checkSceneValue(const std::string& field, double value, const std::string& source) {
  using nlohmann::json;
  if (!std::isfinite(value))
    throw SceneError(source + ": " + field + ": must be a finite number, got " + detail::num(value));
  const std::size_t dot = field.find('.');
  const std::string section = dot == std::string::npos ? std::string() : field.substr(0, dot);
  const std::string leaf = dot == std::string::npos ? field : field.substr(dot + 1);
  // the smallest scene the reader takes, with the one field
  json root = {{"head", {{"type", "sphere"}, {"center", {0.0, 0.0, 0.0}}, {"radius", 0.1}}}};
  if (section == "head") throw SceneError(source + ": " + field + ": the head is not set by value here");
  if (section.empty()) {
    root[leaf] = value;
  } else {
    if (leaf.empty() || leaf.find('.') != std::string::npos)
      throw SceneError(source + ": " + field + ": not a field that takes one number");
    root[section] = json::object();
    root[section][leaf] = value;
    if (section == "motion") root[section]["type"] = "shake";
  }
  const SceneDesc s = parseScene(root.dump(), source);
  if (field == "seed") return static_cast<double>(s.seed);
  if (field == "frames") return s.frames;
  if (field == "hair.particles") return s.hair.particles;
  if (field == "hair.length") return s.hair.length;
  if (field == "wind.speed") return s.wind.speed;
  if (section == "solver") {
    if (const ParamInfo* info = findParam(leaf.c_str())) return info->get(s.sim);
  }
  return value;
}

}  // namespace loosehair
