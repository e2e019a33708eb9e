// Wind on a grid (issue 18; docs/design.md "Air on a grid"): the air of the
// wind box as a velocity field on a fixed staggered (MAC) grid in the world,
// its axes the box's (along the wind, up, across), one cell of
// `WindParams::spacing`. A step adds the hair's drag impulses and the
// viscosity, carries the velocities along themselves (semi-Lagrangian), imposes the inflow and the bodies, and projects
// the field to zero divergence (a pressure solve), so no sound speed bounds
// the step. The hair and the air exchange the drag of method.md §5,
//
//   f_hair_i = dw m_i sum_c w_ic (U_c - v_i),   the cells c get minus it,
//
// with U_c the air's velocity at the centre of cell c (each component the
// mean of its two faces) and w_ic the trilinear weights of the hair
// particle between the eight nearest cell centres (sum_c w_ic = 1): the
// air's SPH average replaced by the grid's interpolation. A cell's impulse
// goes half to each of its two faces of each component. The two forces of
// a pair are one expression, so the exchange keeps momentum; the same
// limiter as the particle air keeps either side from overshooting. The
// box's faces: upwind the wind's velocity, downwind open (pressure 0),
// across the four sides the flow just inside (no pressure there); bodies
// are solid cells whose faces move with them.
//
// Every pass is per face or per cell from the previous arrays; each cell's
// sum of the hair's masses and impulses is taken in hair order (a thread
// owns a range of cells), the solve's sums in a fixed order on one
// thread: the results do not depend on the thread count.
#pragma once

#include "loosehair/head_motion.hpp"
#include "loosehair/wind.hpp"
#include "wind/wind_air.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace loosehair {

class AirGrid final : public WindAir {
 public:
  /// Signed distance (m, < 0 inside) and world velocity of the bodies at
  /// world points.
  using BodySampler = std::function<void(const glm::vec3* world, std::size_t n, float* phi, glm::vec3* velocity)>;

  /// Throws std::invalid_argument naming every bad field of `params`.
  explicit AirGrid(const WindParams& params);

  /// The wind's velocity at time t everywhere, projected around the bodies.
  void fill(double t, const BodySampler& bodies);

  /// The air's own step (s): it crosses kCellsAStep cells at the largest
  /// wind speed. Semi-Lagrangian advection is stable at any step, so this
  /// bounds accuracy only, and the air steps once every few hair steps.
  double stepLength() const;
  static constexpr double kCellsAStep = 3.0;

  /// Drag between the hair (head frame, at the pose of `head`) and the air:
  /// adds the force on each non-root hair particle to `hair_force` (head
  /// frame) and the opposite impulses to the air's velocities at once (so
  /// the limiter holds at every hair step, whether the air steps or not).
  void exchangeDrag(const HeadKinematics& head, std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                    std::span<const float> hair_m, std::span<const std::uint8_t> hair_root,
                    std::span<glm::vec3> hair_force, float dt, int threads);

  /// Counts a hair step of `dt`; true when the air's own step is due (the
  /// time since its last step is nearest a whole number of hair steps to
  /// stepLength()).
  bool due(float dt) override;
  /// Moves the air over the time counted since its last step, ending at
  /// time t, the bodies where `bodies` says they are then (an empty
  /// `bodies`: where they were at the last step, for bodies that have not
  /// moved).
  void advance(double t, const BodySampler& bodies, int threads);

  // WindAir: the exchange is exchangeDrag at every hair step, the move
  // advance() when due (the bodies placed again only when they moved).
  AirModel model() const override { return AirModel::Grid; }
  const WindParams& params() const override { return p_; }
  void exchange(const HeadKinematics& head, std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                std::span<const float> hair_m, std::span<const std::uint8_t> hair_root, std::span<glm::vec3> hair_force,
                float dt, int threads) override {
    exchangeDrag(head, hair_x, hair_v, hair_m, hair_root, hair_force, dt, threads);
  }
  void move(double t, double t_end, float dt, const Bodies& bodies, int threads) override;
  /// The open cells.
  std::size_t count() const override { return openCellCount(); }
  /// The open cells' centres and velocities (the grid is fixed in the world).
  void worldState(const HeadKinematics& head, std::vector<glm::vec3>* x, std::vector<glm::vec3>* v) const override;
  /// The air is incompressible: the rest density in every open cell.
  std::span<const float> density() const override;
  /// None: the air steps at its own pace (due()).
  double stableTimeStep() const override { return INFINITY; }
  void report(StepStats& stats) const override;
  /// The face velocities.
  std::size_t nonFinite() const override;
  void hashState(const std::function<void(const void* data, std::size_t bytes)>& mix) const override;

  glm::ivec3 cells() const { return {n_[0], n_[1], n_[2]}; }
  float cellSize() const { return h_; }
  std::size_t cellCount() const { return cell_count_; }
  /// The cells not inside a body (nor sealed in by bodies).
  std::size_t openCellCount() const;
  /// World centres and world velocities of the cells not inside a body.
  void openCells(std::vector<glm::vec3>& centre, std::vector<glm::vec3>& velocity) const;
  /// The air's world velocity at a world point (inside the box).
  glm::vec3 velocityAt(const glm::vec3& world) const;
  /// Largest |div u| over the open cells after the last step (1/s).
  float maxDivergence() const;
  /// Sum of the drag impulses the last exchangeDrag gave the air, as a
  /// world force (N): minus the sum of the forces it gave the hair.
  glm::dvec3 dragOnAir() const { return drag_on_air_; }
  /// Hair particles inside the box at the last exchangeDrag.
  std::size_t coupledHair() const { return coupled_; }
  /// Conjugate-gradient iterations of the last projection.
  int lastIterations() const { return last_iterations_; }
  float restDensity() const { return p_.density; }

