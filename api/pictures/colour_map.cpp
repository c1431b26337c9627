#include "api/pictures/colour_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "api/pictures/svg_text.h"

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

std::string colour_bar_svg(double x, double top, double height, double lo, double hi, const std::string& label) {
  std::string svg = "<g class=\"colour-bar\">\n";
  for (int k = 0; k < 64; ++k)
    svg += "<rect x=\"" + num(x) + "\" y=\"" + num(top + height * (63 - k) / 64) + "\" width=\"18\" height=\"" +
           num(height / 64 + 0.5) + "\" fill=\"" + viridis((k + 0.5) / 64) + "\"/>\n";
  svg += "<rect x=\"" + num(x) + "\" y=\"" + num(top) + "\" width=\"18\" height=\"" + num(height) +
         "\" fill=\"none\" stroke=\"#333\"/>\n";
  const auto ticks = nice_ticks(lo, hi, 5);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1;
  for (double t : ticks) {
    if (t < lo || t > hi) continue;
    const double y = top + height * (1 - (t - lo) / (hi - lo));
    svg += "<line x1=\"" + num(x + 18) + "\" y1=\"" + num(y) + "\" x2=\"" + num(x + 23) + "\" y2=\"" + num(y) +
           "\" stroke=\"#333\"/><text x=\"" + num(x + 26) + "\" y=\"" + num(y + 4) + "\">" + tick_label(t, step) +
           "</text>\n";
  }
  return svg + "<text transform=\"translate(" + num(x + 95) + "," + num(top + height / 2) +
         ") rotate(-90)\" text-anchor=\"middle\">" + xml_escape(label) + "</text>\n</g>\n";
}

}  // namespace granulab::pictures
