#include "api/pictures/svg_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granulab::pictures {

std::string num(double x, int digits) {
  if (!std::isfinite(x)) return "0";
  if (std::abs(x) < 1e-12) return "0";
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, x);
  return text;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = text[i];
    if (c < 0x20 && c != '\t' && c != '\n') continue;  // not allowed in XML 1.0
    if (c >= 0x80) {
      // Keep a well-formed UTF-8 sequence, drop a stray byte (the XML must parse whatever a label holds).
      const int length = (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
      bool ok = length > 0 && i + length <= text.size();
      for (int k = 1; ok && k < length; ++k) ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 2;
      // XML 1.0 has no U+FFFE, U+FFFF or surrogates (ED A0..BF ..): drop them too.
      const auto byte = [&](int k) { return static_cast<unsigned char>(text[i + k]); };
      if (ok && length == 3 && c == 0xEF && byte(1) == 0xBF && byte(2) >= 0xBE) ok = false;
      if (ok && length == 3 && c == 0xED && byte(1) >= 0xA0) ok = false;
      if (ok) out.append(text, i, length), i += length - 1;
      continue;
    }
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += char(c);
    }
  }
  return out;
}

std::string fit_text(const std::string& text, double width, double px_per_char) {
  const std::size_t fits = std::size_t(std::max(10.0, width / px_per_char));
  if (text.size() <= fits) return text;
  std::size_t cut = fits - 1;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
  return text.substr(0, cut) + "\u2026";
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return {lo};
  const double raw = (hi - lo) / std::max(1, target);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step && ticks.size() < 50; t += step)
    ticks.push_back(std::abs(t) < 1e-9 * step ? 0.0 : t);
  return ticks;
}

std::string tick_label(double x, double step) {
  const int decimals = std::clamp(int(std::ceil(-std::log10(std::abs(step)) - 1e-9)), 0, 12);
  char text[40];
  if (std::abs(x) >= 1e6 || (std::abs(x) > 0 && std::abs(x) < 1e-4)) std::snprintf(text, sizeof text, "%.3g", x);
  else std::snprintf(text, sizeof text, "%.*f", decimals, x);
  return text;
}

}  // namespace granulab::pictures
