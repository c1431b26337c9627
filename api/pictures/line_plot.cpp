#include "api/pictures/line_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "api/pictures/svg_text.h"

namespace granulab::pictures {

const std::string& palette(std::size_t i) {
  static const std::vector<std::string> colours = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                   "#E69F00", "#56B4E9", "#000000", "#F0E442"};
  return colours[i % colours.size()];
}

namespace {

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  // An empty or flat range still gets a span to draw in.
  void settle() {
    if (!(lo <= hi)) lo = 0, hi = 1;
    if (hi - lo < 1e-300 + 1e-12 * std::abs(hi)) {
      const double pad = lo == 0 ? 1 : 0.05 * std::abs(lo);
      lo -= pad, hi += pad;
    }
  }
};

}  // namespace

std::string line_plot_svg(const LinePlot& plot) {
  const double H = plot.height;
  // The legend, right of the plot: each entry's symbol, then its text from 44 px in. It is as wide as its widest
  // text (text_width of 12 px text) and a margin, up to kLegendText px of text: a longer one (a sweep's label
  // of several varied values) wraps onto further lines.
  constexpr double kFont = 12, kLegendText = 320, kIndent = 44, kMargin = 12;
  std::size_t in_legend = 0;
  double widest = 0;
  const auto measure = [&](const std::string& text) {
    ++in_legend;
    widest = std::max(widest, std::min(text_width(text, kFont), kLegendText));
  };
  for (const Series& s : plot.series)
    if (!s.label.empty()) measure(s.label);
  for (const Marker& m : plot.markers) measure(m.label);
  if (!plot.events_label.empty()) measure(plot.events_label);
  const double legend_width = std::clamp(kIndent + widest + kMargin, 120.0, kIndent + kLegendText + kMargin);
  const double left = 78, right = in_legend ? legend_width : 24, top = plot.note.empty() ? 40 : 56, bottom = 56;
  const double W = plot.width + (right > 190 ? right - 190 : 0);  // a long legend widens the picture
  const double pw = W - left - right, ph = H - top - bottom;

  Range xr, yr;
  for (const Series& s : plot.series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) xr.add(s.x[i]), yr.add(s.y[i]);
  for (const Marker& m : plot.markers)
    if (m.on_curve) xr.add(m.x), yr.add(m.y);
  xr.settle(), yr.settle();
  // Stresses and forces start from zero: include it when the data are not far from it.
  if (yr.lo > 0 && yr.lo < 0.5 * yr.hi) yr.lo = 0;
  // A start a hair below zero (a stress's first oscillation) does not buy a whole tick below the axis.
  if (yr.lo < 0 && yr.hi > 0 && -yr.lo < 0.02 * yr.hi) yr.lo = 0;
  if (xr.lo > 0 && xr.lo < 0.5 * xr.hi) xr.lo = 0;
  // The axes start and end on a tick.
  const auto round_out = [](Range& r) {
    const std::vector<double> t = nice_ticks(r.lo, r.hi);
    const double step = t.size() > 1 ? t[1] - t[0] : 0;
    if (step > 0) r.lo = std::floor(r.lo / step + 1e-3) * step, r.hi = std::ceil(r.hi / step - 1e-3) * step;
    return step;
  };
  const double xstep = round_out(xr), ystep = round_out(yr);
  const std::vector<double> xt = nice_ticks(xr.lo, xr.hi), yt = nice_ticks(yr.lo, yr.hi);
  const auto X = [&](double x) { return left + (x - xr.lo) / (xr.hi - xr.lo) * pw; };
  const auto Y = [&](double y) { return top + ph - (y - yr.lo) / (yr.hi - yr.lo) * ph; };

  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    num(W) + "\" height=\"" + num(H) + "\" viewBox=\"0 0 " + num(W) + " " + num(H) +
                    "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  // A title longer than the picture (about 8.5 px per character of 15 px bold text) ends in an ellipsis.
  const std::string title = fit_text(plot.title, W - 20, 8.5);
  svg += "<text x=\"" + num(W / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" +
         xml_escape(title) + "</text>\n";
  if (!plot.note.empty())
    svg += "<text x=\"" + num(W / 2) + "\" y=\"40\" text-anchor=\"middle\" fill=\"#555\">" + xml_escape(plot.note) +
           "</text>\n";
  // Grid and ticks.
  svg += "<g class=\"grid\" stroke=\"#e4e4e4\" stroke-width=\"1\">\n";
  for (double t : xt)
    svg += "<line x1=\"" + num(X(t)) + "\" y1=\"" + num(top) + "\" x2=\"" + num(X(t)) + "\" y2=\"" + num(top + ph) +
           "\"/>\n";
  for (double t : yt)
    svg += "<line x1=\"" + num(left) + "\" y1=\"" + num(Y(t)) + "\" x2=\"" + num(left + pw) + "\" y2=\"" + num(Y(t)) +
           "\"/>\n";
  svg += "</g>\n<g class=\"axes\">\n<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(pw) +
         "\" height=\"" + num(ph) + "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (double t : xt)
    svg += "<line x1=\"" + num(X(t)) + "\" y1=\"" + num(top + ph) + "\" x2=\"" + num(X(t)) + "\" y2=\"" +
           num(top + ph + 5) + "\" stroke=\"#333\"/><text x=\"" + num(X(t)) + "\" y=\"" + num(top + ph + 19) +
           "\" text-anchor=\"middle\">" + tick_label(t, xt.size() > 1 ? xt[1] - xt[0] : xstep) + "</text>\n";
  for (double t : yt)
    svg += "<line x1=\"" + num(left - 5) + "\" y1=\"" + num(Y(t)) + "\" x2=\"" + num(left) + "\" y2=\"" + num(Y(t)) +
           "\" stroke=\"#333\"/><text x=\"" + num(left - 8) + "\" y=\"" + num(Y(t) + 4) + "\" text-anchor=\"end\">" +
           tick_label(t, yt.size() > 1 ? yt[1] - yt[0] : ystep) + "</text>\n";
  svg += "<text x=\"" + num(left + pw / 2) + "\" y=\"" + num(H - 14) + "\" text-anchor=\"middle\">" +
         xml_escape(plot.x_label) + "</text>\n";
  svg += "<text transform=\"translate(18," + num(top + ph / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
         xml_escape(plot.y_label) + "</text>\n</g>\n";

  // Curves, clipped to the plotting area.
  svg += "<clipPath id=\"area\"><rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(pw) +
         "\" height=\"" + num(ph) +
         "\"/></clipPath>\n<g clip-path=\"url(#area)\" fill=\"none\" stroke-width=\"1.8\" stroke-linejoin=\"round\">\n";
  std::vector<std::string> colours;
  std::size_t next_colour = 0;
  for (const Series& s : plot.series) {
    colours.push_back(s.colour.empty() ? palette(next_colour++) : s.colour);
    const std::size_t n = std::min(s.x.size(), s.y.size());
    const std::size_t stride = std::max<std::size_t>(1, (n + 1999) / 2000);
    std::string points;
    const auto point = [&](std::size_t i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) points += num(X(s.x[i]), 6) + "," + num(Y(s.y[i]), 6) + " ";
    };
    for (std::size_t i = 0; i < n; i += stride) point(i);
    if (n > 0 && (n - 1) % stride != 0) point(n - 1);  // the latest row is always drawn
    svg += "<polyline class=\"series\" data-label=\"" + xml_escape(s.label) + "\" stroke=\"" + colours.back() + "\"" +
           (s.dashed ? " stroke-dasharray=\"7 5\"" : "") + " points=\"" + points + "\"/>\n";
  }
  svg += "</g>\n";
  // Events: ticks hanging from the top edge (a rug), so a hundred of them stay readable.
  if (!plot.events.empty()) {
    svg += "<g class=\"events\" stroke=\"#7b3294\" stroke-width=\"1.2\">\n";
    for (double x : plot.events)
      if (std::isfinite(x) && x >= xr.lo && x <= xr.hi)
        svg += "<line class=\"event\" x1=\"" + num(X(x), 6) + "\" y1=\"" + num(top) + "\" x2=\"" + num(X(x), 6) +
               "\" y2=\"" + num(top + 12) + "\"/>\n";
    svg += "</g>\n";
  }
  // Markers: a circle and its number on the curve; the words are in the legend.
  for (std::size_t k = 0; k < plot.markers.size(); ++k) {
    const Marker& m = plot.markers[k];
    if (!m.on_curve) continue;
    svg += "<g class=\"marker\" data-label=\"" + xml_escape(m.label) + "\"><circle cx=\"" + num(X(m.x)) + "\" cy=\"" +
           num(Y(m.y)) + "\" r=\"6\" fill=\"white\" stroke=\"#c00\" stroke-width=\"1.5\"/><text x=\"" + num(X(m.x)) +
           "\" y=\"" + num(Y(m.y) + 3.5) + "\" text-anchor=\"middle\" font-size=\"9\" fill=\"#c00\">" +
           std::to_string(k + 1) + "</text></g>\n";
  }
  // Legend, right of the plot.
  if (in_legend) {
    double y = top + 8;
    // An entry's text at its symbol's height, its further lines 15 px apart; the next entry 18 px below its last.
    const auto legend_text = [&](const std::string& text) {
      const std::vector<std::string> lines = wrap_text(text, kLegendText, kFont);
      std::string out = "<text x=\"" + num(left + pw + kIndent) + "\" y=\"" + num(y + 4) + "\">";
      if (lines.size() == 1) out += xml_escape(lines[0]);
      else
        for (std::size_t k = 0; k < lines.size(); ++k)
          out += "<tspan x=\"" + num(left + pw + kIndent) + "\" dy=\"" + (k ? "15" : "0") + "\">" +
                 xml_escape(lines[k]) + "</tspan>";
      y += 18 + 15 * double(lines.size() - 1);
      return out + "</text>\n";
    };
    svg += "<g class=\"legend\">\n";
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
      const Series& s = plot.series[i];
      if (s.label.empty()) continue;
      svg += "<line x1=\"" + num(left + pw + 12) + "\" y1=\"" + num(y) + "\" x2=\"" + num(left + pw + 38) + "\" y2=\"" +
             num(y) + "\" stroke=\"" + colours[i] + "\" stroke-width=\"2\"" +
             (s.dashed ? " stroke-dasharray=\"7 5\"" : "") + "/>";
      svg += legend_text(s.label);  // after the symbol: it moves y on
    }
    for (std::size_t k = 0; k < plot.markers.size(); ++k) {
      const Marker& m = plot.markers[k];
      const double cx = left + pw + 25;
      svg += "<circle cx=\"" + num(cx) + "\" cy=\"" + num(y) +
             "\" r=\"6\" fill=\"white\" stroke=\"#c00\" stroke-width=\"1.5\"/>"
             "<text x=\"" +
             num(cx) + "\" y=\"" + num(y + 3.5) + "\" text-anchor=\"middle\" font-size=\"9\" fill=\"#c00\">" +
             std::to_string(k + 1) + "</text>";
      svg += legend_text(m.label);
    }
    if (!plot.events_label.empty()) {
      svg += "<line x1=\"" + num(left + pw + 25) + "\" y1=\"" + num(y - 6) + "\" x2=\"" + num(left + pw + 25) +
             "\" y2=\"" + num(y + 6) + "\" stroke=\"#7b3294\" stroke-width=\"1.2\"/>";
      svg += legend_text(plot.events_label);
    }
    svg += "</g>\n";
  }
  return svg + "</svg>\n";
}

}  // namespace granulab::pictures
