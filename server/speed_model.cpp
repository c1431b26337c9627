#include "server/speed_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granulab::server {

namespace {

struct TablePoint {
  double spheres, grains;
  double sphere_steps_per_second;  ///< on 2 threads (1/s)
};

// Points by size alone (an experiment's name belongs to its folder): spheres and spheres per grain set
// the cost of a step, whatever the experiment. Whole runs of the examples on 2 threads, one at a time (wall
// time including confinement, curve rows and snapshots; bench/README.md, "Cost estimates", 2026-12-02, an
// AVX-512 VM). A server on another machine scales them by its speed probe, then by its own finished jobs.
constexpr TablePoint kTable[] = {
    {976, 2, 1.72e8},       // two cubes, N_e = 10 (two runs: 1.51e8, 1.95e8)
    // shear_cubes (80 cubes of 56 spheres, 0.27 ms/step: a small crystal's per-step overhead), 2026-12-04 on a
    // VM whose probe read 0.57 of the table machine: 1.67e7 measured, 1.67e7 / 0.57 here
    {4480, 80, 2.93e7},
    // crystal_quick (8.54e7, 9.81e7; 9.16e7 on 2026-12-06, after the serial integrator and the guided chunks)
    {23760, 216, 9.15e7},
    // The reference crystal at N_e = 4 and fig7a_ne6, 2026-12-06 at the defaults of that day, on a VM whose probe
    // read 0.79 of the table machine (median of 10 daemon starts, 0.77-0.82): confinement_membrane_ne4 1.14e8,
    // imperfections_ne4 1.11e8, fig7a_ne6 2.16e8 there, / 0.79 here. Before the serial integrator and the guided
    // chunks 1.07e8 (0.96-1.15e8) and 2.30e8.
    {95040, 864, 1.42e8},
    {260928, 864, 2.73e8},
    // crystal_ref_p60 at its defaults (1.5 p0/E, 0.3 t0, quarter-step dashpots): 115,624 steps in 267.7 s, 2026-12-06,
    // on a VM whose probe read 0.74 of the table machine (median of 10 daemon starts, 0.70-0.77; 3.64e8 there). Before
    // the contact loop's guided chunks and the serial integrator, 3.73e8 (p0/E: 169,854 steps in 456.6 s).
    {841536, 864, 4.91e8},
};

// The speed probe (engine/crystal/speed_probe.h) on 2 threads on the machine of the table (1/s).
// Measured there as the median of 3 membrane intervals: 9.3e7, the median of 9 daemon starts (7.4-9.8e7). The
// probe is now its fastest 50-step chunk over 0.5 s, which read 1.13x the old median on another VM (32 starts
// of both, 2026-12-04); the table machine's value is converted by that ratio.
constexpr double kTableMachineProbe = 1.05e8;

double distance(const RunSize& a, double spheres, double grains) {
  const double per_grain_a = a.spheres / std::max(1.0, a.grains), per_grain_b = spheres / std::max(1.0, grains);
  return std::abs(std::log(std::max(1.0, a.spheres) / std::max(1.0, spheres))) +
         std::abs(std::log(std::max(1.0, per_grain_a) / std::max(1.0, per_grain_b)));
}

std::string text(const char* format, double x) {
  char out[64];
  std::snprintf(out, sizeof out, format, x);
  return out;
}

}  // namespace

double benchmark_speed(const RunSize& job) {
  // The two nearest points; an exact match is itself.
  double best[2] = {1e300, 1e300}, rate[2] = {0, 0};
  for (const TablePoint& p : kTable) {
    const double d = distance(job, p.spheres, p.grains);
    if (d < best[0]) best[1] = best[0], rate[1] = rate[0], best[0] = d, rate[0] = p.sphere_steps_per_second;
    else if (d < best[1]) best[1] = d, rate[1] = p.sphere_steps_per_second;
  }
  double log_rate = std::log(rate[0]);
  if (rate[1] > 0 && best[0] > 1e-9) {
    const double w0 = 1 / best[0], w1 = 1 / best[1];
    log_rate = (w0 * std::log(rate[0]) + w1 * std::log(rate[1])) / (w0 + w1);
  }
  return std::exp(log_rate) * std::pow(std::max(1, job.threads) / 2.0, 0.85);
}

double table_machine_probe() { return kTableMachineProbe; }

SpeedEstimate estimate_speed(const RunSize& job, const std::vector<MeasuredRun>& history, double probe) {
  const double table = benchmark_speed(job);
  struct Near {
    double distance, ratio;
  };
  std::vector<Near> same, other;
  for (const MeasuredRun& run : history) {
    if (!(run.sphere_steps_per_second > 0) || !(run.size.spheres > 0)) continue;
    // Threads count as size: a 1-thread run says less about a 2-thread job than one of its own kind.
    const double d = distance(job, run.size.spheres, run.size.grains) +
                     std::abs(std::log(double(std::max(1, run.size.threads)) / std::max(1, job.threads)));
    (run.size.experiment == job.experiment ? same : other)
        .push_back({d, run.sphere_steps_per_second / benchmark_speed(run.size)});
  }
  std::vector<Near>& use = same.empty() ? other : same;
  if (use.empty() && probe > 0) {
    const double factor = probe / kTableMachineProbe;
    return {table * factor, "the benchmark table (bench/README.md) times " + text("%.2f", factor) +
                                ", how this machine ran the speed probe at start (" + text("%.3g", probe) +
                                " sphere-steps/s) against the table's machine; no finished jobs here yet"};
  }
  if (use.empty()) return {table, "the benchmark table (bench/README.md); no finished jobs here yet, no speed probe"};
  std::sort(use.begin(), use.end(), [](const Near& a, const Near& b) { return a.distance < b.distance; });
  use.resize(std::min<std::size_t>(5, use.size()));
  std::vector<double> ratios;
  for (const Near& n : use) ratios.push_back(n.ratio);
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  const double factor = ratios[ratios.size() / 2];
  return {table * factor, "the benchmark table (bench/README.md) times " + text("%.2f", factor) + ", how the " +
                              std::to_string(use.size()) + " most similar recent " +
                              (same.empty() ? std::string("jobs of other experiments") : job.experiment + " jobs") +
                              " ran here against it"};
}

}  // namespace granulab::server
