// A rigid-grain estimate of a crystal's first yield, from its lattice, axis and friction alone, in about a
// millisecond (docs/model.md, "Yield estimate"). The grains are taken rigid and the crystal is cut along a
// lattice plane into two halves; the upper half may translate rigidly over the lower one by a unit vector t
// that the faces crossing the cut allow: every face either opens (t . n > 0) or stays closed and slides
// (t . n = 0), with Coulomb friction f opposite to t. A mechanism is possible once the force that the lower
// half exerts on the upper one, R = sigma m, equals sum_i N_i (n_i - f t) over the closed faces with N_i >= 0.
//  - Compression: sigma = p0 I + (sigma1 - p0) z z (the bag's p0 on the sides, the axial stress sigma1 along
//    the axis z); the estimate is the smallest sigma1 / p0 at which a mechanism on any plane of Miller
//    indices up to max_index becomes possible (one face closed, or two with t along their common edge).
//  - Shear on a given plane m along an in-plane direction s (the platens guide the motion): t = cos(theta) s +
//    sin(theta) m rides up the steepest of the closed faces, and tau / sigma_n = tan(theta + atan(f / c)), c
//    the closed face's normal component in the (s, m) plane.
// Elasticity, the platens' friction and the bag's bridging are left out, so a DEM crystal yields lower, as
// elastic strain lets some contacts slide before a whole plane does.
#pragma once

#include <string>
#include <vector>

#include "engine/core/types.h"
#include "engine/crystal/lattice_type.h"
#include "engine/framework/summary_writer.h"

namespace granulab {

struct YieldEstimate {
  bool shear = false;            ///< a shear's estimate (shear_over_normal), else a compression's (axial_over_p0)
  bool found = false;            ///< false: no mechanism on the planes searched (a locked crystal)
  double axial_over_p0 = 0;      ///< compression: sigma1 / p0 at the first possible mechanism (-)
  double shear_over_normal = 0;  ///< shear: tau / sigma_n (-); compression: tau / sigma_n on its plane then
  std::vector<int> plane;        ///< Miller indices of the sliding plane, (h k l), HCP (h k i l)
  std::vector<int> direction;    ///< the slip's in-plane direction, [u v w], HCP [U V T W]; empty if none fits
  Vec3 plane_normal = Vec3::Zero();  ///< unit, crystal frame
  Vec3 slip = Vec3::Zero();          ///< the upper half's unit translation t, crystal frame
  double dilation_angle = 0;     ///< asin(t . m), the uplift over the plane (degrees)
  int closed_faces = 0;          ///< face orientations that stay closed and slide (-)
  std::string plane_text, direction_text;  ///< "(1 1 1)", "[1 -1 0]" (HCP in four indices)
};

/// The estimate in a sentence, for people (the CLI and the page show it as it is).
std::string yield_estimate_text(const YieldEstimate& e);
/// The summary group "yield_estimate": axial_over_p0 and deviator_over_p0 (compression) or shear_over_normal (shear),
/// plane, direction, dilation_angle, closed_faces, text; `found` false and a note when no mechanism was found.
void write_yield_estimate(SummaryWriter& w, const YieldEstimate& e);

/// The lowest axial stress at which a rigid translation becomes possible under compression along unit `axis`
/// (crystal frame) with the lateral stress p0, over the planes with Miller indices up to `max_index`.
YieldEstimate compression_yield_estimate(LatticeType lattice, const Vec3& axis, double friction, int max_index = 3);
/// tau / sigma_n at which the upper half of the crystal cut along the plane of Miller indices `plane` (HCP three-index
/// (h k l) of a1, a2, c) slides along unit `direction` (crystal frame, in the plane), over every cut of the plane.
YieldEstimate shear_yield_estimate(LatticeType lattice, const Indices& plane, const Vec3& direction, double friction);

}  // namespace granulab
