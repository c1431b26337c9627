// The four crystals of space-filling grains (docs/model.md, "Lattices"): simple cubic (cubes), FCC (rhombic
// dodecahedra, the paper's), BCC (truncated octahedra) and ideal HCP (trapezo-rhombic dodecahedra), each grain
// the Voronoi cell of its site. Lattice directions [u v w] are given in the lattice's own indices: along the
// cubic axes for SC, FCC and BCC; for HCP the three-index form along a1, a2 (at 120 degrees) and c, the
// four-index Miller-Bravais [U V T W] converting as u = U - T, v = V - T, w = W.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "engine/core/types.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

enum class LatticeType { fcc, sc, bcc, hcp };

std::string to_string(LatticeType lattice);
/// The lattice named `name` ("fcc", "sc", "bcc", "hcp"); false when there is none.
bool lattice_from_string(const std::string& name, LatticeType& lattice);
/// The grain that tiles it.
Shape grain_shape(LatticeType lattice);

using Indices = std::array<int, 3>;

/// The lattice in its crystal frame (cubic axes; HCP: a1 along x, c along z), for cubic cell a (HCP: the FCC cell
/// of the same grains, nearest-neighbour distance D = a / sqrt2, c = sqrt(8/3) D).
struct LatticeCell {
  Mat3 primitive = Mat3::Identity();  ///< columns: the Bravais lattice's primitive translations (m)
  std::vector<Vec3> basis;            ///< the sites of one primitive cell (m)
  std::vector<Quat> basis_turn;       ///< each basis site's grain, turned in the crystal frame (HCP B: half a turn about c)
  /// Volume per site: one grain's (m^3).
  double site_volume() const { return std::abs(primitive.determinant()) / double(basis.size()); }
};

LatticeCell lattice_cell(LatticeType lattice, double a);
/// [u v w] as a crystal-frame vector (m) for cubic cell a.
Vec3 direction_vector(LatticeType lattice, const Indices& uvw, double a);
/// The compression axis when none is given: the paper's off-axis [-1 -1 2] for FCC, [0 0 1] (a cube axis; the
/// c axis for HCP) for the others.
Indices default_axis(LatticeType lattice);
/// The lattice's close-packed planes, for the section chooser: {111} FCC, {110} BCC, basal (0001) HCP, {100} SC.
std::string close_packed_planes(LatticeType lattice);

/// The unit normal (crystal frame) of the plane of Miller indices (h k l) (HCP: of a1, a2, c).
Vec3 plane_normal(LatticeType lattice, const Indices& plane);
/// The smallest lattice direction indices [u v w] (HCP: of a1, a2, c) along `v` (crystal frame), the largest index at
/// most `max_index`; false when none fits to 1e-9.
bool direction_indices(LatticeType lattice, const Vec3& v, int max_index, Indices& out);

/// The plane's normal as a lattice direction (cubic: the plane's own indices, reduced; HCP: [u v w] of a1, a2, c);
/// throws std::invalid_argument when none has indices up to 12.
Indices normal_direction(LatticeType lattice, const Indices& plane);

}  // namespace granulab
