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
/// About how wide `text` is in `font_px` px regular DejaVu Sans (the pictures' first font, and the widest of
/// their list): each printable ASCII character by its advance, measured in Chromium; any other character a
/// whole em (wider than most are), so that the estimate errs on the wide side.
double text_width(const std::string& text, double font_px);
/// `text` in lines of at most `width` px (text_width): broken after ", " where it can be (a sweep's "key = value"
/// pairs stay whole), else after spaces, a word wider than a line cut with an ellipsis. At least one line; `text`
/// itself when it fits.
std::vector<std::string> wrap_text(const std::string& text, double width, double font_px);
/// Ticks covering [lo, hi] at a 1/2/5 x 10^k step, about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);
/// A tick label: as few digits as tell neighbouring ticks apart.
std::string tick_label(double x, double step);

}  // namespace granulab::pictures
