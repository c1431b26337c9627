// The colour scale of field pictures: viridis (perceptually uniform, readable in grey and by most
// colour-blind readers), as "#rrggbb".
#pragma once

#include <string>

namespace granulab::pictures {

/// The colour at t in [0, 1] (clamped; NaN is grey).
std::string viridis(double t);
/// A vertical colour bar for values lo..hi at (x, top), `height` px tall, with about five ticks and `label` (text,
/// escaped here) beside it: an SVG group.
std::string colour_bar_svg(double x, double top, double height, double lo, double hi, const std::string& label);

}  // namespace granulab::pictures
