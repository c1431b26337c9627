// What every run reports about its own execution and the model numbers it derived, filled by the
// World that ran it (World::run_stats), so experiments do not copy them field by field.
#pragma once

#include <cstddef>
#include <cstdint>

namespace granulab {

/// Wall-clock seconds spent in each stage of the time step since the world was created (s).
struct StageTimes {
  double integrate = 0, spheres = 0, rebuild = 0, contacts = 0, walls = 0;
};

struct RunStats {
  std::size_t grains = 0;             ///< rigid bodies (-)
  std::size_t spheres = 0;            ///< spheres of all grains (-)
  std::uint64_t steps = 0;            ///< time steps since the world was built (-)
  std::uint64_t rebuilds = 0;         ///< neighbour-list rebuilds (-)
  double time_step = 0;               ///< dt (s)
  double sphere_diameter = 0;         ///< d (m)
  double normal_stiffness = 0;        ///< k_n of one sphere pair (N/m)
  int spheres_per_face = 0;           ///< N_f = N_e^2 (-)
  int threads = 1;                    ///< OpenMP threads of the run (-)
  double wall_seconds = 0;            ///< wall-clock time of the run (s)
  StageTimes stage_times;
};

}  // namespace granulab
