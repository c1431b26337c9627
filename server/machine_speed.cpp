#include "server/machine_speed.h"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "engine/contact/pair_kernel.h"
#include "engine/crystal/speed_probe.h"
#include "server/speed_model.h"

namespace granulab::server {

MachineSpeed::MachineSpeed(double seconds)
    : MachineSpeed(
          seconds,
          [seconds] {
            omp_set_num_threads(2);  // the table's threads (this thread's setting only)
            const SpeedProbeResult r = crystal_speed_probe(seconds);
            spdlog::debug("speed probe: {:.3g} sphere-steps/s ({} steps in {:.2f} s)", r.sphere_steps_per_second,
                          r.steps, r.seconds);
            return r.sphere_steps_per_second;
          },
          [] { return Clock::now(); }) {}

MachineSpeed::MachineSpeed(double seconds, Measure measure, Now now)
    : seconds_(seconds), measure_(std::move(measure)), now_(std::move(now)) {}

double MachineSpeed::best_locked() const {
  double best = 0;
  for (const auto& [at, value] : kept_) best = std::max(best, value);
  return best;
}

void MachineSpeed::measure() {
  if (!(seconds_ > 0)) return;
  double value = 0;
  std::string failure;
  try {
    value = measure_();
  } catch (const std::exception& e) {
    failure = e.what();
  }
  const Clock::time_point at = now_();
  std::lock_guard<std::mutex> lock(mutex_);
  const double before = best_locked();
  ++attempts_;
  last_attempt_ = at;
  if (std::isfinite(value) && value > 0) {
    kept_.emplace_back(at, value);
    kept_.erase(std::remove_if(kept_.begin(), kept_.end(), [&](const auto& r) { return at - r.first > kKeep; }),
                kept_.end());
  }
  const double best = best_locked();
  if (attempts_ == 1 && best > 0)
    spdlog::info("speed probe: {:.3g} sphere-steps/s on 2 threads with the {} contact kernel, {:.2f} x the machine "
                 "of the benchmark table",
                 best, resolve_pair_kernel(""), best / table_machine_probe());
  else if (attempts_ == 1)
    spdlog::warn("speed probe failed ({}): cost estimates use the benchmark table as measured",
                 failure.empty() ? "no reading" : failure);
  else if (best > 0 && std::abs(best - before) > 0.05 * std::max(before, best))
    spdlog::info(
        "speed probe read again while no job ran: {:.3g} sphere-steps/s ({:.2f} x the table's machine; "
        "this reading {:.2f} x), was {:.2f} x",
        best, best / table_machine_probe(), value / table_machine_probe(), before / table_machine_probe());
  done_.notify_all();
}

bool MachineSpeed::refresh(bool quiet) {
  if (!(seconds_ > 0) || !quiet) return false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (attempts_ == 0) return false;  // the first reading is the daemon's, at start
    // 30 s after the first reading, then twice the interval each time, up to kMaxRefresh.
    Clock::duration interval = kFirstRefresh;
    for (int k = 1; k < attempts_ && interval < kMaxRefresh; ++k) interval *= 2;
    if (now_() - last_attempt_ < std::min(interval, kMaxRefresh)) return false;
  }
  measure();
  return true;
}

double MachineSpeed::probe() const {
  std::unique_lock<std::mutex> lock(mutex_);
  if (seconds_ > 0) done_.wait_for(lock, std::chrono::seconds(10), [&] { return attempts_ > 0; });
  return best_locked();
}

int MachineSpeed::readings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return attempts_;
}

}  // namespace granulab::server
