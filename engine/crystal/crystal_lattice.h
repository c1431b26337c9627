// A crystal's lattice sites in the sample box (docs/model.md, "Crystal lattice", "Lattices and loading axes").
// Any lattice (lattice_type.h) along any lattice direction: lab z is the compression axis, lab x the lateral
// direction, y = z x x; the box holds grains_x x layers_y x rows_z grain periods w_x, w_y, w_z: w_x the lattice's
// repeat along x, w_y the spacing of its site planes normal to y, w_z = grain volume / (w_x w_y), so that it
// holds about as many grains as the product of the three. The default, the paper's FCC crystal of identical
// rhombic dodecahedra in the "off-axis" orientation, keeps its own exact construction:
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
#include <string>
#include <vector>

#include "engine/core/types.h"
#include "engine/crystal/lattice_type.h"

namespace granulab {

/// A cylinder through the whole thickness (axis along y) at (x, z) in units of the grain size a,
/// measured from the sample centre; grains whose centre lies inside are removed.
struct KnockoutRegion {
  double x = 0, z = 0;  ///< centre offset from the sample centre (in a)
  double radius = 0;    ///< in a
};

struct CrystalGeometry {
  LatticeType lattice = LatticeType::fcc;
  Indices axis{-1, -1, 2};  ///< the compression axis (lab z), a lattice direction
  Indices lateral{0, 0, 0}; ///< lab x, a lattice direction normal to the axis; all zero: the shortest one
  double size = 0.01;    ///< the cubic cell a (m)
  double prestrain = 0;  ///< eps0 (-), the lattice is built with cell (1 - eps0) a
  int grains_x = 8, rows_z = 18, layers_y = 6;
  std::vector<GrainId> knockout_ids;
  std::vector<KnockoutRegion> knockout_regions;
};

struct LatticeSite {
  GrainId id;  ///< stable grain id
  int column, row, layer;  ///< the box cell the site lies in: along x, z and y, in periods w_x, w_z, w_y
  Vec3 position;  ///< lab frame, sample centre at the origin (m)
  std::uint8_t basis = 0;  ///< which site of the primitive cell (HCP: 0 = A, 1 = B); its grain's orientation
};

struct CrystalLattice {
  LatticeType type = LatticeType::fcc;
  Quat orientation;                ///< crystal axes -> lab
  std::vector<Quat> basis_orientation;  ///< body -> lab of the grains of each basis site (site.basis)
  std::vector<LatticeSite> sites;  ///< present grains, ascending id
  Vec3 period = Vec3::Zero();      ///< w_x, w_y, w_z (m); off-axis FCC: a'/sqrt2, a'/sqrt3, a' sqrt6/4
  Vec3 extent = Vec3::Zero();      ///< box size: grains_x w_x, layers_y w_y, rows_z w_z (m)
  Vec3 box_lo = Vec3::Zero();      ///< the box's corners in the sites' frame: a site is there iff inside (m)
  Vec3 box_hi = Vec3::Zero();
  std::size_t knocked_out = 0;
};

/// Rotation taking the cubic crystal axes of an RD to the off-axis lab frame.
Quat off_axis_orientation();
/// True for the paper's crystal: FCC along [-1 -1 2] (or a multiple), x along [1 -1 0] or by default. It keeps its
/// own construction and the measures tuned on it (slip-plane hints, step bounds).
bool papers_crystal(LatticeType lattice, const Indices& axis, const Indices& lateral);
/// The spacing of the Bravais lattice's planes normal to unit `n` (m): 1/|g| for the shortest reciprocal vector g along
/// n. Throws std::invalid_argument when n is not within 1e-9 of a plane normal with indices up to about 2000.
double bravais_plane_spacing(const LatticeCell& cell, const Vec3& n);
/// The most lattice points build_crystal searches for the sites of a box along a general axis (-).
constexpr double kMaxLatticeSearch = 2e7;
/// Builds the lattice; throws std::invalid_argument on a knock-out id outside the box, an axis or lateral
/// direction that is zero, a lateral direction not normal to the axis, an axis with no normal direction of
/// indices up to 12, or a box whose search exceeds kMaxLatticeSearch (naming loading.axis / loading.lateral).
CrystalLattice build_crystal(const CrystalGeometry& g);
/// What the layers along y are, for captions: their Miller indices, "(h k l)" for the cubic lattices ("{111}" for the
/// paper's crystal, as it always said), "(h k i l)" for HCP ("(0 0 0 1)" the basal planes); "layers normal to y"
/// when none fit up to 12 times the smallest nonzero index.
std::string layer_planes(const CrystalLattice& lattice);
/// The lateral direction used when none is given: the shortest lattice translation normal to the axis (ties: the
/// largest indices in lexicographic order, first nonzero index positive). Throws std::invalid_argument when there
/// is none with indices up to 12.
Indices default_lateral(LatticeType lattice, const Indices& axis);

}  // namespace granulab
