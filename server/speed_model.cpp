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
// the cost of a step, whatever the experiment. This machine, 2 threads, whole runs of the examples (wall time
// including confinement, curve rows and snapshots; bench/README.md, "Cost estimates", 2026-12-02, an AVX2 VM
// about 2x slower than the AVX-512 one of the sessions before: a server's own finished jobs rescale it).
constexpr TablePoint kTable[] = {
    {976, 2, 6.7e7},        // two cubes, N_e = 10
    {23760, 216, 4.0e7},    // crystal_quick
    {95040, 864, 4.6e7},    // the reference crystal at N_e = 4 (confinement_*_ne4, imperfections_ne4)
    {260928, 864, 7.43e7},  // fig7a_ne6
    {841536, 864, 9.38e7},  // crystal_ref_p60
};

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

SpeedEstimate estimate_speed(const RunSize& job, const std::vector<MeasuredRun>& history) {
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
  if (use.empty()) return {table, "this machine's benchmark table (bench/README.md); no finished jobs here yet"};
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
