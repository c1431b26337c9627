// Integer command-line options for both programs (granulab, granulabd): parsed without exceptions or
// locale, whole text only, range checked, and an error that names the option and its range.
#pragma once

#include <charconv>
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

}  // namespace granulab::api
