// Imperfect grains (the paper's main limitation: its model is several times stiffer than the experiments,
// which it puts down to surface roughness, misaligned grains and small size variations). The lattice
// keeps its sites; each grain is drawn, from (seed, grain id) alone, smaller or tilted:
//  - size: a factor 1 - sigma_s |z| (z standard normal): grains are never larger than their site, since
//    a larger grain would overlap its neighbours by far more than the pre-strain that carries p0;
//  - misorientation: a rotation about a random axis, the rotation vector's components normal with
//    standard deviation sigma_r / sqrt3, so that the rms angle is sigma_r; the tilted grain is then shrunk
//    until it fits its lattice cell again (its support along each face normal no larger than the upright
//    grain's), so that it touches one neighbour as before and leaves thin gaps and partial contacts to
//    the others.
// Smaller or tilted grains thus leave gaps that the confinement closes as it can.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/types.h"
#include "engine/crystal/crystal_lattice.h"
#include "engine/geometry/grain_template.h"

namespace granulab {

struct ImperfectionParams {
  double size_dispersion = 0;  ///< sigma_s, relative (-)
  double misorientation = 0;   ///< sigma_r, rms rotation angle (degrees)
  std::uint64_t seed = 1;
  bool any() const { return size_dispersion > 0 || misorientation > 0; }
};

struct GrainImperfection {
  double scale = 1;                  ///< the grain's size over the template's (-)
  Quat rotation = Quat::Identity();  ///< body-frame rotation applied before the lattice's orientation
};

/// One per lattice site, in site order; all perfect when p.any() is false.
std::vector<GrainImperfection> draw_imperfections(const ImperfectionParams& p, const CrystalLattice& lattice,
                                                  const GrainTemplate& grain);

/// A lower bound of the smallest scale draw_imperfections() gives for `p` (without drawing): the size
/// factor at 5 sigma_s, times the fit of a grain turned by 4 sigma_r (the largest rms-sigma_r angle among
/// 50,000 grains is about 3 sigma_r), from the bound h0 / (h0 + R theta) on fit_scale (h0: the smallest
/// face support, R: the farthest sphere centre). For cost estimates.
double min_scale_bound(const ImperfectionParams& p, const GrainTemplate& grain);

/// The largest factor (<= 1) by which a grain turned by `rotation` in its body frame must be scaled to fit
/// inside the upright grain's face planes.
double fit_scale(const GrainTemplate& grain, const Quat& rotation);

}  // namespace granulab
