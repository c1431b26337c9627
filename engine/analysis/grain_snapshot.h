// The state of every grain at one moment of a run, with the per-grain and per-interface measures of
// the paper's Figs. 8, 9 and 11 (docs/model.md, "Snapshots and local strain"). Any experiment that
// takes pictures of its grains hands these to its ResultSink; the api writes them as JSON, LAMMPS
// dumps and VTK, the server stores them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/types.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

/// A band of sliding interfaces on one plane (slip_bands.h): where a snapshot's slip concentrates, named by the
/// lattice plane nearest to the plane fitted through it.
struct SlipBand {
  int plane[3] = {0, 0, 0};     ///< Miller indices of the nearest lattice plane, crystal frame (HCP: of a1, a2, c)
  double angle_to_plane = 0;    ///< between the fitted plane and that lattice plane (degrees)
  double normal[3] = {0, 0, 0}; ///< the fitted plane's unit normal, lab frame
  double offset = 0;            ///< the fitted plane: normal . x = offset, reference positions (m)
  double slip = 0;              ///< the mean in-plane displacement of the side the normal points to over the other (m)
  int direction[3] = {0, 0, 0}; ///< the lattice direction nearest to that slip, indices up to 3 (all zero: none)
  double direction_angle = 0;   ///< between the slip and that direction (degrees)
  double dilation_angle = 0;    ///< atan of the mean normal opening over the slip (degrees)
  double extent = 0;            ///< the largest distance between two of its interfaces' midpoints (m)
  std::uint32_t interfaces = 0; ///< sliding interfaces in it (-)
  std::uint32_t snapshot = 0;   ///< index of its snapshot, where a run keeps the bands of all of them
};

struct GrainSnapshot {
  double strain = 0;       ///< the experiment's strain when taken: axial, or a shear's shear strain (-)
  std::uint64_t step = 0;  ///< time steps since the world was built (-)
  // The crystal, for pictures: its grain and the layers normal to y (defaults: the paper's crystal, measured
  // from the snapshot itself, as snapshots stored before lattices were a choice are read).
  Shape grain_shape = Shape::rhombic_dodecahedron;
  double grain_size = 0;              ///< the cubic cell a (m); 0: a'/sqrt2 from the neighbour distance
  double layer_spacing = 0;           ///< mean distance between layers along y (m); 0: {111} layers, a'/sqrt3
  std::string layer_planes = "{111}"; ///< what the layers are, for captions
  int edge_spheres = 0;               ///< N_e of the grains' sphere clumps; 0: not kept (older snapshots)
  double sphere_overlap = 0;          ///< kappa of the clumps (-)
  // Per grain, in ascending grain id.
  std::vector<GrainId> id;
  std::vector<Vec3> position;             ///< centre of mass (m)
  std::vector<Vec3> displacement;         ///< since the reference state, the start of loading (m)
  std::vector<Quat> orientation;          ///< body -> lab rotation (unit quaternion)
  std::vector<double> penetration;        ///< Delta, sum of the sphere overlaps with other grains (m)
  std::vector<double> penetration_ratio;  ///< Delta / mean Delta over the grains (-)
  std::vector<double> gamma_max;          ///< gamma_max = (e1 - e3)/2 of the local Green-Lagrange strain (-)
  std::vector<double> equivalent_strain;  ///< von Mises equivalent of the local Green-Lagrange strain (-)
  // Snapshots stored before these existed have them empty.
  std::vector<double> d2min;              ///< Falk & Langer's D^2_min of that fit: its non-affine residual (m^2)
  std::vector<double> misorientation;     ///< rotation since the reference state (degrees)
  std::vector<Vec3> misorientation_axis;  ///< its unit axis, lab frame (zero for no rotation)
  /// The crystal's axes -> lab (slip bands name their planes in it); the paper's off-axis frame for snapshots stored
  /// before lattices were a choice.
  Quat crystal_orientation = Quat::Identity();
  std::vector<SlipBand> slip_bands;  ///< found at the snapshot (slip_bands.h); empty when none, or in older snapshots
  std::vector<double> scale;  ///< each grain's size over the template's (-); empty (older snapshots): all 1
  // The contact network when taken: per grain pair in contact, the two grains and the force on `a` from `b` (N).
  // Empty in snapshots stored before it was kept.
  std::vector<GrainPair> contacts;
  std::vector<Vec3> contact_force;
  // Per interface between neighbouring grains (in the reference state).
  std::vector<GrainPair> interfaces;
  std::vector<double> sliding;  ///< relative tangential displacement across the interface (m)
};

}  // namespace granulab
