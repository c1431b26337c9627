// How fast this server will run a job, in sphere-steps per second, for the dry run's expected time
// (docs/api.md, "Cost estimates"). The cost of a sphere-step depends on the run's size and grain (a small
// crystal pays a per-step overhead, coarse grains have more contacts per sphere) and on the machine, so
// the estimate is this machine's benchmark table (bench/README.md, "Cost estimates") at the job's size,
// scaled by how this server's own finished jobs of the most similar sizes ran against the same table, or,
// before any has finished, by how this machine ran the speed probe at start against the table's machine.
#pragma once

#include <string>
#include <vector>

namespace granulab::server {

struct RunSize {
  std::string experiment;
  double spheres = 0;  ///< (-)
  double grains = 0;   ///< (-)
  int threads = 1;     ///< OpenMP threads of the run (-)
};

struct MeasuredRun {
  RunSize size;
  double sphere_steps_per_second = 0;  ///< as its summary reports it (1/s)
};

struct SpeedEstimate {
  double sphere_steps_per_second = 0;  ///< (1/s)
  std::string basis;                   ///< what it rests on, in words
};

/// The benchmark table's speed at a size (1/s): the two nearest measured points in log spheres and log
/// spheres per grain, weighted by inverse distance; times
/// (threads / 2)^0.85 since the table ran on 2 threads.
double benchmark_speed(const RunSize& job);

/// The speed probe (engine/crystal/speed_probe.h, 2 threads) on the machine the table was measured on (1/s).
double table_machine_probe();

/// The table's speed at `job`'s size times the median of measured / table over the (at most 5) runs of
/// `history` nearest to it (same experiment first). Without history, the table times this machine's
/// `probe` (its speed probe on 2 threads, 1/s) over table_machine_probe(), or the table alone when `probe`
/// is 0 (not measured). Pure, so that it can be checked without a server.
SpeedEstimate estimate_speed(const RunSize& job, const std::vector<MeasuredRun>& history, double probe = 0);

}  // namespace granulab::server
