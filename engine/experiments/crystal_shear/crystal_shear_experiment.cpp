#include "engine/experiments/crystal_shear/crystal_shear_experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/analysis/apparent_modulus.h"
#include "engine/analysis/curve_peak.h"
#include "engine/analysis/slip_bands.h"
#include "engine/crystal/sample_parameters.h"
#include "engine/framework/energy_report.h"

namespace granulab {

namespace {

// The sense of the first move: the estimate and its line are for the direction the top layer goes first.
double first_sense(const ShearParams& p) {
  for (const LoadSegment& s : p.program)
    if (s.kind == LoadSegment::Kind::to_strain && s.value != 0) return s.value > 0 ? 1 : -1;
  return 1;
}

struct ShearSummary : ExperimentResult {
  ShearResult r;
  ShearParams params;
  std::optional<YieldEstimate> estimate;

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.count("shear_steps", r.shear_steps);
    w.number("normal_stress", params.normal_stress, "Pa");
    w.number("rate_number", params.rate_number, "-");
    w.number("shear_rate", r.gap > 0 ? r.speed / r.gap : 0.0, "1/s");
    w.number("gap", r.gap, "m");
    w.number("cross_section", r.cross_section, "m^2");
    w.count("layers", r.layers);
    w.begin_group("layer_grains");
    w.count("bottom", r.layer_grains[0]);
    w.count("top", r.layer_grains[1]);
    w.end_group();
    write_confinement(w, r.confinement);
    // The peak and the residual of the first segment that moves (the whole run without a program).
    std::size_t from = 0, last = r.curve.empty() ? 0 : r.curve.size() - 1;
    for (const SegmentRecord& s : r.segments)
      if (s.kind == LoadSegment::Kind::to_strain && s.direction != 0) {
        from = std::size_t(s.first_row), last = std::size_t(s.last_row);
        break;
      }
    last = std::min(last, r.curve.empty() ? 0 : r.curve.size() - 1);
    std::vector<ShearRow> first;
    if (!r.curve.empty()) first.assign(r.curve.begin() + std::min(from, last), r.curve.begin() + last + 1);
    // A peak only where |tau / sigma_n| falls 2 % below its running maximum afterwards (curve_peak.h): a slab still
    // hardening at the end of its travel has none.
    std::vector<double> ratio;
    for (const ShearRow& row : first) ratio.push_back(std::abs(row.shear_over_normal));
    double largest = 0;
    for (double x : ratio) largest = std::max(largest, x);
    const CurvePeak found = first_peak(ratio, 0.1 * largest, 0.02);
    const std::size_t peak = found.row;  // shear_peak_row()'s row
    char text[64];
    std::snprintf(text, sizeof text, "|tau / sigma_n| %.3g", found.highest);
    const double travel = first.empty() ? 0.0 : std::abs(first.back().shear_strain - first.front().shear_strain);
    if (begin_curve_peak(w, "peak", found, missing_peak_reason(percent_text(travel) + " shear strain", text))) {
      const ShearRow& p = first[peak];
      w.number("shear_strain", p.shear_strain, "-");
      w.number("shear_over_normal", p.shear_over_normal, "-");
      w.number("shear_stress", p.shear_stress, "Pa");
      w.number("normal_stress", p.normal_stress, "Pa");
      w.number("dilation", p.dilation, "-");
      if (estimate && estimate->found && estimate->shear_over_normal > 0)
        w.number("over_estimate", std::abs(p.shear_over_normal) / estimate->shear_over_normal, "-");
    }
    w.end_group();
    std::vector<double> gamma;
    for (const ShearRow& row : first) gamma.push_back(std::abs(row.shear_strain - first.front().shear_strain));
    std::vector<double> tau;
    for (const ShearRow& row : first) tau.push_back(std::abs(row.shear_stress));
    double largest_tau = 0;
    for (double x : tau) largest_tau = std::max(largest_tau, x);
    const double tau_reference = found.found ? std::abs(first[peak].shear_stress) : largest_tau;
    write_apparent_modulus(w, apparent_modulus(gamma, tau, tau_reference), params.normal_stress, "over_normal_stress",
                           0.0, found.found ? "peak" : "largest shear stress");
    // Residual: the mean over the last quarter of that segment's travel.
    const double start = first.empty() ? 0 : first.front().shear_strain, end = first.empty() ? 0 : first.back().shear_strain;
    const double quarter = start + 0.75 * (end - start);
    double sum = 0, rows = 0;
    for (const ShearRow& row : first)
      if ((end - start) * (row.shear_strain - quarter) >= 0) sum += row.shear_over_normal, rows += 1;
    w.begin_group("residual");
    w.number("shear_over_normal", rows > 0 ? sum / rows : 0.0, "-");
    w.number("from_strain", quarter, "-");
    w.number("to_strain", end, "-");
    w.end_group();
    const double window = std::max(0.1 * std::abs(end - start), 1e-4);
    w.number("dilation_angle", first.empty() ? 0.0 : shear_dilation_angle(first, first[peak].shear_strain, window), "deg");
    if (estimate) write_yield_estimate(w, *estimate);
    w.begin_list("snapshots");
    for (std::size_t k = 0; k < r.snapshots.size(); ++k) {
      w.begin_group(nullptr);
      w.count("index", k);
      w.number("strain", r.snapshots[k].strain, "-");
      w.count("step", r.snapshots[k].step);
      write_slip_bands(w, r.snapshots[k].slip_bands, params.lattice);
      if (k < r.sliding_planes.size() && r.sliding_planes[k].gap >= 0) {
        const SlidingPlane& s = r.sliding_planes[k];
        w.begin_group("sliding_plane");
        w.count("gap", std::uint64_t(s.gap));
        w.number("height", s.height, "m");
        w.number("share", s.share, "-");
        w.count("interfaces", s.interfaces);
        w.end_group();
      }
      w.end_group();
    }
    w.end_list();
    w.begin_list("segments");
    for (std::size_t k = 0; k < r.segments.size(); ++k) {
      const SegmentRecord& s = r.segments[k];
      if (s.last_row >= r.curve.size()) continue;
      w.begin_group(nullptr);
      w.count("index", k);
      w.text("kind", s.kind == LoadSegment::Kind::hold ? "hold" : "to_shear_strain");
      w.count("steps", s.steps);
      w.number("start_strain", r.curve[s.first_row].shear_strain, "-");
      w.number("end_strain", r.curve[s.last_row].shear_strain, "-");
      w.number("end_shear_over_normal", r.curve[s.last_row].shear_over_normal, "-");
      write_energy_change(w, "energy", r.curve[s.first_row].energy, r.curve[s.last_row].energy);
      w.end_group();
    }
    w.end_list();
    write_quality(w);
  }

