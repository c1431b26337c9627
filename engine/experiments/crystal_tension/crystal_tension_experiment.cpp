#include "engine/experiments/crystal_tension/crystal_tension_experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/analysis/curve_peak.h"
#include "engine/analysis/slip_bands.h"
#include "engine/crystal/sample_parameters.h"
#include "engine/framework/energy_report.h"

namespace granulab {

namespace {

struct TensionSummary : ExperimentResult {
  TensionResult r;
  TensionParams params;

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.count("tension_steps", r.tension_steps);
    w.number("rate_number", params.rate_number, "-");
    w.number("strain_rate", r.gauge > 0 ? r.speed / r.gauge : 0.0, "1/s");
    w.text("confinement_while_pulling", params.bag ? "membrane" : "none");
    w.number("gauge_length", r.gauge, "m");
    w.number("cross_section", r.cross_section, "m^2");
    w.count("layers", r.layers);
    w.number("grip_depth", params.grip_depth, "-");
    w.begin_group("grip_grains");
    w.count("bottom", r.grip_grains[0]);
    w.count("top", r.grip_grains[1]);
    w.end_group();
    w.begin_group("grip_layers");
    w.count("bottom", std::uint64_t(r.grip_layers[0]));
    w.count("top", std::uint64_t(r.grip_layers[1]));
    w.end_group();
    write_confinement(w, r.confinement);
    // The largest tension the crystal carried, tracked every step. It is a strength only when the crystal failed:
    // it came apart, or its tension fell 2 % below that largest value afterwards. A crystal still holding (or still
    // stiffening) at max_strain has none, and says so (curve_peak.h), rather than report its last tension.
    const double last = r.curve.empty() ? 0.0 : r.curve.back().tensile_stress;
    CurvePeak failure;
    failure.found = r.peak.stress > 0 && (r.apart || last < 0.98 * r.peak.stress);
    failure.value = failure.highest = r.peak.stress;
    char text[96];
    std::snprintf(text, sizeof text, "still holding %.3g kPa (its largest %.3g kPa)", last / 1e3, r.peak.stress / 1e3);
    const std::string reason = r.peak.stress > 0 ? "none to " + percent_text(params.max_strain) + " strain: " + text
                                                 : "none: the crystal never pulled on its grips";
    if (begin_curve_peak(w, "failure", failure, reason)) w.count("step", r.peak.step);
    w.end_group();
    if (failure.found) {
      w.number("tensile_strength", r.peak.stress, "Pa");
      w.number("tensile_strength_over_p0", r.peak.stress / params.confining_pressure, "-");
      w.number("failure_strain", r.peak.strain, "-");
      w.count("failure_step", r.peak.step);
    }
    w.text("stopped", r.apart ? "apart" : "max_strain");
    w.number("initial_stress", r.curve.empty() ? 0.0 : r.curve.front().tensile_stress, "Pa");
    w.begin_group("failure_plane");
    if (r.failure.gap >= 0) {
      w.count("gap", std::uint64_t(r.failure.gap));
      w.number("height", r.failure.height, "m");
      w.number("opening", r.failure.opening, "m");
      w.number("share", r.failure.share, "-");
      w.text("where", r.failure.where);
    }
    w.end_group();
    w.begin_list("snapshots");
    for (std::size_t k = 0; k < r.snapshots.size(); ++k) {
      w.begin_group(nullptr);
      w.count("index", k);
      w.number("strain", r.snapshots[k].strain, "-");
      w.count("step", r.snapshots[k].step);
      write_slip_bands(w, r.snapshots[k].slip_bands, params.lattice);
      w.end_group();
    }
    w.end_list();
    if (!r.curve.empty()) write_energy_change(w, "energy", r.curve.front().energy, r.curve.back().energy);
    w.begin_list("warnings");
    write_confinement_warning(w, r.confinement);
    const double reached = r.curve.empty() ? 0.0 : r.curve.back().axial_strain;
    if (const std::string missed = missed_snapshots_warning(params.snapshot_strains, r.snapshots, reached); !missed.empty())
      w.text(nullptr, missed);
    w.end_list();
  }
};

}  // namespace

