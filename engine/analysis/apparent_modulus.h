// The apparent modulus of a loading curve, one definition for every experiment and document (issue 51): the secant
// of the stress against the strain between the first crossings of 10 % and 40 % of a reference stress, the first
// yield (or, when there is none, the largest stress of the run). The lower bound skips the loading's start-up (the
// platen's ramp and the first contacts settling), the upper one stays below the yield's curvature.
//
// Beside it the summary gives the affine modulus along the axis (every grain following the strain, every face
// closed and stuck: the tangent at the origin, affine_stiffness.h) and their ratio. The secant is 1.1-8 times lower
// on the perfect crystals (docs/results.md, "Young's modulus against the compression runs"): it spans strains of
// 7-250 eps0, over which faces inclined to the load open or slide, and the bag holds the lateral stress, not the
// width, so the secant is the crystal's nonlinear start, not its tangent.
#pragma once

#include <vector>

#include "engine/framework/summary_writer.h"

namespace granulab {

struct ApparentModulus {
  bool found = false;       ///< both crossings exist and are apart
  double value = 0;         ///< the secant (Pa)
  double from_strain = 0;   ///< where the stress first reaches 10 % of the reference (-)
  double to_strain = 0;     ///< 40 % (-)
  double reference = 0;     ///< the stress the window is measured in (Pa)
};

/// The secant of `stress` (Pa) over `strain` (-) between 10 % and 40 % of `reference` (Pa), crossings interpolated
/// linearly between rows.
ApparentModulus apparent_modulus(const std::vector<double>& strain, const std::vector<double>& stress, double reference);

/// The group "apparent_modulus": found, value (Pa), the value over `scale` (Pa) under `over_key` ("over_p0"), the
/// window, and with `affine` (Pa, > 0) the affine modulus along the axis and affine / value. `of` names the reference
/// ("first yield", "largest deviator", "peak").
void write_apparent_modulus(SummaryWriter& w, const ApparentModulus& m, double scale, const char* over_key,
                            double affine, const char* of);

}  // namespace granulab
