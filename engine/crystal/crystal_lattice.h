// The FCC crystal of identical rhombic dodecahedra in the "off-axis" orientation (docs/model.md, "Crystal lattice"):
// lab x || [1 -1 0]/sqrt2, lab y || [1 1 1]/sqrt3 (the front face is a {111} plane), lab z || [-1 -1 2]/sqrt6
// (the compression axis). In that frame the lattice is spanned by
//   b1 = a'/2 [1 -1 0] = (a'/sqrt2, 0, 0)                   along a row (x)
//   b2 = a'/2 [0 -1 1] = (a'/(2 sqrt2), 0, a' sqrt6/4)      the next row of the same {111} layer
//   b3 = a'/2 [1 0 1]  = (a'/(2 sqrt2), a'/sqrt3, a'/(2 sqrt6))  the next {111} layer (ABC stacking)
// with a' = (1 - eps0) a, the pre-strained cubic cell. The sample is the set of lattice sites inside a
// box of grains_x row spacings along x, rows_z row spacings along z and layers_y layer spacings along y,
// so every row holds grains_x grains, every layer rows_z rows. Grain ids number the sites of the full
// box (layer-major, then row, then position along x) and survive knock-outs unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

/// A cylinder through the whole thickness (axis along y) at (x, z) in units of the grain size a,
/// measured from the sample centre; grains whose centre lies inside are removed.
struct KnockoutRegion {
  double x = 0, z = 0;  ///< centre offset from the sample centre (in a)
  double radius = 0;    ///< in a
};

struct CrystalGeometry {
  double size = 0.01;    ///< RD cubic cell a (m)
  double prestrain = 0;  ///< eps0 (-), the lattice is built with cell (1 - eps0) a
  int grains_x = 8, rows_z = 18, layers_y = 6;
  std::vector<GrainId> knockout_ids;
  std::vector<KnockoutRegion> knockout_regions;
};

struct LatticeSite {
  GrainId id;  ///< stable grain id
  int column, row, layer;
  Vec3 position;  ///< lab frame, sample centre at the origin (m)
};

struct CrystalLattice {
  Quat orientation;                ///< body (cubic crystal axes) -> lab, the same for every grain
  std::vector<LatticeSite> sites;  ///< present grains, ascending id
  Vec3 extent = Vec3::Zero();      ///< box size: grains_x a'/sqrt2, layers_y a'/sqrt3, rows_z a' sqrt6/4 (m)
  Vec3 box_lo = Vec3::Zero();      ///< the box's corners in the sites' frame: a site is there iff inside (m)
  Vec3 box_hi = Vec3::Zero();
  std::size_t knocked_out = 0;
};

/// Rotation taking the cubic crystal axes of an RD to the off-axis lab frame.
Quat off_axis_orientation();
/// Builds the lattice; throws std::invalid_argument on a knock-out id outside the box.
CrystalLattice build_crystal(const CrystalGeometry& g);

}  // namespace granulab
