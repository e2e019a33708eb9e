#include "loosehair/body.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace loosehair {

SphereBody::SphereBody(glm::vec3 center, float radius) : center_(center), radius_(radius) {
  if (!(radius > 0.0f)) throw std::invalid_argument("sphere radius must be positive");
}

void SphereBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const {
  for (std::size_t k = 0; k < n; ++k) {
    const glm::vec3 d = p[k] - center_;
    const float r = glm::length(d);
    phi[k] = r - radius_;
    normal[k] = r > 0.0f ? d / r : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

bool SphereBody::bounds(glm::vec3& lower, glm::vec3& upper) const {
  lower = center_ - glm::vec3(radius_);
  upper = center_ + glm::vec3(radius_);
  return true;
}

CapsuleBody::CapsuleBody(glm::vec3 a, glm::vec3 b, float radius) : a_(a), b_(b), radius_(radius) {
  if (!(radius > 0.0f) || !std::isfinite(radius)) throw std::invalid_argument("capsule radius must be positive");
}

void CapsuleBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const {
  const glm::vec3 ab = b_ - a_;
  const float len2 = glm::dot(ab, ab);
  for (std::size_t k = 0; k < n; ++k) {
    const float t = len2 > 0.0f ? std::clamp(glm::dot(p[k] - a_, ab) / len2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 d = p[k] - (a_ + t * ab);
    const float r = glm::length(d);
    phi[k] = r - radius_;
    normal[k] = r > 0.0f ? d / r : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

bool CapsuleBody::bounds(glm::vec3& lower, glm::vec3& upper) const {
  lower = glm::min(a_, b_) - glm::vec3(radius_);
  upper = glm::max(a_, b_) + glm::vec3(radius_);
  return true;
}

namespace {

// phi, normal = the least over the parts of what `ask(part, phi, normal)`
// gives
template <class Ask>
void leastOver(const std::vector<std::shared_ptr<const Body>>& parts, std::size_t n, float* phi, glm::vec3* normal,
               const Ask& ask) {
  for (std::size_t k = 0; k < n; ++k) {
    phi[k] = INFINITY;
    normal[k] = glm::vec3(0.0f, 1.0f, 0.0f);
  }
  // blocks of points, so that the scratch lives on the stack
  constexpr std::size_t kBlock = 256;
  float pb[kBlock];
  glm::vec3 nb[kBlock];
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t len = std::min(kBlock, n - b);
    for (std::uint32_t q = 0; q < parts.size(); ++q) {
      ask(q, b, len, pb, nb);
      for (std::size_t k = 0; k < len; ++k)
        if (pb[k] < phi[b + k]) {
          phi[b + k] = pb[k];
          normal[b + k] = nb[k];
        }
    }
  }
}

}  // namespace

template <class Query>
void UnionBody::least(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal, const Query& query) const {
  leastOver(parts_, n, phi, normal, [&](std::uint32_t q, std::size_t b, std::size_t len, float* pb, glm::vec3* nb) {
    query(*parts_[q], p + b, len, pb, nb);
  });
}

void UnionBody::signedDistance(const glm::vec3* p, std::size_t n, float* phi, glm::vec3* normal) const {
  least(p, n, phi, normal, [](const Body& part, const glm::vec3* x, std::size_t m, float* d, glm::vec3* nq) {
    part.signedDistance(x, m, d, nq);
  });
}

void UnionBody::signedDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                                    glm::vec3* normal) const {
  least(p, n, phi, normal, [limit](const Body& part, const glm::vec3* x, std::size_t m, float* d, glm::vec3* nq) {
    part.signedDistanceBelow(x, m, limit, d, nq);
  });
}

void UnionBody::roughDistanceBelow(const glm::vec3* p, std::size_t n, float limit, float* phi,
                                   glm::vec3* normal) const {
  least(p, n, phi, normal, [limit](const Body& part, const glm::vec3* x, std::size_t m, float* d, glm::vec3* nq) {
    part.roughDistanceBelow(x, m, limit, d, nq);
  });
}

void UnionBody::signedDistanceBelowHinted(const glm::vec3* p, std::size_t n, float limit, float* phi, glm::vec3* normal,
                                          std::int32_t* hint) const {
  const auto parts = static_cast<std::int32_t>(parts_.size());
  std::int32_t own[256];  // leastOver's block
  leastOver(parts_, n, phi, normal, [&](std::uint32_t q, std::size_t b, std::size_t len, float* pb, glm::vec3* nb) {
    for (std::size_t k = 0; k < len; ++k) {
      const std::int32_t h = hint[b + k];
      own[k] = h >= 0 && h % parts == static_cast<std::int32_t>(q) ? h / parts : -1;
    }
    parts_[q]->signedDistanceBelowHinted(p + b, len, limit, pb, nb, own);
    // the part's new hint, kept where it is the nearest so far
    for (std::size_t k = 0; k < len; ++k)
      if (own[k] >= 0 && pb[k] < phi[b + k] && own[k] <= (INT32_MAX - parts) / parts)
        hint[b + k] = own[k] * parts + static_cast<std::int32_t>(q);
  });
}

float UnionBody::roughError() const {
  float most = 0.0f;
  for (const auto& part : parts_) {
    const float e = part->roughError();
    if (!(e >= 0.0f)) return -1.0f;
    most = std::max(most, e);
  }
  return most;
}

bool UnionBody::bounds(glm::vec3& lower, glm::vec3& upper) const {
  if (parts_.empty()) return false;
  lower = glm::vec3(INFINITY);
  upper = glm::vec3(-INFINITY);
  for (const auto& part : parts_) {
    glm::vec3 lo, hi;
    if (!part->bounds(lo, hi)) return false;
    lower = glm::min(lower, lo);
    upper = glm::max(upper, hi);
  }
  return true;
}

BodyContacts placedBodyContacts(std::vector<BodyPlacement> placed) {
  return [placed = std::move(placed)](std::span<const glm::vec3> x, float limit, bool rough, std::span<float> phi,
                                      std::span<glm::vec3> normal) {
    constexpr std::size_t kBlock = 256;  // points a block, so that the scratch lives on the stack
    glm::vec3 q[kBlock], nb[kBlock];
    float pb[kBlock];
    for (std::size_t b = 0; b < x.size(); b += kBlock) {
      const std::size_t len = std::min(kBlock, x.size() - b);
      for (std::size_t k = 0; k < len; ++k) phi[b + k] = INFINITY;
      for (const BodyPlacement& pl : placed) {
        for (std::size_t k = 0; k < len; ++k) q[k] = pl.m * x[b + k] + pl.d;
        if (rough)
          pl.body->roughDistanceBelow(q, len, limit, pb, nb);
        else
          pl.body->signedDistanceBelow(q, len, limit, pb, nb);
        for (std::size_t k = 0; k < len; ++k) {
          if (!(pb[k] < phi[b + k])) continue;
          phi[b + k] = pb[k];
          normal[b + k] = glm::transpose(pl.m) * nb[k];
        }
      }
    }
  };
}

}  // namespace loosehair
