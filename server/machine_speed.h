// This machine's speed probe (engine/crystal/speed_probe.h): what scales the benchmark table of the cost
// estimates before any job has finished here (server/speed_model.h). The daemon takes a first reading on its
// own thread before the executor starts, so no job competes with it; a dry run asked meanwhile waits for it (a
// fraction of a second) rather than answer with another machine's speed.
//
// One reading on a busy machine reads low: with a build on the same cores it gave 0.08 of the table, a third of
// the quiet machine's, and every dry run was 3x pessimistic for as long as the daemon ran (issue 51). So the
// daemon reads again while it runs no job, 30 s after the first reading, then at twice the interval each time up
// to every 5 minutes, and the probe is the best reading of the last 6 hours (of readings, counted back from the
// latest): a transient load passes, a machine that has become slower for good is seen within 6 hours.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <utility>
#include <vector>

namespace granulab::server {

class MachineSpeed {
 public:
  using Clock = std::chrono::steady_clock;
  /// One reading: sphere-steps per second on the table's 2 threads (0 or an exception: it failed).
  using Measure = std::function<double()>;
  using Now = std::function<Clock::time_point()>;

  static constexpr Clock::duration kFirstRefresh = std::chrono::seconds(30);
  static constexpr Clock::duration kMaxRefresh = std::chrono::minutes(5);
  static constexpr Clock::duration kKeep = std::chrono::hours(6);

  /// `seconds` of stepping per reading (0: no probe; the table is used as measured): the crystal probe on 2
  /// OpenMP threads, timed by the steady clock.
  explicit MachineSpeed(double seconds);
  /// The same with another probe and clock (tests).
  MachineSpeed(double seconds, Measure measure, Now now);

  /// Takes a reading now, on the calling thread (the daemon's first, before the executor starts).
  void measure();
  /// Takes a reading now when one is due (the interval since the last has passed: 30 s after the first, doubling
  /// up to 5 minutes) and the machine is `quiet` (no job running or waiting); returns whether it did.
  bool refresh(bool quiet);
  /// This machine's speed (sphere-steps/s): the best reading of those taken within kKeep of the latest, waiting
  /// up to 10 s for the first; 0 when off, failed or late.
  double probe() const;
  /// Readings taken, failed ones included.
  int readings() const;

 private:
  double best_locked() const;

  double seconds_;
  Measure measure_;
  Now now_;
  mutable std::mutex mutex_;
  mutable std::condition_variable done_;
  int attempts_ = 0;
  Clock::time_point last_attempt_{};
  std::vector<std::pair<Clock::time_point, double>> kept_;  ///< successful readings within kKeep of the latest
};

}  // namespace granulab::server
