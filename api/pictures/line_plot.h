// A line chart as a standalone SVG document: axes with ticks and labelled units, a legend, dashed
// reference lines and labelled markers. The server draws curves with it, so clients need no plotting
// library (docs/api.md, "Pictures").
#pragma once

#include <string>
#include <vector>

namespace granulab::pictures {

struct Series {
  std::string label;  ///< legend text; empty = not in the legend
  std::vector<double> x, y;
  std::string colour;  ///< any SVG colour; empty = the next one of the palette
  bool dashed = false;
};

/// A named value: in the legend, numbered, and, when it is a point of a curve, circled there with its
/// number (its text never lies over the curves).
struct Marker {
  double x = 0, y = 0;
  std::string label;
  bool on_curve = true;
};

struct LinePlot {
  std::string title;
  std::string x_label, y_label;  ///< with their units, e.g. "axial strain (%)"
  std::vector<Series> series;
  std::vector<Marker> markers;
  std::string note;  ///< a line under the title (what was left out, say)
  /// Events drawn as short ticks hanging from the top of the plot at their x, in the legend as `events_label`.
  std::vector<double> events;
  std::string events_label;
  int width = 760, height = 480;
};

/// The palette series take their colours from, in order (colour-blind friendly, Okabe-Ito).
const std::string& palette(std::size_t i);
/// The SVG document. Series longer than 2,000 points are thinned (every k-th point, the last kept).
std::string line_plot_svg(const LinePlot& plot);

}  // namespace granulab::pictures
