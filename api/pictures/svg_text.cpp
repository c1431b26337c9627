#include "api/pictures/svg_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

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

namespace {

// The advance of ' ' to '~' in DejaVu Sans, in hundredths of an em, rounded up (Chromium's getComputedTextLength()
// of ten of each character at 12 px).
constexpr unsigned char kAsciiAdvance[95] = {
    32, 41, 46, 84, 64, 96, 78, 28, 40,  40, 50, 84, 32, 37, 32, 34, 64, 64, 64, 64, 64, 64, 64, 64,
    64, 64, 34, 34, 84, 84, 84, 54, 100, 71, 69, 70, 78, 64, 58, 78, 76, 30, 30, 66, 56, 87, 75, 79,
    61, 79, 70, 64, 60, 74, 69, 99, 69,  62, 69, 40, 34, 40, 84, 50, 50, 62, 64, 55, 64, 62, 35, 64,
    64, 28, 28, 58, 28, 98, 64, 61, 64,  64, 40, 53, 40, 64, 60, 82, 60, 60, 53, 64, 34, 64, 84};

bool continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

}  // namespace

double text_width(const std::string& text, double font_px) {
  double em = 0;
  for (const char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u >= 32 && u < 127) em += kAsciiAdvance[u - 32] / 100.0;
    else if (u >= 0x80 && !continuation(c)) em += 1;  // a character beyond ASCII: its first byte counts
  }
  return em * font_px;
}

namespace {

// `text` in pieces, each ending just after an occurrence of `after` and the spaces that follow it.
std::vector<std::string> split_after(const std::string& text, const std::string& after) {
  std::vector<std::string> pieces;
  for (std::size_t i = 0; i < text.size();) {
    std::size_t end = text.find(after, i);
    if (end != std::string::npos) end = text.find_first_not_of(' ', end + after.size());
    if (end == std::string::npos) end = text.size();
    pieces.push_back(text.substr(i, end - i));
    i = end;
  }
  return pieces;
}

std::string trimmed(std::string s) { return s.erase(s.find_last_not_of(' ') + 1); }

}  // namespace

std::vector<std::string> wrap_text(const std::string& text, double width, double font_px) {
  std::vector<std::string> lines;
  std::string line;  // with the spaces after its last piece: they take no room at the end of a line
  // A piece goes on the line if it fits there, else on a new line; one wider than a whole line is broken in
  // turn: a list of "key = value, " pieces after its commas, such a piece after its spaces, a word cut at a
  // character boundary with an ellipsis.
  const std::function<void(const std::string&, int)> place = [&](const std::string& piece, int level) {
    if (text_width(trimmed(line + piece), font_px) <= width) {
      line += piece;
      return;
    }
    if (!trimmed(line).empty()) lines.push_back(trimmed(line));
    line.clear();
    if (text_width(trimmed(piece), font_px) <= width) {
      line = piece;
    } else if (level == 0) {
      for (const std::string& word : split_after(piece, " ")) place(word, 1);
    } else {
      std::string word = trimmed(piece);
      while (!word.empty() && text_width(word + "\u2026", font_px) > width) {
        word.pop_back();
        while (!word.empty() && continuation(word.back())) word.pop_back();
      }
      line = word + "\u2026 ";
    }
  };
  for (const std::string& piece : split_after(text, ", ")) place(piece, 0);
  if (!trimmed(line).empty() || lines.empty()) lines.push_back(trimmed(line));
  return lines;
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
