// Small pieces every SVG picture needs: numbers written compactly, text escaped for XML, and "nice"
// axis ticks (1, 2 or 5 times a power of ten).
#pragma once

#include <string>
#include <vector>

namespace granulab::pictures {

/// A coordinate or value with `digits` significant digits, no exponent for ordinary magnitudes.
std::string num(double x, int digits = 5);
/// Text safe inside an XML element or attribute (& < > " ' escaped; invalid UTF-8 bytes dropped).
std::string xml_escape(const std::string& text);
/// `text` cut (at a character boundary, with an ellipsis) to about `width` px of `px_per_char` wide text.
std::string fit_text(const std::string& text, double width, double px_per_char);
/// Ticks covering [lo, hi] at a 1/2/5 x 10^k step, about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);
/// A tick label: as few digits as tell neighbouring ticks apart.
std::string tick_label(double x, double step);

}  // namespace granulab::pictures
