// The faces of a crystal's grains that its surface exposes: the paper's LAMMPS set-up pushed every surface
// grain with p0 times the vector area of these (CrystalSample::fix_face_forces, docs/model.md, "Fixed forces").
#pragma once

#include <vector>

#include "engine/crystal/crystal_lattice.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

/// Sum of area x outward normal over a grain's exposed faces (m^2), split by where the missing neighbour lies.
struct ExposedArea {
  Vec3 lateral = Vec3::Zero();  ///< beyond the lattice box along x or y
  Vec3 end = Vec3::Zero();      ///< beyond it along z (a corner neighbour beyond both counts here)
};

/// Per site of `lattice` (its order): the faces of `solid` (in its site's orientation) whose neighbour, twice the
/// face's distance (pre-strained) away across the face, lies outside the lattice box. A neighbour
/// missing inside the box (a knock-out) exposes nothing: the bag spans holes. `cell` is the pre-strained
/// cubic cell (1 - eps0) a the lattice was built with (m). O(sites x faces).
std::vector<ExposedArea> exposed_face_areas(const CrystalLattice& lattice, const Polyhedron& solid, double cell);

}  // namespace granulab