  // How quasi-static it was: the rate against p0 / E, the two layers' shear stresses against each other, the
  // kinetic energy against the elastic.
  void write_quality(SummaryWriter& w) const {
    const double quasi_static = quasi_static_rate_number(params.confining_pressure, params.material.youngs_modulus);
    double largest = 0, ke_max = 0, ke_sum = 0, imbalance = 0, n = 0;
    for (const ShearRow& row : r.curve) largest = std::max(largest, std::abs(row.shear_stress));
    for (const ShearRow& row : r.curve) {
      ke_max = std::max(ke_max, row.kinetic_elastic_ratio), ke_sum += row.kinetic_elastic_ratio;
      if (largest > 0 && std::abs(row.shear_stress) > 0.1 * largest) {
        const double d = (row.shear_stress - row.shear_stress_bottom) / largest;
        imbalance += d * d, n += 1;
      }
    }
    const double rms = n > 0 ? std::sqrt(imbalance / n) : 0;
    w.begin_group("quasi_static");
    w.number("rate_over_quasi_static", params.rate_number / quasi_static, "-");
    w.number("layer_imbalance_rms", rms, "-");
    w.number("kinetic_elastic_mean", r.curve.empty() ? 0.0 : ke_sum / double(r.curve.size()), "-");
    w.number("kinetic_elastic_max", ke_max, "-");
    w.end_group();
    w.begin_list("warnings");
    write_confinement_warning(w, r.confinement);
    double reached = 0;
    for (const ShearRow& row : r.curve) reached = std::max(reached, std::abs(row.shear_strain));
    if (const std::string missed = missed_snapshots_warning(params.snapshot_strains, r.snapshots, reached); !missed.empty())
      w.text(nullptr, missed);
    if (params.rate_number > 2 * quasi_static)
      w.text(nullptr, "loading.rate_number " + std::to_string(params.rate_number) + " is " +
                          std::to_string(params.rate_number / quasi_static) +
                          " x p0 / E, the rate shown quasi-static for compression: the stresses may carry inertia");
    if (rms > 0.05)
      w.text(nullptr, "the top and bottom layers' shear stresses differ by " + std::to_string(100 * rms) +
                          " % rms of the largest: the shearing was not quasi-static");
    w.end_list();
  }
};

void visit_program(ParameterVisitor& v, ShearParams& p) {
  const std::size_t n = v.begin_list(
      "program", 1000,
      "segments run in order after confinement, each an object with one of to_shear_strain, hold_steps; without them "
      "the run shears to max_shear_strain");
  p.program.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    v.begin_item(i);
    LoadSegment& segment = p.program[i];
    const std::string path = "loading.program[" + std::to_string(i) + "]";
    const bool strain = v.present("to_shear_strain"), hold = v.present("hold_steps");
    const std::string one_of = "'" + path + "' must hold exactly one of to_shear_strain, hold_steps";
    v.require(int(strain) + int(hold) <= 1, path.c_str(), one_of);
    if (strain) {
      segment.kind = LoadSegment::Kind::to_strain;
      v.number("to_shear_strain", segment.value, {-p.max_shear_strain, p.max_shear_strain, false, "loading.max_shear_strain"},
               "-", "move the top layer to this shear strain (either sign: back through zero reverses the shear)");
    }
    if (hold) {
      int steps = 1000;
      v.integer("hold_steps", steps, 1, 100000000, "hold the top layer still along the shear direction for this many steps");
      segment.kind = LoadSegment::Kind::hold;
      segment.steps = std::uint64_t(steps);
    }
    v.end_item();
    v.require(strain || hold, path.c_str(), one_of);
  }
  v.end_list();
}

}  // namespace

