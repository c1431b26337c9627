// Per-grain and per-interface kinematics between a reference state and the current one, for snapshots
// (paper Figs. 8, 9, 11): the local strain of each grain from the best-fit deformation of its
// neighbours' displacements, and the sliding distance at each interface of two neighbouring grains.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

/// Pairs (a, b), a < b, of bodies whose reference centres are closer than `cutoff` (m): the interfaces.
std::vector<BodyPair> neighbour_pairs(const std::vector<Vec3>& positions, double cutoff);

struct LocalStrain {
  double max_shear = 0;   ///< gamma_max = (e1 - e3)/2 of the Green-Lagrange strain E (tensor shear)
  double equivalent = 0;  ///< von Mises equivalent strain sqrt(2/3 dev(E):dev(E))
  Mat3 green_lagrange = Mat3::Zero();  ///< E = (F^T F - I)/2 itself (-)
  double d2min = 0;       ///< Falk & Langer's D^2_min: sum over the neighbours of |d - F d0|^2 (m^2), the non-affine part
};

/// The deformation gradient F that best maps each grain's reference neighbour vectors onto the current
/// ones (least squares, as in Falk & Langer 1998), E = (F^T F - I)/2 and its invariants, and the fit's residual
/// D^2_min.
/// Directions that a grain's neighbours do not span (a planar or linear neighbourhood) are taken as
/// undeformed.
std::vector<LocalStrain> local_strains(const std::vector<Vec3>& reference, const std::vector<Vec3>& current,
                                       const std::vector<BodyPair>& pairs);

/// A grain's rotation since the reference: angle (degrees, in [0, 180]) and unit axis (lab frame; zero when the
/// angle is), of q q_ref^-1.
struct Misorientation {
  double angle = 0;
  Vec3 axis = Vec3::Zero();
};
Misorientation misorientation(const Quat& reference, const Quat& current);

/// Sliding distance at each interface: the two grains' material points that coincided at the reference
/// interface midpoint, their current separation projected on the interface plane as carried by the
/// grains' rotations (m).
std::vector<double> interface_sliding(const std::vector<Vec3>& ref_pos, const std::vector<Quat>& ref_q,
                                      const std::vector<Vec3>& pos, const std::vector<Quat>& q,
                                      const std::vector<BodyPair>& pairs);

}  // namespace granulab
