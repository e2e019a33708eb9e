// Heights on a head mesh that hairstyles are cut to (issue 44): the top of
// the head, the brows, the ears' top and bottom and the chin, measured from
// the mesh in the simulator's frame (+Y up, the face towards +Z). The
// bundled styles' generator cuts to them, and the tests of styles made in
// the viewer check against them (a bob's ends between the ears and the
// chin).
#pragma once

#include "loosehair/mesh.hpp"

namespace loosehair {

struct HeadHeights {
  float top = 0;         ///< the highest point (m)
  float brows = 0;       ///< 30% of the way from the ears' top to the top of the head
  float ear_top = 0;     ///< the slices (5 mm) where the head is wider than
  float ear_bottom = 0;  ///  its cranium by 4% or more: the ears
  float chin = 0;        ///< the lowest slice where the face still stands out before the profile steps back to the neck
};

/// Measures a head mesh: slices of 5 mm from the top down; the cranium's
/// width is the widest slice above half the nose's depth (the nose: the
/// slice reaching furthest towards +Z near x = 0); the ears are the first run
/// of slices below a third of the nose's depth wider than the cranium by 4%;
/// the chin is where the face's profile (the furthest +Z within 2 cm of
/// x = 0) steps back by more than 2 cm from one slice to the next below the
/// nose (the lowest slice if it never does). Throws MeshError for a mesh
/// without vertices, without a face near x = 0, with nothing above the nose
/// or with no slice wider than its cranium.
HeadHeights measureHeadHeights(const TriangleMesh& head);

}  // namespace loosehair
