// How fast this machine steps a crystal, measured in a fraction of a second: the machine factor of the
// server's cost estimates (server/speed_model.h). The benchmark table was measured on one machine; a server
// on another runs the same probe at start and scales the table by probe here / probe there, so that a fresh
// server's dry runs are right before any of its jobs has finished (bench/README.md, "Cost estimates").
#pragma once

namespace granulab {

struct SpeedProbeResult {
  double sphere_steps_per_second = 0;  ///< its fastest chunk of 50 steps (1/s)
  long steps = 0;                      ///< time steps taken (-)
  double seconds = 0;                  ///< wall time of the steps, the crystal's construction excluded (s)
};

/// Steps the tutorial's crystal (6 x 12 x 3 rhombic dodecahedra, N_e = 4, 23,760 spheres, 30 kPa) at rest
/// from its lattice, the bag re-detected every membrane interval as in a run, for at least `seconds` of wall
/// time, on the calling thread's OpenMP thread count. Its cost: that time plus about 20 ms to build.
SpeedProbeResult crystal_speed_probe(double seconds);

}  // namespace granulab
