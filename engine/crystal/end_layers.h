// A crystal held by its own end grains: after confinement, the sites on the lowest and the highest of the lattice's
// distinct heights along z (and those within a depth of them) become rigid grips (prescribed motion, at rest), and the platens step back two grain sizes,
// so that the grips carry the axial load from then on (the shear experiment drives the top grip along its plane).
#pragma once

#include <vector>

#include "engine/crystal/crystal_sample.h"

namespace granulab {

struct EndLayers {
  std::vector<BodyId> layer[2];  ///< bottom and top grips' grains
  int layers[2] = {0, 0};        ///< the distinct site heights each grip holds (-)
  double spacing = 0;            ///< the smallest distance between two distinct site heights along z (m)
};

/// Makes the end layers of a confined `sample` its grips, each holding the sites within `depth` (m) of its end height,
/// and steps the platens back; forces are recomputed. Throws std::invalid_argument when no distinct height along z is
/// left between the two grips.
EndLayers grip_end_layers(CrystalSample& sample, double depth = 0);
/// The distinct site heights of a lattice's `sites` along z, ascending (m): equal within 1e-9 of the grain size `size`.
std::vector<double> site_heights(const std::vector<LatticeSite>& sites, double size);

/// The mean coordinate `axis` (0 x, 1 y, 2 z) of `bodies` at positions `x` (m); 0 for none.
double mean_coordinate(const std::vector<BodyId>& bodies, const std::vector<Vec3>& x, int axis);

/// The heights of the layers the grains' centres `x` form along z, each the mean of the centres within a quarter of
/// `spacing` of their neighbours in height, ascending (m).
std::vector<double> layer_heights(const std::vector<Vec3>& x, double spacing);

}  // namespace granulab
