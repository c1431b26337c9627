// The daemon's log lines, one per event whatever a client sends: a path with `%0a` (a newline once
// decoded) or `%1b` (an escape that recolours a terminal) would otherwise let any client write lines that
// look like the daemon's own. Every message goes through here, so no call site has to remember.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include <spdlog/formatter.h>

namespace granulab::server {

/// `text` with every ASCII control character (below 0x20, and 0x7f) written as \xNN.
std::string printable(std::string_view text);

/// spdlog's pattern formatter over the message made printable().
class PrintableFormatter : public spdlog::formatter {
 public:
  explicit PrintableFormatter(std::string pattern);
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override;
  std::unique_ptr<spdlog::formatter> clone() const override;

 private:
  std::string pattern_;
  std::unique_ptr<spdlog::formatter> inner_;
};

}  // namespace granulab::server
