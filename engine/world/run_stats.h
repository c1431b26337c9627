// What every run reports about its own execution and the model numbers it derived, filled by the
// World that ran it (World::run_stats), so experiments do not copy them field by field.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace granulab {

/// Wall-clock seconds spent in each stage of the time step since the world was created (s): the
/// world's own stages, and those an experiment runs around them (the bag, the platens' control, the
/// recording of curve rows and snapshots), so that a profile accounts for the whole loop.
struct StageTimes {
  double integrate = 0, spheres = 0, rebuild = 0, contacts = 0, walls = 0;
  double membrane = 0, control = 0, record = 0;
};

/// Adds the seconds of its own lifetime to `sink` (a StageTimes field).
class StageTimer {
 public:
  explicit StageTimer(double& sink) : sink_(sink), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() { sink_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& sink_;
  std::chrono::steady_clock::time_point start_;
};

struct RunStats {
  std::size_t grains = 0;           ///< rigid bodies (-)
  std::size_t spheres = 0;          ///< spheres of all grains (-)
  std::uint64_t steps = 0;          ///< time steps since the world was built (-)
  std::uint64_t rebuilds = 0;       ///< force evaluations at which some candidates were searched again (-)
  std::uint64_t pair_searches = 0;  ///< grain pairs whose sphere pairs were searched, summed over the run (-)
  double mean_candidates = 0;       ///< sphere-pair candidates per force evaluation, averaged over the steps (-)
  double mean_skipped = 0;  ///< of which in grain pairs skipped as apart (engine/world/open_pairs.h), averaged (-)
  double time_step = 0;             ///< dt (s)
  double sphere_diameter = 0;       ///< d (m)
  double normal_stiffness = 0;      ///< the law's normal stiffness: k_n of one sphere pair (N/m) for hooke, k_N (Pa) else
  const char* normal_stiffness_unit = "N/m";
  int spheres_per_face = 0;         ///< N_f = N_e^2 (-)
  int threads = 1;                  ///< OpenMP threads of the run (-)
  double wall_seconds = 0;          ///< wall-clock time of the run (s)
  std::string kernel;               ///< the contact kernel's instruction set that ran (pair_kernels())
  StageTimes stage_times;
};

}  // namespace granulab
