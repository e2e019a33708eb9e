// Body contacts after the corrections: no particle left inside a body.
#include "solver/body_contacts.hpp"

#include "solver/solver_internal.hpp"

namespace loosehair {

namespace {

// A particle's clearance now: integrate()'s bound, less how far it moved
// since (the strain limit, the tethers) and how far any world body moved
// in its frame (rigidly: a body's distance is 1-Lipschitz in the point).
// Bodies that came or went since integrate(): no bound.
template <class Frame>
class ClearanceBound {
 public:
  ClearanceBound(const StepContext& ctx, const std::vector<Frame>& start_frames, const std::vector<Frame>& frames,
                 const std::vector<glm::vec3>& x)
      : start_(start_frames),
        frames_(frames),
        x_(x),
        integrated_(ctx.integrated_position.data()),
        clear_(ctx.body_clearance.data()) {
    same_bodies_ = start_frames.size() == frames.size() &&
                   std::equal(frames.begin(), frames.end(), start_frames.begin(),
                              [](const Frame& a, const Frame& c) { return a.body == c.body; });
    for (std::size_t k = 0; same_bodies_ && k < frames.size(); ++k)
      bodies_moved_ = bodies_moved_ || frames[k].m != start_frames[k].m || frames[k].d != start_frames[k].d;
  }
  float operator()(std::size_t i) const {
    if (!same_bodies_) return -INFINITY;
    const glm::vec3 xi = integrated_[i];
    float body_move = 0.0f;  // the farthest a world body moved at xi
    for (std::size_t k = 0; bodies_moved_ && k < frames_.size(); ++k)
      body_move =
          std::max(body_move, glm::length((frames_[k].m * xi + frames_[k].d) - (start_[k].m * xi + start_[k].d)));
    return clear_[i] - glm::length(x_[i] - xi) - body_move;
  }

