// The spec fields of a crystal sample, shared by every crystal experiment: "grain", "material", the
// "crystal" section, loading.confining_pressure, loading.mass_scaling, loading.wall_friction and the
// engine knobs of "run", with the rules between them (see engine/framework/parameters.h).
#pragma once

#include "engine/crystal/crystal_sample.h"
#include "engine/framework/parameters.h"

namespace granulab {

/// With `shear_plane`, the sample's axes are a shear's: loading.plane (read into it; its normal is the axis) and
/// loading.direction (the lateral x axis, in the plane), instead of loading.axis and loading.lateral.
void visit_crystal_sample(ParameterVisitor& v, CrystalSampleParams& p, Indices* shear_plane = nullptr);

}  // namespace granulab
