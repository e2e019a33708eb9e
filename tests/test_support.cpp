#include "test_support.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lhtest {

loosehair::SceneDesc sphereScene(int particles, const std::string& solver_json, const std::string& motion_json,
                                 int substeps) {
  const std::string text = R"({
    "name": "test-sphere", "seed": 3, "frame_rate": 30, "substeps": )" +
                           (substeps > 0 ? std::to_string(substeps) : std::string("\"auto\"")) +
                           R"(,
    "head": {"type": "sphere", "center": [0, 0, 0], "radius": 0.1},
    "scalp": {"type": "sphere-cap", "cap_angle_deg": 100},
    "hair": {"particles": )" +
                           std::to_string(particles) +
                           R"(, "length": 0.25, "mass": 0.06},
    "solver": )" + solver_json +
                           R"(,
    "motion": )" + motion_json +
                           "}";
  return loosehair::parseScene(text, "test-scene");
}

float maxStretch(const loosehair::Solver& solver, float hair_length) {
  const auto& p = solver.particles();
  float worst = -1e30f;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) continue;
    const float d = glm::length(p.position[i] - p.root_point[i]);
    worst = std::max(worst, (d - p.arc_length[i]) / hair_length);
  }
  return worst;
}

float minBodyDistance(const loosehair::Solver& solver, const loosehair::SceneDesc& scene) {
  const auto& p = solver.particles();
  float best = 1e30f;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_root[i]) continue;
    best = std::min(best, glm::length(p.position[i] - scene.head_center) - scene.head_radius);
  }
  return best;
}

bool allFinite(const loosehair::Solver& solver) {
  const auto& p = solver.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(p.position[i][a]) || !std::isfinite(p.velocity[i][a]) || !std::isfinite(p.direction[i][a]))
        return false;
  return true;
}

std::string sourceDir() { return LOOSEHAIR_SOURCE_DIR; }

double headYaw(const loosehair::Solver& s) {
  const glm::dvec3 z = s.head().pose.rotation * glm::dvec3(0, 0, 1);
  return std::atan2(z.x, z.z);
}

double hairYaw(const loosehair::Solver& s, const std::vector<glm::vec3>& start, float min_arc_length,
               const std::vector<std::uint8_t>& only) {
  std::vector<glm::vec3> w;
  s.worldPositions(w);
  double sum = 0, weight = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (s.particles().arc_length[i] < min_arc_length || (!only.empty() && !only[i])) continue;
    const double r = std::hypot(w[i].x, w[i].z);
    double d = std::atan2(w[i].x, w[i].z) - std::atan2(start[i].x, start[i].z);
    while (d > std::numbers::pi) d -= 2 * std::numbers::pi;
    while (d < -std::numbers::pi) d += 2 * std::numbers::pi;
    sum += r * d;
    weight += r;
  }
  return sum / weight;
}

GainLag fitGainAndLag(const std::vector<double>& t, const std::vector<double>& head, const std::vector<double>& hair,
                      double from, double to) {
  double shh = 0, shd = 0, sdd = 0, syh = 0, syd = 0;
  for (std::size_t k = 1; k + 1 < t.size(); ++k) {
    if (t[k] < from || t[k] > to) continue;
    const double h = head[k], d = (head[k + 1] - head[k - 1]) / (t[k + 1] - t[k - 1]);
    shh += h * h;
    shd += h * d;
    sdd += d * d;
    syh += hair[k] * h;
    syd += hair[k] * d;
  }
  const double det = shh * sdd - shd * shd;
  return {(syh * sdd - syd * shd) / det, -(shh * syd - shd * syh) / det};
}

float strandLengthError(const loosehair::StrandField& field, const std::vector<glm::vec3>& points) {
  const loosehair::StrandSet& r = field.rest();
  float worst = 0;
  for (std::size_t s = 0; s < r.size(); ++s) {
    double len = 0, rest = 0;
    for (std::uint32_t q = r.first[s]; q + 1 < r.first[s + 1]; ++q) {
      len += glm::length(points[q + 1] - points[q]);
      rest += glm::length(r.points[q + 1] - r.points[q]);
    }
    worst = std::max(worst, static_cast<float>(std::abs(len / rest - 1.0)));
  }
  return worst;
}

void extraTurns(const loosehair::StrandField& field, const std::vector<glm::vec3>& points, std::vector<float>& out) {
  const loosehair::StrandSet& r = field.rest();
  auto turn = [](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const float d = glm::dot(glm::normalize(b - a), glm::normalize(c - b));
    return glm::degrees(std::acos(std::clamp(d, -1.0f, 1.0f)));
  };
  for (std::size_t s = 0; s < r.size(); ++s)
    for (std::uint32_t q = r.first[s] + 1; q + 1 < r.first[s + 1]; ++q)
      out.push_back(turn(points[q - 1], points[q], points[q + 1]) -
                    turn(r.points[q - 1], r.points[q], r.points[q + 1]));
}

void addBox(loosehair::TriangleMesh& mesh, glm::vec3 lo, glm::vec3 hi) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int k = 0; k < 8; ++k)
    mesh.vertices.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  const std::uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) mesh.triangles.push_back({base + f[0], base + f[1], base + f[2]});
}

}  // namespace lhtest
