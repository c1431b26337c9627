// The colour scale of field pictures: viridis (perceptually uniform, readable in grey and by most
// colour-blind readers), as "#rrggbb".
#pragma once

#include <string>

namespace granulab::pictures {

/// The colour at t in [0, 1] (clamped; NaN is grey).
std::string viridis(double t);

}  // namespace granulab::pictures