 private:
  const std::vector<Frame>& start_;
  const std::vector<Frame>& frames_;
  const std::vector<glm::vec3>& x_;
  const glm::vec3* integrated_;
  const float* clear_;
  bool same_bodies_ = false, bodies_moved_ = false;
};

// The velocity of a particle after the corrections moved it from
// `integrated` to `x`. The move over dt is a velocity (position-based
// dynamics: hair dragged along keeps the drag's speed), unless the step
// absorbs the corrections; where the hair chain moved the particle
// (`chain_moved`) the move only stops a motion against it: counted whole,
// a particle the chain drew back flew on past it, and fell again. A push
// out of a body adds no speed away from its surface.
glm::vec3 correctedVelocity(glm::vec3 vi, const glm::vec3& x, const glm::vec3& integrated, float dt, bool absorb,
                            bool chain_moved, bool pushed, const glm::vec3& push_normal, const glm::vec3& surface) {
  if (x != integrated && !absorb) {
    const glm::vec3 d = x - integrated;
    if (chain_moved) {
      const float moved = glm::length(d);
      const glm::vec3 dir = d / moved;
      const float a = glm::dot(vi, dir);
      vi += (std::min(a + moved / dt, std::max(a, 0.0f)) - a) * dir;
    } else {
      vi += d / dt;
    }
  }
  if (pushed) {
    const float vn = glm::dot(vi - surface, push_normal);
    if (vn > 0.0f) vi -= vn * push_normal;  // the push-out is not a velocity
  }
  return vi;
}

}  // namespace

// The tethers, then: project what is still inside the body to its surface
// and take the new velocity from the corrected positions (no added normal
// speed, so nothing is thrown off the body).
// Several bodies (head, torso, obstacles) may meet in a crease, where
// leaving one can mean entering another: a few rounds settle it. The first
// round asks the bodies about every particle of a block; a later round only
// about the particles whose answer can differ from what asking all of them
// would give: a particle that has not moved gets the same answer from the
// same bodies, so the rounds with obstacles ask those pushed in the round
// before, and the last round, without obstacles, asks every particle pushed
// so far (its surface velocity is the one that counts). The particles never
// pushed are outside the bodies with obstacles, so outside those without.
// On the mesh-head scenes the later rounds asked all 256 particles of any
// block with one particle inside.
bool projectOutOfBodies(const BodyContactSettings& settings, const ContactBodies& bodies, const BodyContactParticles& p,
                        const StepContext& ctx, std::vector<std::uint8_t>& trapped, int threads) {
  const std::size_t n = p.position.size();
  const auto& x = p.position;
  const auto& v = p.velocity;
  const auto& root = p.is_root;
  // rounds of the head and the world bodies (obstacles too): all but the
  // last slide round the tethers (docs/design.md "Implicit springs")
  const int rounds = bodies.rounds();
  const bool has_obstacles = bodies.hasObstacles();
  const float dt = ctx.dt;
  const bool absorb = ctx.absorb_corrections;
  const auto& chain_moved = ctx.chain_moved;
  const glm::vec3* integrated_position = ctx.integrated_position.data();
  const int total_rounds = rounds + (has_obstacles ? 1 : 0);
  const bool slide = settings.slide;
  const auto& rp = p.root_point;
  const auto& sarc = p.arc_length;
  const float reach_scale = 1.0f + settings.tether_slack;
  if (slide) trapped.resize(n);
  std::atomic<bool> any_trapped{false};
  static_assert(kBodyBlock <= 65536);
  // Blocks near the surface cost the exact queries, the others little:
  // handed out one by one (each block's result is its own).
  parallel::forEachDynamic(threads, static_cast<std::size_t>((n + kBodyBlock - 1) / kBodyBlock), [&](std::size_t bb) {
    const std::size_t b = bb * kBodyBlock;
    const std::size_t len = std::min(n, b + kBodyBlock) - b;
    glm::vec3 surface[kBodyBlock], body_normal[kBodyBlock];
    float body_phi[kBodyBlock];  // the block's answers
    bool pushed[kBodyBlock] = {};
    glm::vec3 push_normal[kBodyBlock];
    std::uint16_t ask[kBodyBlock];  // the block's particles asked in this round
    glm::vec3 q[kBodyBlock], q_normal[kBodyBlock], q_surface[kBodyBlock];
    float q_phi[kBodyBlock];
    std::size_t asked = 0;
    std::uint32_t index[kBodyBlock];  // the particles asked
    // The first round asks about the particles integrate() did not
    // prove clear of every body; the others keep that proof.
    float lower[kBodyBlock];
    bodies.clearance(b, len, lower);
    for (std::size_t o = 0; o < len; ++o)
      if (!root[b + o] && !(lower[o] > kClearMargin))
        ask[asked++] = static_cast<std::uint16_t>(o);  // roots: never pushed
    for (int round = 0; round < total_rounds; ++round) {
      if (round == 0 && asked == len) {
        for (std::size_t o = 0; o < len; ++o) index[o] = static_cast<std::uint32_t>(b + o);
        bodies.nearest(&x[b], len, index, true, body_phi, body_normal, surface);
      } else {
        for (std::size_t k = 0; k < asked; ++k) {
          q[k] = x[b + ask[k]];
          index[k] = static_cast<std::uint32_t>(b + ask[k]);
        }
        bodies.nearest(q, asked, index, round < rounds, q_phi, q_normal, q_surface);
        for (std::size_t k = 0; k < asked; ++k) {
          body_phi[ask[k]] = q_phi[k];
          body_normal[ask[k]] = q_normal[k];
          surface[ask[k]] = q_surface[k];
        }
      }
      std::size_t moved = 0;  // pushed in this round, kept in ask[0, moved)
      for (std::size_t k = 0; k < asked; ++k) {
        const std::size_t o = ask[k], i = b + o;
        if (root[i] || !(body_phi[o] < 0.0f)) continue;
        // onto the surface and kSkin beyond, so that rounding does not
        // leave it a hair's breadth inside (and asked again)
        x[i] -= (body_phi[o] - kSkin) * body_normal[o];
        // a tether through the body: slide round it (a later round
        // checks where that went; the last one only pushes out)
        if (slide && round + 1 < total_rounds)
          x[i] += tether::slideAlongSurface(x[i], body_normal[o], rp[i], reach_scale * sarc[i]);
        if (!pushed[o]) push_normal[o] = body_normal[o];
        pushed[o] = true;
        ask[moved++] = static_cast<std::uint16_t>(o);
      }
      if (moved == 0) break;
      asked = moved;
      if (round + 1 == rounds && has_obstacles) {  // next: the round without obstacles
        asked = 0;
        for (std::size_t o = 0; o < len; ++o)
          if (pushed[o]) ask[asked++] = static_cast<std::uint16_t>(o);
      }
    }
    for (std::size_t i = b; i < b + len; ++i) {
      if (root[i]) continue;
      const std::size_t o = i - b;
      v[i] = correctedVelocity(v[i], x[i], integrated_position[i], dt, absorb, !chain_moved.empty() && chain_moved[i],
                               pushed[o], push_normal[o], surface[o]);
      // pushed out beyond its tether's reach: caught where sliding
      // does not help (freeTrappedHair)
      if (slide) {
        const float caught = reach_scale * sarc[i] + settings.trapped_excess;
        const glm::vec3 d = x[i] - rp[i];
        trapped[i] = pushed[i - b] && glm::dot(d, d) > caught * caught;
        if (trapped[i]) any_trapped.store(true, std::memory_order_relaxed);
      }
    }
  });
  return any_trapped.load();
}

// The solver's bodies at the step's end for the body contacts: the placed
// world bodies with and without obstacles, integrate's clearances less
// what moved since (ClearanceBound), the exact queries' hints.
class Solver::EndBodies final : public ContactBodies {
 public:
  EndBodies(const Solver& solver, const StepContext& ctx, const std::vector<BodyFrame>& start_frames,
            const std::vector<BodyFrame>& frames, const std::vector<BodyFrame>& solid_frames,
            const HeadKinematics& head)
      : solver_(solver),
        frames_(frames),
        solid_frames_(solid_frames),
        head_(head),
        bound_(ctx, start_frames, frames, solver.particles_.position) {}
  void nearest(const glm::vec3* x, std::size_t n, const std::uint32_t* index, bool with_obstacles, float* phi,
               glm::vec3* normal, glm::vec3* surface_velocity) const override {
    solver_.queryBodies(with_obstacles ? frames_ : solid_frames_, head_, x, n, phi, normal, surface_velocity, 0.0f,
                        false, index);
  }
  void clearance(std::size_t first, std::size_t count, float* lower) const override {
    for (std::size_t k = 0; k < count; ++k) lower[k] = bound_(first + k);
  }
  int rounds() const override { return frames_.empty() ? 2 : 4; }
  bool hasObstacles() const override { return solid_frames_.size() != frames_.size(); }

 private:
  const Solver& solver_;
  const std::vector<BodyFrame>& frames_;
  const std::vector<BodyFrame>& solid_frames_;
  const HeadKinematics& head_;
  const ClearanceBound<BodyFrame> bound_;
};

void Solver::resolveBodyContacts(const StepContext& ctx, const std::vector<BodyFrame>& start_frames,
                                 const std::vector<BodyFrame>& frames, const std::vector<BodyFrame>& solid_frames,
                                 const HeadKinematics& head) {
  prepareBodyHints(frames);
  const EndBodies bodies(*this, ctx, start_frames, frames, solid_frames, head);
  const BodyContactSettings settings{params_.tether, params_.tether_slack, tether::kTrappedExcess * longest_hair_};
  const BodyContactParticles p{particles_.position, particles_.velocity, particles_.is_root, particles_.root_point,
                               particles_.arc_length};
  const bool any_trapped = projectOutOfBodies(settings, bodies, p, ctx, trapped_, threads_);
  if (any_trapped) freeTrappedHair(solid_frames, head);  // rare: most steps catch none
}

}  // namespace loosehair
