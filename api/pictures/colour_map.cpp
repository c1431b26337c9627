#include "api/pictures/colour_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granulab::pictures {

std::string viridis(double t) {
  if (!std::isfinite(t)) return "#999999";
  // Nine samples of the viridis map (t = 0, 1/8, ..., 1), interpolated linearly in RGB.
  static const unsigned char stops[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                            {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                            {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 8;
  const int i = std::min(7, int(t));
  const double f = t - i;
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", int(std::lround(stops[i][0] + f * (stops[i + 1][0] - stops[i][0]))),
                int(std::lround(stops[i][1] + f * (stops[i + 1][1] - stops[i][1]))),
                int(std::lround(stops[i][2] + f * (stops[i + 1][2] - stops[i][2]))));
  return text;
}

}  // namespace granulab::pictures
