// loosehair: interactive hair dynamics with loosely connected particles
// (Bando, Chen, Nishita 2003). The public interface of the simulator library.
//
//   auto scene = loosehair::loadScene("data/scenes/sphere-hang.json");
//   loosehair::Solver solver = loosehair::buildSolver(scene);
//   solver.advance(100);
//   std::uint64_t h = solver.stateHash();
#pragma once

#include "loosehair/body.hpp"
#include "loosehair/connections.hpp"
#include "loosehair/file_io.hpp"
#include "loosehair/head_motion.hpp"
#include "loosehair/live_head.hpp"
#include "loosehair/mesh.hpp"
#include "loosehair/params.hpp"
#include "loosehair/particles.hpp"
#include "loosehair/ply_writer.hpp"
#include "loosehair/scene.hpp"
#include "loosehair/snapshot.hpp"
#include "loosehair/render_strands.hpp"
#include "loosehair/solver.hpp"
#include "loosehair/strand_field.hpp"
#include "loosehair/wind.hpp"
