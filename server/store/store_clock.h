// The store's clock: every time it writes (created_ms, started_ms, events' at_ms) is Unix epoch milliseconds.
#pragma once

#include <chrono>
#include <cstdint>

namespace granulab::server {

inline std::int64_t now_ms() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
}

}  // namespace granulab::server
