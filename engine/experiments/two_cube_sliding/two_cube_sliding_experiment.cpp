#include "engine/experiments/two_cube_sliding/two_cube_sliding_experiment.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/model/model_parameters.h"

namespace granulab {

namespace {

struct TwoCubeSummary : ExperimentResult {
  TwoCubeResult r;
  // T / P while the cubes slide (eq. 1: the friction coefficient f): the median over the rows past the
  // first 5 % of the slide (T is still building up elastically before) with P above 0.2 P0 (the
  // contact's last spheres, where few pairs carry the load, are left out). 0 without such rows.
  double friction_ratio() const {
    std::vector<double> ratios;
    for (const TwoCubeRow& row : r.curve)
      if (row.slide_over_size > 0.05 && row.normal_over_p0 > 0.2 && row.normal_force > 0)
        ratios.push_back(row.tangential_force / row.normal_force);
    if (ratios.empty()) return 0;
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    return ratios[ratios.size() / 2];
  }
  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.number("sphere_spacing", r.spacing, "m");
    w.number("p0", r.p0, "N");
    w.number("slide_speed", r.slide_speed, "m/s");
    w.number("critical_prestrain", r.critical_prestrain, "-");
    w.number("contact_end_slide_over_size", r.contact_end_slide, "-");
    w.number("friction_ratio", friction_ratio(), "-");
    w.begin_list("warnings");
    w.end_list();
  }
};

}  // namespace

void TwoCubeSlidingExperiment::parameters(ParameterVisitor& v) {
  TwoCubeParams& p = params;
  visit_grain(v, p.grain);
  visit_material(v, p.material);
  v.section("loading");
  v.number("prestrain", p.prestrain, {0, 0.1, true}, "-", "eps0; centre distance l(1 - eps0)");
  v.number("max_slide", p.max_slide, {0, 1.5, true}, "-", "final u / l");
  v.number("rate_number", p.rate_number, {1e-8, 0.1}, "-", "slide speed / sqrt(E/rho); 4/R steps at the default dt");
  v.section("output");
  v.integer("curve_points", p.curve_points, 1, 100000, "curve rows after u = 0");
  visit_integration(v, p.time_step_factor, p.skin_factor, p.kernel);
}

Headline TwoCubeSlidingExperiment::headline() const {
  Headline h{"slide_over_size",
             {"slide u / l", {1, "-"}, {1, "-"}},
             {"force", {1, "P0"}, {1, "N"}},
             {{"P", "normal_over_p0", "normal_force"}, {"T", "tangential_over_p0", "tangential_force"}},
             {{"friction_ratio", "friction ratio T / P", "-"}},
             {},
             {},
             nullptr,
             {}};
  // Eq. 1 of the paper: P/P0 = 1 - u/l, T/P0 = f (1 - u/l), up to the largest slide; in N times P0.
  const double f = params.material.friction, end = params.max_slide;
  const double p0 = params.material.youngs_modulus * params.grain.size * params.grain.size * params.prestrain;
  h.references.push_back({"P, eq. 1", 0, {0, end}, {1, 1 - end}, {p0, p0 * (1 - end)}});
  h.references.push_back({"T, eq. 1 (f = " + std::to_string(f).substr(0, 5) + ")",
                          1,
                          {0, end},
                          {f, f * (1 - end)},
                          {f * p0, f * p0 * (1 - end)}});
  return h;
}

Workload TwoCubeSlidingExperiment::workload() const {
  Workload w;
  w.grains = 2;
  w.spheres = 2.0 * double(sphere_count(params.grain));
  // The top cube slides max_slide * l at R sqrt(E / rho), in steps of dt (as in TwoCubeSliding::run).
  const GrainTemplate grain(params.grain);
  const double dt =
      params.time_step_factor * contact_time_scale(grain, params.material.youngs_modulus, params.material.density);
  const double wave_speed = std::sqrt(params.material.youngs_modulus / params.material.density);
  w.steps = params.max_slide * params.grain.size / (params.rate_number * wave_speed * dt) + params.curve_points;
  w.phases.push_back({"slide", w.steps});  // the run is its one slide: the bound is what it takes
  w.curve_rows = double(params.curve_points) + 1;
  return w;
}

std::unique_ptr<ExperimentResult> TwoCubeSlidingExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  auto out = std::make_unique<TwoCubeSummary>();
  TwoCubeSliding experiment(params);
  out->r = experiment.run(sink, resume);
  return out;
}

std::unique_ptr<Experiment> make_two_cube_sliding() { return std::make_unique<TwoCubeSlidingExperiment>(); }

}  // namespace granulab
