#include "server/log_format.h"

#include <spdlog/pattern_formatter.h>

namespace granulab::server {

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  static const char hex[] = "0123456789abcdef";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
      continue;
    }
    out += "\\x";
    out += hex[u >> 4];
    out += hex[u & 15];
  }
  return out;
}

PrintableFormatter::PrintableFormatter(std::string pattern)
    : pattern_(std::move(pattern)), inner_(std::make_unique<spdlog::pattern_formatter>(pattern_)) {}

void PrintableFormatter::format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) {
  const std::string_view payload(msg.payload.data(), msg.payload.size());
  for (const char c : payload) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      const std::string safe = printable(payload);
      spdlog::details::log_msg copy = msg;
      copy.payload = spdlog::string_view_t(safe.data(), safe.size());
      inner_->format(copy, dest);
      // The colour sink reads where the level's colour goes from the message it passed (mutable fields).
      msg.color_range_start = copy.color_range_start;
      msg.color_range_end = copy.color_range_end;
      return;
    }
  }
  inner_->format(msg, dest);
}

std::unique_ptr<spdlog::formatter> PrintableFormatter::clone() const {
  return std::make_unique<PrintableFormatter>(pattern_);
}

}  // namespace granulab::server
