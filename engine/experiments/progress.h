// How a long experiment reports progress and learns that it should stop. The engine knows nothing
// about terminals or servers: the caller decides what to do with the fraction.
#pragma once

#include <functional>
#include <stdexcept>

namespace granulab {

/// Called with the completed fraction in [0, 1]; return false to stop the run (cancellation).
using ProgressFn = std::function<bool(double fraction)>;

/// Thrown by an experiment whose progress callback asked it to stop.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace granulab
