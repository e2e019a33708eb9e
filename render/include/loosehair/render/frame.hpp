// What the renderer needs of a solver state (world coordinates).
#pragma once

#include "loosehair/render/renderer.hpp"
#include "loosehair/solver.hpp"

namespace loosehair::render {

/// Positions, directions, density, speed, active connections (closer than
/// 2 h1) and the head pose of the solver's current state. `spacing` is the
/// typical particle spacing (the scene's mean nearest-neighbour distance).
FrameInput frameFromSolver(const Solver& solver, float spacing);

/// The map from the head frame to the world for a head `pose`
/// (FrameInput::head_pose, GpuStrandCarry::carry).
glm::mat4 headToWorld(const HeadPose& pose);

}  // namespace loosehair::render