void CrystalShearExperiment::parameters(ParameterVisitor& v) {
  ShearParams& p = params;
  visit_crystal_sample(v, p, &p.plane);
  v.section("loading");
  if (!(p.normal_stress > 0)) p.normal_stress = p.confining_pressure;
  v.number("normal_stress", p.normal_stress, {0, 1e8, true}, "Pa",
           "sigma_n: the constant load on the top layer along the plane's normal, over the cross-section (default: "
           "loading.confining_pressure)");
  v.number("max_shear_strain", p.max_shear_strain, {0, 2, true}, "-",
           "shearing stops here (top layer travel over the gap); with a loading.program, the largest |strain| it may ask "
           "for");
  if (!(p.rate_number > 0)) p.rate_number = quasi_static_rate_number(p.confining_pressure, p.material.youngs_modulus);
  v.number("rate_number", p.rate_number, {1e-8, 0.1}, "-",
           "R = v / sqrt(E/rho), v the top layer's speed (default: p0 / E, the quasi-static scale; compression's "
           "default is 1.5 p0 / E)");
  visit_program(v, p);
  // Two layers are the platens: at least one more must shear between them.
  std::size_t layers = 3;
  try {
    layers = slab_layers(p).count;
  } catch (const std::exception&) {
    // a sample that cannot be cut: visit_crystal_sample named its field
  }
  v.require(layers >= 3, "crystal.rows_z",
            "'crystal.rows_z' gives " + std::to_string(layers) +
                " layer(s) along the plane's normal: the slab needs three or more, its first and last being the platens");
  v.section("output");
  v.integer("curve_points", p.curve_points, 1, 100000, "curve rows over the planned travel");
  std::vector<double> reachable;
  for (double e : p.snapshot_strains)
    if (e <= p.max_shear_strain) reachable.push_back(e);
  p.snapshot_strains = reachable;
  v.numbers("snapshot_strains", p.snapshot_strains, {0, p.max_shear_strain, false, "loading.max_shear_strain"}, 1000,
            "-", "shear strains (their size, either sense) at which snapshots are taken");
}

std::optional<YieldEstimate> CrystalShearExperiment::yield_estimate() const {
  const Vec3 s = first_sense(params) * direction_vector(params.lattice, params.lateral, 1);
  return shear_yield_estimate(params.lattice, params.plane, s, params.material.friction);
}

Headline CrystalShearExperiment::headline() const {
  Headline h{"shear_strain",
             {"shear strain", {100, "%"}, {100, "%"}},
             {"shear stress", {1, "sigma_n", "loading.normal_stress"}, {1e-3, "kPa"}},
             {{"top layer", "shear_stress"}},
             {{"peak.shear_over_normal", "peak tau / sigma_n", "-", "peak.shear_strain", "peak.shear_stress", "peak"},
              {"residual.shear_over_normal", "residual tau / sigma_n", "-"},
              {"dilation_angle", "dilation angle at the peak", "deg"}},
             {{"segments", "loading segments"}},
             {},
             "the shear stress the top layer receives, over the normal stress",
             {}};
  if (const auto e = yield_estimate(); e && e->found) {
    const double ratio = first_sense(params) * e->shear_over_normal, sn = params.normal_stress;
    const double reach = first_sense(params) * params.max_shear_strain;
    h.references.push_back({"rigid-grain estimate", 0, {0, reach}, {ratio, ratio},
                            {1e-3 * ratio * sn, 1e-3 * ratio * sn}});
  }
  return h;
}

Workload CrystalShearExperiment::workload() const {
  Workload w = confinement_workload(params);
  const SlabLayers layers = slab_layers(params);  // builds the lattice: once
  w.steps += shear_steps_bound(params, layers.gap);
  for (WorkPhase& phase : shear_phases(params, layers.gap, crystal_time_step(params))) w.phases.push_back(std::move(phase));
  const double n = double(std::max<std::size_t>(1, params.program.size()));
  w.curve_rows = 2 + 2 * n + params.curve_points;
  w.snapshots = double(params.snapshot_strains.size());
  return w;
}

std::unique_ptr<ExperimentResult> CrystalShearExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  auto out = std::make_unique<ShearSummary>();
  CrystalShear experiment(params);
  out->r = experiment.run(sink, resume);
  out->params = params;
  if (!(out->params.rate_number > 0))
    out->params.rate_number = quasi_static_rate_number(params.confining_pressure, params.material.youngs_modulus);
  if (!(out->params.normal_stress > 0)) out->params.normal_stress = params.confining_pressure;
  out->estimate = yield_estimate();
  return out;
}

std::unique_ptr<Experiment> make_crystal_shear() { return std::make_unique<CrystalShearExperiment>(); }

}  // namespace granulab
