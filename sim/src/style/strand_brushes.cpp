#include "loosehair/strand_brushes.hpp"

#include "loosehair/style.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace loosehair {

StrandBrush parseStrandBrush(const std::string& name) {
  if (name == "comb") return StrandBrush::Comb;
  if (name == "length") return StrandBrush::Length;
  if (name == "puff") return StrandBrush::Puff;
  if (name == "smooth") return StrandBrush::Smooth;
  throw StyleError("a brush is comb, length, puff or smooth, got \"" + name + "\"");
}

const char* strandBrushName(StrandBrush b) {
  switch (b) {
    case StrandBrush::Comb:
      return "comb";
    case StrandBrush::Length:
      return "length";
    case StrandBrush::Puff:
      return "puff";
    case StrandBrush::Smooth:
      return "smooth";
  }
  return "comb";
}

glm::vec3 keptOutsideHead(const HeadModel& head, glm::vec3 p, float clearance) {
  const std::shared_ptr<const Body> bodies[2] = {head.head(), head.torso()};
  for (int round = 0; round < 4; ++round) {
    bool moved = false;
    for (const auto& b : bodies) {
      if (!b) continue;
      float phi = 0.0f;
      glm::vec3 n(0.0f);
      b->signedDistance(&p, 1, &phi, &n);
      if (phi < clearance && std::isfinite(phi) && glm::length(n) > 0.5f) {
        p += (clearance - phi) * n;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return p;
}

namespace {

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// each span back to its length in `lengths`, from the root out, keeping its
// direction (a zero span keeps the old one)
void restoreLengths(std::vector<glm::vec3>& p, const std::vector<glm::vec3>& old, const std::vector<float>& lengths) {
  for (std::size_t k = 1; k < p.size(); ++k) {
    glm::vec3 d = p[k] - p[k - 1];
    float l = glm::length(d);
    if (!(l > 1e-9f)) {
      d = old[k] - old[k - 1];
      l = glm::length(d);
    }
    if (l > 1e-9f) p[k] = p[k - 1] + d * (lengths[k - 1] / l);
  }
}

}  // namespace

std::vector<glm::vec3> brushedKeyStrand(const std::vector<glm::vec3>& key, const BrushDab& dab, const HeadModel& head,
                                        glm::vec3 root_normal, float clearance) {
  const std::size_t n = key.size();
  if (n < 2) throw StyleError("brush: a key strand needs at least two control points");
  if (dab.weight.size() != n)
    throw StyleError("brush: " + std::to_string(dab.weight.size()) + " weights for " + std::to_string(n) +
                     " control points");
  for (float w : dab.weight)
    if (!(w >= 0.0f && w <= 1.0f)) throw StyleError("brush: a weight must be in [0, 1]");
  if (!(dab.strength >= 0.0f && dab.strength <= 1.0f)) throw StyleError("brush: the strength must be in [0, 1]");
  if (!std::isfinite(dab.grow) || std::abs(dab.grow) > 1.0f) throw StyleError("brush: grow must be in [-1, 1]");
  if (!finite(root_normal)) throw StyleError("brush: the root normal is not finite");
  std::vector<float> lengths(n - 1), along(n, 0.0f);
  float total = 0.0f;
  for (std::size_t k = 1; k < n; ++k) {
    lengths[k - 1] = glm::length(key[k] - key[k - 1]);
    total += lengths[k - 1];
    along[k] = total;
  }
  if (!(total > 0.0f)) return key;
  for (float& a : along) a /= total;  // 0 at the root, 1 at the tip
  std::vector<glm::vec3> p = key;
  switch (dab.brush) {
    case StrandBrush::Comb: {
      if (dab.move.size() != n)
        throw StyleError("brush: " + std::to_string(dab.move.size()) + " moves for " + std::to_string(n) +
                         " control points");
      for (std::size_t k = 1; k < n; ++k) {
        if (!finite(dab.move[k])) throw StyleError("brush: a move is not finite");
        p[k] += (dab.weight[k] * dab.strength * along[k]) * dab.move[k];
      }
      restoreLengths(p, key, lengths);
      break;
    }
    case StrandBrush::Length: {
      float f = 1.0f + dab.grow * dab.strength * dab.weight[n - 1];
      f = std::clamp(f, 0.01f / total, 2.0f);
      for (std::size_t k = 1; k < n; ++k) p[k] = key[0] + f * (key[k] - key[0]);
      break;
    }
    case StrandBrush::Puff: {
      const glm::vec3 up = glm::length(root_normal) > 0.0f ? glm::normalize(root_normal) : glm::vec3(0, 1, 0);
      for (std::size_t k = 1; k < n; ++k)
        p[k] += (0.2f * total * dab.weight[k] * dab.strength * (1.0f - along[k])) * up;
      restoreLengths(p, key, lengths);
      break;
    }
    case StrandBrush::Smooth: {
      for (std::size_t k = 1; k + 1 < n; ++k)
        p[k] = key[k] + (dab.weight[k] * dab.strength) * (0.5f * (key[k - 1] + key[k + 1]) - key[k]);
      break;
    }
  }
  for (std::size_t k = 1; k < n; ++k)
    if (p[k] != key[k]) p[k] = keptOutsideHead(head, p[k], clearance);
  return p;
}

}  // namespace loosehair
