#include "engine/experiments/two_cube_sliding/two_cube_sliding_experiment.h"

#include <cmath>

#include "engine/model/model_parameters.h"

namespace granulab {

namespace {

struct TwoCubeSummary : ExperimentResult {
  TwoCubeResult r;
  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.number("sphere_spacing", r.spacing, "m");
    w.number("p0", r.p0, "N");
    w.number("slide_speed", r.slide_speed, "m/s");
    w.number("critical_prestrain", r.critical_prestrain, "-");
    w.number("contact_end_slide_over_size", r.contact_end_slide, "-");
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
  visit_integration(v, p.time_step_factor, p.skin_factor);
}

Workload TwoCubeSlidingExperiment::workload() const {
  Workload w;
  w.grains = 2;
  w.spheres = 2.0 * double(sphere_count(params.grain));
  // The top cube slides max_slide * l at R sqrt(E / rho), in steps of dt (as in TwoCubeSliding::run).
  const GrainTemplate grain(params.grain);
  const double dt = params.time_step_factor * contact_time_scale(grain, params.material.youngs_modulus, params.material.density);
  const double wave_speed = std::sqrt(params.material.youngs_modulus / params.material.density);
  w.steps = params.max_slide * params.grain.size / (params.rate_number * wave_speed * dt) + params.curve_points;
  return w;
}

std::unique_ptr<ExperimentResult> TwoCubeSlidingExperiment::run(ResultSink& sink, const std::string& resume) const {
  auto out = std::make_unique<TwoCubeSummary>();
  TwoCubeSliding experiment(params);
  out->r = experiment.run(sink, resume);
  return out;
}

std::unique_ptr<Experiment> make_two_cube_sliding() { return std::make_unique<TwoCubeSlidingExperiment>(); }

}  // namespace granulab
