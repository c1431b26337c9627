// A grain's faces as springs (docs/derivations/affine_stiffness.md): each face f of the grain's solid, with the
// N_f spheres lying under it, meets the neighbour across it in N_f aligned sphere pairs, so under a uniform strain
// it acts as one normal spring N_f k_n and one tangential spring N_f k_t between centres l_f = 2 h_f apart. Both
// the lattice's pre-strain (crystal_sample.h) and the affine elastic tensor (elastic_tensor.h) are sums over them.
#pragma once

#include <vector>

#include "engine/core/types.h"
#include "engine/geometry/grain_template.h"

namespace granulab {

struct FaceSpring {
  Vec3 normal;        ///< outward unit normal, the grain's body frame (-)
  double branch = 0;  ///< l_f: centre to the neighbour's centre across the face, twice the face's distance (m)
  long pairs = 0;     ///< N_f: spheres under the face, each touching one of the neighbour's (-)
};

/// The template's faces as springs (one per face of its solid).
std::vector<FaceSpring> face_springs(const GrainTemplate& grain);

/// How many of the spheres of grain A (turned `turn_a`, at the origin) touch one of grain B's (turned `turn_b`, at
/// `branch`) when their faces meet, the lattice unstrained: N_f when the two faces' sphere grids line up, as they do
/// on every face of FCC, SC and HCP, fewer where they do not (BCC's hexagons at N_e = 4: 7 of their 22).
long touching_pairs(const GrainTemplate& grain, const Quat& turn_a, const Quat& turn_b, const Vec3& branch);

}  // namespace granulab