void CrystalTensionExperiment::parameters(ParameterVisitor& v) {
  TensionParams& p = params;
  visit_crystal_sample(v, p);
  v.section("loading");
  v.number("max_strain", p.max_strain, {0, 0.5, true}, "-",
           "the pull stops at this axial strain, or earlier once the crystal is apart (both grips under 1 % of the "
           "peak tension past twice its strain)");
  if (!(p.rate_number > 0))
    p.rate_number = tension_default_rate_number(p);
  v.number("rate_number", p.rate_number, {1e-8, 0.1}, "-",
           "R = v / sqrt(E/rho), v the top grip's speed (default: sigma / (10 E), sigma the larger of p0 and a cohesive "
           "law's pull-off force of one sphere pair over s^2, the order of the tensile strength)");
  std::string bag = p.bag ? "membrane" : "none";
  v.choice("confinement", bag, {"membrane", "none"},
           "while pulling: membrane (the bag keeps p0 on the lateral faces) or none (the bag is taken away after "
           "confinement; the crystal holds by its grips and its cohesion alone)");
  p.bag = bag == "membrane";
  v.number("grip_depth", p.grip_depth, {0, 5}, "-",
           "each grip holds the grains whose centres lie within this depth of its end, in grain sizes a (0: the end "
           "layer alone; 0.5: a row of the paper's crystal, whose end layers hold half its grains)");
  TensionLayers layers;
  try {
    layers = tension_layers(p);
  } catch (const std::exception&) {
    layers.free = 1;  // a sample that cannot be cut: visit_crystal_sample named its field
  }
  v.require(layers.free >= 1, "loading.grip_depth",
            "'crystal.rows_z' and 'loading.grip_depth' leave " + std::to_string(layers.free) + " of " +
                std::to_string(layers.count) +
                " layers along the axis (after knock-outs) between the grips: the crystal needs one or more there");
  v.section("output");
  v.integer("curve_points", p.curve_points, 1, 100000, "curve rows over the pull");
  std::vector<double> reachable;
  for (double e : p.snapshot_strains)
    if (e <= p.max_strain) reachable.push_back(e);
  p.snapshot_strains = reachable;
  v.numbers("snapshot_strains", p.snapshot_strains, {0, p.max_strain, false, "loading.max_strain"}, 1000, "-",
            "axial strains at which snapshots are taken");
}

Headline CrystalTensionExperiment::headline() const {
  return Headline{"axial_strain",
                  {"axial strain", {100, "%"}, {100, "%"}},
                  {"tensile stress", {1e-3, "kPa"}, {1e-3, "kPa"}},
                  {{"top grip", "tensile_stress"}, {"bottom grip", "tensile_stress_bottom"}},
                  {{"tensile_strength", "tensile strength", "Pa", "failure_strain", "tensile_strength", "failure"},
                   {"failure_strain", "strain at failure", "-", nullptr, nullptr, "failure"}},
                  {},
                  {},
                  "the contact force the grips receive along the axis over the cross-section, tension positive",
                  {}};
}

Workload CrystalTensionExperiment::workload() const {
  Workload w = confinement_workload(params);
  const double gap = tension_layers(params).gap;  // builds the lattice: once
  w.steps += tension_steps_bound(params, gap);
  w.phases.push_back({"pull to " + std::to_string(100 * params.max_strain) + " %",
                      tension_steps_expected(params, gap)});
  w.curve_rows = 2 + params.curve_points;
  w.snapshots = double(params.snapshot_strains.size());
  return w;
}

std::unique_ptr<ExperimentResult> CrystalTensionExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  auto out = std::make_unique<TensionSummary>();
  CrystalTension experiment(params);
  out->r = experiment.run(sink, resume);
  out->params = params;
  if (!(out->params.rate_number > 0))
    out->params.rate_number = tension_default_rate_number(params);
  return out;
}

std::unique_ptr<Experiment> make_crystal_tension() { return std::make_unique<CrystalTensionExperiment>(); }

}  // namespace granulab
