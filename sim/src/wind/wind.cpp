// What both air models share of the wind parameters (wind.hpp): their
// check, the gust profile and the box's axes.
#include "loosehair/wind.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loosehair {

void requireValid(const WindParams& w) {
  const auto problems = validate(w);
  if (problems.empty()) return;
  std::string msg = "invalid wind parameters:";
  for (const auto& pr : problems) msg += "\n  " + pr;
  throw std::invalid_argument(msg);
}

float windSpeedAt(const WindParams& w, double t) {
  const auto& pr = w.profile;
  float scale = 1.0f;
  if (!pr.empty()) {
    if (t <= pr.front().first)
      scale = pr.front().second;
    else if (t >= pr.back().first)
      scale = pr.back().second;
    else {
      std::size_t k = 1;
      while (pr[k].first < t) ++k;
      const double f = (t - pr[k - 1].first) / (pr[k].first - pr[k - 1].first);
      scale = static_cast<float>((1.0 - f) * pr[k - 1].second + f * pr[k].second);
    }
  }
  return w.speed * scale;
}

float windMaxSpeed(const WindParams& w) {
  float s = w.profile.empty() ? 1.0f : 0.0f;
  for (const auto& [t, v] : w.profile) s = std::max(s, v);
  return w.speed * s;
}

WindAxes windAxes(const WindParams& w) {
  WindAxes a;
  a.wind = glm::normalize(w.direction);
  glm::vec3 up(0.0f, 1.0f, 0.0f);
  if (std::abs(glm::dot(up, a.wind)) > 0.95f) up = glm::vec3(1.0f, 0.0f, 0.0f);
  a.up = glm::normalize(up - glm::dot(up, a.wind) * a.wind);
  a.side = glm::cross(a.wind, a.up);
  return a;
}

}  // namespace loosehair
