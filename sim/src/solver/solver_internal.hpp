// What the solver's files share (solver.cpp and the stages' files in
// sim/src/solver/ that are still members of Solver): the internal headers,
// the body-contact constants and the placement of a world body.
#pragma once

#include "loosehair/solver.hpp"
#include "loosehair/param_table.hpp"

#include "solver/connection_builder.hpp"
#include "solver/connection_slices.hpp"
#include "solver/hair_chain.hpp"
#include "solver/hair_chain_stage.hpp"
#include "solver/implicit_springs.hpp"
#include "solver/kernel.hpp"
#include "wind/air.hpp"
#include "wind/air_grid.hpp"
#include "solver/neighbor_grid.hpp"
#include "solver/pair_columns.hpp"
#include "util/parallel.hpp"
#include "solver/spring_scratch.hpp"
#include "solver/connection_passes.hpp"
#include "solver/step_context.hpp"
#include "solver/strain_limit.hpp"
#include "solver/tethers.hpp"
#include "solver/directions.hpp"
#include "solver/density.hpp"
#include "solver/hair_hair.hpp"
#include "solver/spring_forces.hpp"
#include "solver/external_forces.hpp"
#include "solver/implicit_spring_step.hpp"
#include "solver/integrate.hpp"
#include "solver/body_query.hpp"
#include "solver/shape_keeping.hpp"
#include "solver/tether.hpp"
#include "util/thread_choice.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <numbers>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace loosehair {

inline constexpr std::size_t kBodyBlock = 256;
using tether::kSkin;
// m: what a particle's clearance must exceed to skip the exact query, room
// for the rounding of positions and body placements (~1e-7 m) many times over
inline constexpr float kClearMargin = 2e-5f;
// m/s: the fastest approach to a body that speculative contacts catch
// within one step (faster ones are left to the projection)
inline constexpr float kSpeculativeSpeed = 2.0f;

// A world body seen from the head frame at one time: q = M x + d in the
// body's frame, n_head = M^T n_body.
struct Solver::BodyFrame {
  const Body* body = nullptr;
  glm::mat3 m{1.0f};
  glm::vec3 d{0.0f};
  // for the surface velocity: world velocity vo + Ro (wo x q)
  glm::mat3 ro{1.0f}, rh_t{1.0f};
  glm::vec3 vo{0.0f}, wo{0.0f};
};

// The head and the world bodies placed at one time (`frames`, `head`), as
// the stages ask them (body_query.hpp).
class Solver::PlacedBodies final : public BodyQuery {
 public:
  PlacedBodies(const Solver& solver, const std::vector<BodyFrame>& frames, const HeadKinematics& head)
      : solver_(solver), frames_(frames), head_(head) {}
  void nearest(const glm::vec3* x, std::size_t n, float* phi, glm::vec3* normal, glm::vec3* surface_velocity,
               float limit, bool rough) const override {
    solver_.queryBodies(frames_, head_, x, n, phi, normal, surface_velocity, limit, rough);
  }
  // a body without a bound of its rough answers' error leaves every
  // particle to be asked
  float roughError() const override {
    auto error = [](const Body& body) { return body.roughError() < 0.0f ? INFINITY : body.roughError(); };
    float worst = error(*solver_.head_);
    for (const BodyFrame& f : frames_) worst = std::max(worst, error(*f.body));
    return worst;
  }

 private:
  const Solver& solver_;
  const std::vector<BodyFrame>& frames_;
  const HeadKinematics& head_;
};

}  // namespace loosehair
