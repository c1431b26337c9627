// What a run will cost, estimated from its parameters alone, before anything is built: a shared server
// refuses a job it cannot afford when it is submitted, not hours later (docs/api.md, "Budgets"), and a
// researcher plans with the expected time (docs/api.md, "Cost estimates").
#pragma once

#include <string>
#include <vector>

namespace granulab {

/// One phase of a run as the experiment models it (confinement, a loading segment, a slide).
struct WorkPhase {
  std::string name;  ///< what it does, as a user reads it ("confinement", "to_strain 0.5 %")
  double steps = 0;  ///< expected time steps (-)
};

struct Workload {
  double spheres = 0;  ///< spheres simulated (-)
  double grains = 0;   ///< rigid bodies (-)
  double steps = 0;    ///< time steps, an upper bound: budgets and time limits rely on it (-)
  std::vector<WorkPhase> phases;  ///< the expected steps of each phase, in the order they run
  /// What the run hands its sink, at most: what a store must have room for (the api sizes the bytes).
  double curve_rows = 0;  ///< curve rows (-)
  double snapshots = 0;   ///< grain snapshots, each of every grain (-)

  /// The steps the run is expected to take (-): the phases' sum (the bound when there are none).
  double expected_steps() const {
    if (phases.empty()) return steps;
    double sum = 0;
    for (const WorkPhase& p : phases) sum += p.steps;
    return sum;
  }
  double sphere_steps() const { return spheres * steps; }  ///< at most (-)
  double expected_sphere_steps() const { return spheres * expected_steps(); }  ///< expected (-)
  /// Peak resident memory (bytes). Measured with bench/memory_per_sphere.py (bench/README.md,
  /// "Memory"): 9 MB + 56 B per sphere + 3,050 B per grain fits every size from 0.1 to 50 million
  /// spheres within 3 %; the margin here (70 B, 3,800 B, 16 MB) covers the rest and other compilers.
  /// Checkpoints add their chunks, not a copy of the state (engine/core/checkpoint.h): one being written
  /// (16 MiB) or, when a run resumes, one fetched and the reader's buffers (18 MiB): kCheckpointBytes.
  static constexpr double kCheckpointBytes = 40e6;
  double peak_bytes() const { return 16e6 + kCheckpointBytes + 70.0 * spheres + 3800.0 * grains; }
};

}  // namespace granulab
