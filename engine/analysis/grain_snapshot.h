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

struct GrainSnapshot {
  double strain = 0;       ///< the experiment's strain when taken: axial, or a shear's shear strain (-)
  std::uint64_t step = 0;  ///< time steps since the world was built (-)
  // The crystal, for pictures: its grain and the layers normal to y (defaults: the paper's crystal, measured
  // from the snapshot itself, as snapshots stored before lattices were a choice are read).
  Shape grain_shape = Shape::rhombic_dodecahedron;
  double grain_size = 0;              ///< the cubic cell a (m); 0: a'/sqrt2 from the neighbour distance
  double layer_spacing = 0;           ///< mean distance between layers along y (m); 0: {111} layers, a'/sqrt3
  std::string layer_planes = "{111}"; ///< what the layers are, for captions
  // Per grain, in ascending grain id.
  std::vector<GrainId> id;
  std::vector<Vec3> position;             ///< centre of mass (m)
  std::vector<Vec3> displacement;         ///< since the reference state, the start of loading (m)
  std::vector<Quat> orientation;          ///< body -> lab rotation (unit quaternion)
  std::vector<double> penetration;        ///< Delta, sum of the sphere overlaps with other grains (m)
  std::vector<double> penetration_ratio;  ///< Delta / mean Delta over the grains (-)
  std::vector<double> max_shear_strain;   ///< gamma_max = (e1 - e3)/2 of the local Green-Lagrange strain (-)
  std::vector<double> equivalent_strain;  ///< von Mises equivalent of the local Green-Lagrange strain (-)
  // Snapshots stored before these existed have them empty.
  std::vector<double> d2min;              ///< Falk & Langer's D^2_min of that fit: its non-affine residual (m^2)
  std::vector<double> misorientation;     ///< rotation since the reference state (degrees)
  std::vector<Vec3> misorientation_axis;  ///< its unit axis, lab frame (zero for no rotation)
  // Per interface between neighbouring grains (in the reference state).
  std::vector<GrainPair> interfaces;
  std::vector<double> sliding;  ///< relative tangential displacement across the interface (m)
};

}  // namespace granulab
