#include "server/machine_speed.h"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>

#include "engine/crystal/speed_probe.h"
#include "server/speed_model.h"

namespace granulab::server {

void MachineSpeed::measure() {
  double result = 0;
  if (seconds_ > 0) {
    try {
      omp_set_num_threads(2);
      const SpeedProbeResult r = crystal_speed_probe(seconds_);
      result = r.sphere_steps_per_second;
      spdlog::info("speed probe: {:.3g} sphere-steps/s on 2 threads ({} steps in {:.2f} s), {:.2f} x the machine "
                   "of the benchmark table",
                   result, r.steps, r.seconds, result / table_machine_probe());
    } catch (const std::exception& e) {
      spdlog::warn("speed probe failed ({}): cost estimates use the benchmark table as measured", e.what());
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  probe_ = result;
  finished_ = true;
  done_.notify_all();
}

double MachineSpeed::probe() const {
  std::unique_lock<std::mutex> lock(mutex_);
  if (seconds_ > 0) done_.wait_for(lock, std::chrono::seconds(10), [&] { return finished_; });
  return probe_;
}

}  // namespace granulab::server
