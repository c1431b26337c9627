// The faces of a crystal's grains that its surface exposes: the paper's LAMMPS set-up pushed every surface
// grain with p0 times the vector area of these (CrystalSample::fix_face_forces, docs/model.md, "Fixed forces").
#pragma once

#include <vector>

#include "engine/crystal/crystal_lattice.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

/// One face a crystal's surface exposes: site `site` of the lattice, face `face` of the grain's solid (in the grain's
/// own frame, the site's orientation applied), and whether its missing neighbour lies beyond the box along z.
struct ExposedFace {
  std::size_t site = 0;
  int face = 0;
  bool end = false;  ///< an end face (a corner neighbour beyond both z and x or y counts here)
};

/// The faces of `solid` (in each site's orientation) whose neighbour, twice the face's distance (pre-strained)
/// away across the face, lies outside the lattice box, site by site. A neighbour missing inside the box (a
/// knock-out) exposes nothing: the bag spans holes. `cell` is the pre-strained cubic cell (1 - eps0) a the lattice
/// was built with (m). O(sites x faces).
std::vector<ExposedFace> exposed_faces(const CrystalLattice& lattice, const Polyhedron& solid, double cell);

/// Sum of area x outward normal over a grain's exposed faces (m^2), split by where the missing neighbour lies.
struct ExposedArea {
  Vec3 lateral = Vec3::Zero();  ///< beyond the lattice box along x or y
  Vec3 end = Vec3::Zero();      ///< beyond it along z (a corner neighbour beyond both counts here)
};

/// Per site of `lattice` (its order): the vector areas of its exposed_faces().
std::vector<ExposedArea> exposed_face_areas(const CrystalLattice& lattice, const Polyhedron& solid, double cell);

}  // namespace granulab