  /// What a step carries to the next (snapshots): the face velocities of
  /// the three components, the last pressure (the solve's start) and the
  /// time since the air's last step.
  struct State {
    std::array<std::vector<float>, 3> u;
    std::vector<float> pressure;
    double pending = 0.0;
  };
  State state() const { return {u_, pressure_, pending_}; }
  /// Throws std::invalid_argument if the arrays do not fit this grid.
  void restore(State s);
  /// The sizes restore() expects: faces of component c, then cells.
  std::size_t faceCount(int c) const { return u_[static_cast<std::size_t>(c)].size(); }

 private:
  // exchangeDrag's constants and its steps, in order (each inside the
  // parallel region, between barriers)
  struct DragPass {
    glm::mat3 rot{1.0f}, rot_t{1.0f};
    glm::vec3 centre{0.0f}, omega{0.0f}, frame_v{0.0f}, extent{0.0f};
    std::uint32_t offset[8] = {};
    float rate = 0, cell_mass = 0, hair_limit = 0;
  };
  void dragStencils(const DragPass& pass, std::span<const glm::vec3> hair_x, std::span<const glm::vec3> hair_v,
                    std::span<const std::uint8_t> hair_root);
  void dragLimiters(const DragPass& pass, std::span<const float> hair_m, float dt, std::size_t cb, std::size_t ce);
  void dragOnHair(const DragPass& pass, std::span<const float> hair_m, std::span<glm::vec3> hair_force);
  void dragOnCells(const DragPass& pass, std::span<const float> hair_m, float dt, std::size_t cb, std::size_t ce);
  void cellsToFaces();
  // faces of component c: (n0 + [c==0]) x (n1 + [c==1]) x (n2 + [c==2])
  std::size_t face(int c, int i, int j, int k) const {
    const auto& d = fdim_[static_cast<std::size_t>(c)];
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(d[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(d[1]) * static_cast<std::size_t>(k));
  }
  std::size_t cell(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n_[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(n_[1]) * static_cast<std::size_t>(k));
  }
  /// A world point in grid metres (0 at the grid's lower corner).
  glm::vec3 toGrid(const glm::vec3& world) const;
  glm::vec3 toWorld(const glm::vec3& grid) const;
  /// The trilinear stencils of all three components at grid point q
  /// (clamped to the faces): kTaps face indices and weights,
  /// component-major.
  void stencils(const glm::vec3& q, std::uint32_t* index, float* weight) const;
  /// The flux out of cell (i, j, k), h div u (m/s).
  double outflow(int i, int j, int k) const;
  /// The pressure matrix's diagonal and its MIC(0) factor, for the cells'
  /// present links.
  void buildPreconditioner();
  /// Body distances and velocities at the cell centres; the cells that the
  /// open faces cannot reach (sealed by bodies) count as bodies too.
  void placeBodies(const BodySampler& bodies);
  /// The inflow face and the faces touching a body take their velocities.
  void imposeBoundaries(double t);
  void project(int threads);

  WindParams p_;
  WindAxes axes_;
  glm::vec3 origin_;  // world position of the grid's lower corner
  float h_ = 0;
  int n_[3] = {0, 0, 0};
  std::array<std::array<int, 3>, 3> fdim_{};
  std::size_t cell_count_ = 0;

  std::array<std::vector<float>, 3> u_, next_;
  double pending_ = 0.0;  // hair time since the air's last step (s)
  std::vector<float> pressure_;
  std::vector<std::uint8_t> solid_;  // per cell: inside a body (or sealed)
  std::vector<glm::vec3> solid_v_;   // per cell: body velocity (grid axes)
  std::vector<std::uint8_t> links_;  // per cell: bit d set = face d takes the pressure gradient
  // the pressure solve's arrays, in cell order with solve_pad_ zero cells
  // before and after (a slab: the loops read neighbours without a test)
  std::size_t solve_pad_ = 0;
  std::vector<double> diag_, x_, r_, z_, d_, ad_;
  std::array<std::vector<double>, 3> coupling_;   // the matrix's +x, +y, +z entries (-1 or 0)
  std::vector<double> mic_;                       // the preconditioner's inverse diagonal
  std::array<std::vector<double>, 3> mic_up_;     // its +x, +y, +z couplings times that
  std::array<std::vector<double>, 2> mic_chain_;  // the x couplings before / after, times it again
  bool mic_stale_ = true;                         // the links changed since buildPreconditioner
  // placeBodies' scratch
  std::vector<glm::vec3> centre_, body_v_;
  std::vector<float> body_phi_;
  std::vector<std::uint8_t> reached_;
  std::vector<std::size_t> queue_;
  glm::dvec3 drag_on_air_{0.0};
  std::size_t coupled_ = 0;
  int last_iterations_ = 0;

  // velocityAt's stencils: 3 components x 8 faces
  static constexpr int kTaps = 24;
  // exchangeDrag's scratch: per hair particle the lower cell of its
  // trilinear stencil between cell centres (UINT32_MAX: not coupled), the
  // eight weights and its world velocity in grid axes; per cell the air's
  // velocity at the centre with the pairs' limiter (the hair mass, until
  // the limiter replaces it) and the velocity change the cell takes
  std::vector<std::uint32_t> hair_cell_;
  std::vector<std::array<float, 8>> hair_w_;
  std::vector<glm::vec3> hair_vb_;
  std::vector<glm::vec4> cell_air_;
  std::vector<glm::vec3> cell_push_;
  mutable std::vector<float> density_;  // density()'s
};

}  // namespace loosehair
