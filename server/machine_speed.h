// This machine's speed probe, taken once at start (engine/crystal/speed_probe.h): what scales the
// benchmark table of the cost estimates before any job has finished here (server/speed_model.h). The
// daemon measures it on its own thread before the executor starts, so no job competes with it; a dry run
// asked meanwhile waits for it (a fraction of a second) rather than answer with another machine's speed.
#pragma once

#include <condition_variable>
#include <mutex>

namespace granulab::server {

class MachineSpeed {
 public:
  /// `seconds` of stepping (0: no probe; the table is used as measured).
  explicit MachineSpeed(double seconds) : seconds_(seconds) {}

  /// Runs the probe on 2 OpenMP threads (the table's), on the calling thread; once.
  void measure();
  /// The probe's sphere-steps per second, waiting up to 10 s for measure(); 0 when off, failed or late.
  double probe() const;

 private:
  double seconds_;
  mutable std::mutex mutex_;
  mutable std::condition_variable done_;
  bool finished_ = false;
  double probe_ = 0;
};

}  // namespace granulab::server
