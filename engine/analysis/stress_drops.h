// Stick-slip events of a loading: the drops of a stress signal (a crystal's deviator) while the platen compresses,
// found step by step with hysteresis. A drop starts at a running peak once the signal has fallen `threshold`
// below it; it ends at its trough once the signal has risen `threshold` above that (or the loading stretch ends),
// so the elastic wiggles of a quasi-static run, smaller than the threshold, neither start nor split one. Its size
// is peak - trough, its duration the time between them. Everything is plain data, kept through checkpoints.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/framework/summary_writer.h"

namespace granulab {

struct StressSample {
  std::uint64_t step = 0;  ///< world step (-)
  double time = 0;         ///< s
  double strain = 0;       ///< the experiment's strain (-)
  double value = 0;        ///< the stress (Pa)
};

struct StressDrop {
  double strain = 0;       ///< at the peak, where it began (-)
  double end_strain = 0;   ///< at the trough (-)
  double peak = 0;         ///< the stress there (Pa)
  double size = 0;         ///< peak - trough (Pa)
  double duration = 0;     ///< trough's time - peak's (s)
  std::uint64_t steps = 0; ///< the same in steps (-)
};

/// The detector's state between two samples.
struct StressDropTracker {
  double threshold = 0;  ///< Pa
  bool has_peak = false, in_drop = false;
  StressSample peak, trough;

  /// Takes a sample; true when it ended a drop, which is then in `out`.
  bool add(const StressSample& s, StressDrop& out);
  /// The loading stretch ends (an unloading or a hold follows, which are no events): a drop under way ends at its
  /// trough (true, in `out`); the running peak is forgotten.
  bool close(StressDrop& out);
};

/// The summary group "stress_drops": `threshold` (Pa), `count`, `largest`, `mean` and `total` size (Pa), `rate`
/// (drops per unit strain of the loading, over `loading_strain`), `size_distribution` (bins doubling from the
/// threshold: `from`, `to` (Pa), `count`) and `events` (in order, at most `max_listed`: `strain`, `end_strain`,
/// `peak`, `size` (Pa), `duration` (s), `steps`).
void write_stress_drops(SummaryWriter& w, const std::vector<StressDrop>& drops, double threshold,
                        double loading_strain, std::size_t max_listed = 1000);

}  // namespace granulab
