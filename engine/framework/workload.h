// What a run will cost, estimated from its parameters alone, before anything is built: a shared server
// refuses a job it cannot afford when it is submitted, not hours later (docs/api.md, "Budgets").
#pragma once

namespace granulab {

struct Workload {
  double spheres = 0;  ///< spheres simulated (-)
  double grains = 0;   ///< rigid bodies (-)
  double steps = 0;    ///< time steps, an upper estimate (-)

  double sphere_steps() const { return spheres * steps; }
  /// Peak resident memory (bytes). Measured with bench/memory_per_sphere.py (bench/README.md,
  /// "Memory"): 9 MB + 56 B per sphere + 3,050 B per grain fits every size from 0.1 to 50 million
  /// spheres within 3 %; the margin here (70 B, 3,800 B, 16 MB) covers the rest and other compilers.
  double peak_bytes() const { return 16e6 + 70.0 * spheres + 3800.0 * grains; }
};

}  // namespace granulab
