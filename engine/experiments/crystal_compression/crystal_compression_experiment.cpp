#include "engine/experiments/crystal_compression/crystal_compression_experiment.h"

#include <cmath>
#include <string>

#include "engine/crystal/sample_parameters.h"

namespace granulab {

namespace {

struct CrystalSummary : ExperimentResult {
  CrystalResult r;
  double p0 = 0;  // Pa

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.count("knocked_out", r.knocked_out);
    w.count("compression_steps", r.compression_steps);
    w.number("prestrain", r.prestrain, "-");
    w.number("strain_rate", r.strain_rate, "1/s");
    w.number("initial_length", r.initial_length, "m");
    w.number("cross_section", r.cross_section, "m^2");
    write_confinement(w, r.confinement);
    // The paper does not say whether its sigma_y ~ 7 p0 is the total axial stress or the deviator: both.
    const auto [yield_strain, yield_deviator] = first_yield_peak(r.curve, p0);
    double peak = 0, peak_strain = 0;
    for (const CrystalRow& row : r.curve)
      if (row.deviator > peak) peak = row.deviator, peak_strain = row.strain;
    auto stress_point = [&](const char* key, double strain, double deviator) {
      w.begin_group(key);
      w.number("strain", strain, "-");
      w.number("deviator", deviator, "Pa");
      w.number("deviator_over_p0", p0 > 0 ? deviator / p0 : 0.0, "-");
      w.number("axial_over_p0", p0 > 0 ? (deviator + p0) / p0 : 0.0, "-");
      w.end_group();
    };
    stress_point("first_yield", yield_strain, yield_deviator);
    stress_point("peak", peak_strain, peak);
    w.begin_list("snapshots");
    for (std::size_t k = 0; k < r.snapshots.size(); ++k) {
      w.begin_group(nullptr);
      w.count("index", k);
      w.number("strain", r.snapshots[k].strain, "-");
      w.count("step", r.snapshots[k].step);
      w.end_group();
    }
    w.end_list();
    w.begin_list("warnings");
    write_confinement_warning(w, r.confinement);
    w.end_list();
  }
};

}  // namespace

void CrystalCompressionExperiment::parameters(ParameterVisitor& v) {
  CrystalParams& p = params;
  visit_crystal_sample(v, p);
  v.section("loading");
  v.number("max_strain", p.max_strain, {0, 0.5, true}, "-", "compression stops here");
  if (!(p.rate_number > 0)) p.rate_number = quasi_static_rate_number(p.confining_pressure, p.material.youngs_modulus);
  v.number("rate_number", p.rate_number, {1e-8, 0.1}, "-",
           "R = L eps_dot / sqrt(E/rho) (default: p0 / E, quasi-static to 2 %; docs/results.md)");
  v.section("output");
  v.integer("curve_points", p.curve_points, 1, 100000, "curve rows (a quarter of them over the first 2.5 % of the run)");
  // By default, the paper's snapshot strains that the run reaches; explicit ones must be reachable.
  std::vector<double> reachable;
  for (double e : p.snapshot_strains)
    if (e <= p.max_strain) reachable.push_back(e);
  p.snapshot_strains = reachable;
  v.numbers("snapshot_strains", p.snapshot_strains, {0, p.max_strain}, 1000, "-",
            "axial strains at which snapshots are taken (at most loading.max_strain)");
}

Workload CrystalCompressionExperiment::workload() const {
  Workload w = confinement_workload(params);
  // Compression: the platen approaches at R c after a ramp of 10 L / c (run()), over max_strain of a
  // sample no longer than rows_z grain sizes.
  const double wave_speed = std::sqrt(params.material.youngs_modulus / (params.material.density * params.mass_scaling));
  const double length = params.rows_z * params.grain.size;
  const double seconds = params.max_strain * length / (params.rate_number * wave_speed) + 5 * length / wave_speed;
  w.steps += seconds / crystal_time_step(params);
  return w;
}

std::unique_ptr<ExperimentResult> CrystalCompressionExperiment::run(ResultSink& sink, const std::string& resume) const {
  auto out = std::make_unique<CrystalSummary>();
  CrystalCompression experiment(params);
  out->r = experiment.run(sink, resume);
  out->p0 = params.confining_pressure;
  return out;
}

std::unique_ptr<Experiment> make_crystal_compression() { return std::make_unique<CrystalCompressionExperiment>(); }

}  // namespace granulab
