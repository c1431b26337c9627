// Integer and number command-line options for both programs (granulab, granulabd): parsed without exceptions or
// locale, whole text only, range checked, and an error that names the option and its range.
#pragma once

#include <charconv>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace granulab::api {

inline int parse_int_option(const std::string& option, const std::string& text, int lo, int hi) {
  int v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
    throw std::invalid_argument("'" + option + "' must be an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return v;
}

/// A finite number, e.g. `1e13`, in [lo, hi]: strtod on the whole text (from_chars for doubles needs gcc 11+
/// and is not in every libstdc++ we build on).
inline double parse_number_option(const std::string& option, const std::string& text, double lo, double hi) {
  char* end = nullptr;
  const double v = text.empty() ? 0 : std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(v >= lo && v <= hi))
    throw std::invalid_argument("'" + option + "' must be a number in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return v;
}

}  // namespace granulab::api
