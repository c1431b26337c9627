#include "engine/experiments/crystal_compression/crystal_compression_experiment.h"

#include "engine/analysis/slip_bands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/analysis/apparent_modulus.h"
#include "engine/analysis/curve_peak.h"
#include "engine/analysis/loading_cycles.h"
#include "engine/analysis/stress_drops.h"
#include "engine/crystal/affine_stiffness.h"
#include "engine/crystal/sample_parameters.h"
#include "engine/framework/energy_report.h"
#include "engine/experiments/crystal_compression/quasi_static_quality.h"

namespace granulab {

namespace {

struct CrystalSummary : ExperimentResult {
  CrystalResult r;
  CrystalParams params;
  double p0 = 0;  // Pa
  double affine_modulus = 0;  // Pa, the affine tensor's Young's modulus along the axis (affine_stiffness.h)
  std::optional<YieldEstimate> estimate;

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.count("knocked_out", r.knocked_out);
    w.count("compression_steps", r.compression_steps);
    w.number("prestrain", r.prestrain, "-");
    w.number("strain_rate", r.strain_rate, "1/s");
    w.number("initial_length", r.initial_length, "m");
    w.number("cross_section", r.cross_section, "m^2");
    write_confinement(w, r.confinement);
    // The paper does not say whether its sigma_y ~ 7 p0 is the total axial stress or the deviator: both. A crystal
    // that never yields (or never falls from its largest deviator) has no first yield (or peak): found false, and
    // why, never the last row's numbers.
    std::vector<double> strain, deviator;
    for (const CrystalRow& row : r.curve) strain.push_back(row.strain), deviator.push_back(row.deviator);
    const double reached = strain.empty() ? 0.0 : *std::max_element(strain.begin(), strain.end());
    const CurvePeak first = first_peak(deviator, 0.1 * p0, 0.02);
    const CurvePeak highest = highest_peak(deviator, 0.1 * p0, 0.02);
    auto stress_point = [&](const char* key, const CurvePeak& peak, bool against_estimate) {
      char text[64];
      std::snprintf(text, sizeof text, "%.3g p0", p0 > 0 ? peak.highest / p0 : 0.0);
      if (begin_curve_peak(w, key, peak, missing_peak_reason(percent_text(reached) + " strain", text))) {
        const double dev = peak.value;
        w.number("strain", strain[peak.row], "-");
        w.number("deviator", dev, "Pa");
        w.number("deviator_over_p0", p0 > 0 ? dev / p0 : 0.0, "-");
        w.number("axial_over_p0", p0 > 0 ? (dev + p0) / p0 : 0.0, "-");
        // sigma1 measured over the rigid-grain estimate's (yield_estimate.h), when the run yielded and it found one
        if (against_estimate && estimate && estimate->found && dev > 0 && p0 > 0)
          w.number("over_estimate", (dev + p0) / p0 / estimate->axial_over_p0, "-");
      }
      w.end_group();
    };
    stress_point("first_yield", first, true);
    stress_point("peak", highest, false);
    write_apparent_modulus(w, apparent_modulus(strain, deviator, first.found ? first.value : highest.highest), p0,
                           "over_p0", affine_modulus, first.found ? "first yield" : "largest deviator");
    if (estimate) write_yield_estimate(w, *estimate);
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
    write_program(w, strain, deviator);
    double loading = 0;  // the strain the platen compressed over, all segments
    for (const SegmentRecord& s : r.segments)
      if (s.direction > 0 && s.last_row < r.curve.size())
        loading += r.curve[s.last_row].strain - r.curve[s.first_row].strain;
    write_stress_drops(w, r.stress_drops, params.stress_drop_threshold * p0, loading);
    if (r.fixed.on) {
      // Per face, the area the fixed forces were computed from and their sum over it: p0 x area.
      static const char* const faces[6] = {"x_plus", "x_minus", "y_plus", "y_minus", "z_plus", "z_minus"};
      w.begin_group(r.fixed.follows ? "pressed_faces" : "fixed_forces");
      for (int k = 0; k < 6; ++k) {
        w.begin_group(faces[k]);
        w.number("area", r.fixed.area[k], "m^2");
        w.number("force", r.fixed.load[k], "N");
        w.end_group();
      }
      w.end_group();
    }
    const QuasiStaticQuality quality = assess_quasi_static(params, r);
    write_quality(w, quality);
    w.begin_list("warnings");
    write_confinement_warning(w, r.confinement);
    for (const std::string& warning : quality.warnings) w.text(nullptr, warning);
    if (const std::string missed = missed_snapshots_warning(params.snapshot_strains, r.snapshots, reached); !missed.empty())
      w.text(nullptr, missed);
    w.end_list();
  }

  static void write_quality(SummaryWriter& w, const QuasiStaticQuality& q) {
    w.begin_group("quasi_static");
    w.number("rate_over_quasi_static", q.rate_over_quasi_static, "-");
    w.number("expected_bias", q.expected_bias, "-");
    w.number("platen_imbalance_rms", q.platen_imbalance_rms, "-");
    w.number("platen_imbalance_max", q.platen_imbalance_max, "-");
    w.number("kinetic_elastic_mean", q.kinetic_elastic_mean, "-");
    w.number("kinetic_elastic_max", q.kinetic_elastic_max, "-");
    w.number("slip_plane_span", q.slip_plane_span, "-");
    w.begin_list("hints");
    for (const std::string& hint : q.hints) w.text(nullptr, hint);
    w.end_list();
    w.end_group();
  }

  // The program's segments as run, and its load-unload cycles (loading_cycles.h).
  void write_program(SummaryWriter& w, const std::vector<double>& strain, const std::vector<double>& deviator) const {
    std::vector<CurveSegment> spans;
    w.begin_list("segments");
    for (std::size_t k = 0; k < r.segments.size(); ++k) {
      const SegmentRecord& s = r.segments[k];
      spans.push_back({s.direction, std::size_t(s.first_row), std::size_t(s.last_row)});
      if (s.last_row >= r.curve.size()) continue;
      w.begin_group(nullptr);
      w.count("index", k);
      w.text("kind", segment_kind_name(s.kind));
      w.text("direction", s.direction > 0 ? "compress" : s.direction < 0 ? "release" : "hold");
      w.count("steps", s.steps);
      w.number("start_strain", strain[s.first_row], "-");
      w.number("end_strain", strain[s.last_row], "-");
      w.number("end_deviator", deviator[s.last_row], "Pa");
      write_energy_change(w, "energy", r.curve[s.first_row].energy, r.curve[s.last_row].energy);
      w.end_group();
    }
    w.end_list();
    w.begin_list("cycles");
    for (const LoadingCycle& c : loading_cycles(strain, deviator, spans)) {
      w.begin_group(nullptr);
      w.count("unloading_segment", c.unloading_segment);
      w.number("peak_strain", c.peak_strain, "-");
      w.number("peak_deviator", c.peak_deviator, "Pa");
      w.number("residual_strain", c.residual_strain, "-");
      w.number("residual_deviator", c.residual_deviator, "Pa");
      const auto finite = [&](const char* key, double v, const char* unit) {
        if (std::isfinite(v)) w.number(key, v, unit);  // left out when the curve does not have it
      };
      finite("loading_slope", c.loading_slope, "Pa");
      finite("unloading_slope", c.unloading_slope, "Pa");
      finite("reloading_slope", c.reloading_slope, "Pa");
      finite("unloading_slope_end", c.unloading_slope_end, "Pa");
      finite("reloading_slope_end", c.reloading_slope_end, "Pa");
      finite("dissipated_energy", c.dissipated_energy, "J/m^3");
      write_energy_change(w, "energy", r.curve[c.first_row].energy, r.curve[c.last_row].energy);
      w.end_group();
    }
    w.end_list();
  }
};

}  // namespace

namespace {

void visit_program(ParameterVisitor& v, CrystalParams& p) {
  const std::size_t n = v.begin_list(
      "program", 1000,
      "segments run in order after confinement, each an object with one of to_strain, to_deviator, hold_steps; "
      "without them the run compresses to max_strain (docs/model.md, \"Loading programs\")");
  p.program.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    v.begin_item(i);
    LoadSegment& segment = p.program[i];
    const std::string path = "loading.program[" + std::to_string(i) + "]";
    const bool strain = v.present("to_strain"), deviator = v.present("to_deviator"), hold = v.present("hold_steps");
    const std::string one_of = "'" + path + "' must hold exactly one of to_strain, to_deviator, hold_steps";
    v.require(int(strain) + int(deviator) + int(hold) <= 1, path.c_str(), one_of);
    if (strain) {
      segment.kind = LoadSegment::Kind::to_strain;
      v.number("to_strain", segment.value, {0, p.max_strain, false, "loading.max_strain"}, "-",
               "compress or release the platen to this axial strain, at the rate's speed (at most loading.max_strain)");
    }
    if (deviator) {
      segment.kind = LoadSegment::Kind::to_deviator;
      v.number("to_deviator", segment.value, {-1e8, 1e8}, "Pa",
               "release the platen until the deviator falls to this value (above -p0), or until the platen lets go of "
               "the crystal");
      v.require(segment.value > -p.confining_pressure, (path + ".to_deviator").c_str(),
                "'" + path + ".to_deviator' must be above -p0 = " + std::to_string(-p.confining_pressure) +
                    " Pa: below it the platens have let go of the crystal");
    }
    if (hold) {
      int steps = 1000;
      v.integer("hold_steps", steps, 1, 100000000, "hold the platen still for this many time steps");
      segment.kind = LoadSegment::Kind::hold;
      segment.steps = std::uint64_t(steps);
    }
    v.end_item();  // an unknown key is named here, before the lack of a known one
    v.require(strain || deviator || hold, path.c_str(), one_of);
  }
  v.end_list();
}

}  // namespace

void CrystalCompressionExperiment::parameters(ParameterVisitor& v) {
  CrystalParams& p = params;
  visit_crystal_sample(v, p);
  v.section("loading");
  v.number("max_strain", p.max_strain, {0, 0.5, true}, "-",
           "compression stops here; with a loading.program, the largest strain its segments may ask for");
  static const char* const confinements[] = {"membrane", "fixed_forces", "face_forces", "taut_membrane"};
  std::string confinement = confinements[int(p.confinement)];
  v.choice("confinement", confinement, {"membrane", "fixed_forces", "face_forces", "taut_membrane"},
           "membrane: the vacuum bag wrapped over the whole sample, p0 on every exposed face of every surface grain, "
           "end faces included, turning and moving with it (a pressure on any surface); a crystal with knock-outs "
           "keeps the taut bag, which spans its holes; taut_membrane: the bag as "
           "modelled until 2026-12-07, p0 on each lateral grain's footprint on the face plane, re-detected every 200 "
           "steps, with the platens carrying p0 (too weak on staircase faces: docs/model.md, \"Confinement\"); "
           "fixed_forces: the taut bag confines it, then each lateral surface grain keeps p0 x its projected area "
           "along its face's inward normal and the end grains share the platens' p0 x cross-section, fixed in size "
           "and direction; face_forces: the paper's LAMMPS set-up: from the lattice as built, each surface grain "
           "keeps p0 x the vector area of its exposed faces, end grains included, fixed. Except with the taut bag "
           "the platens carry the deviator alone (the stress columns count p0 back in)");
  for (int k = 0; k < 4; ++k)
    if (confinement == confinements[k]) p.confinement = Confinement(k);
  v.require(p.confinement == Confinement::membrane || p.confinement == Confinement::taut_membrane || p.rows_z >= 2,
            "loading.confinement",
            "'loading.confinement' " + confinement +
                " needs crystal.rows_z >= 2: a grain on both ends would get both ends' forces");
  visit_program(v, p);
  if (!(p.rate_number > 0))
    p.rate_number = default_compression_rate_number(p.confining_pressure, p.material.youngs_modulus);
  v.number("rate_number", p.rate_number, {1e-8, 0.1}, "-",
           "R = L eps_dot / sqrt(E/rho) (default: 1.5 p0 / E, quasi-static to 2 %, docs/results.md)");
  v.section("output");
  v.integer("curve_points", p.curve_points, 1, 100000,
            "curve rows (a quarter of them over the first 2.5 % of the run)");
  // By default, the paper's snapshot strains that the run reaches; explicit ones must be reachable.
  std::vector<double> reachable;
  for (double e : p.snapshot_strains)
    if (e <= p.max_strain) reachable.push_back(e);
  p.snapshot_strains = reachable;
  v.numbers("snapshot_strains", p.snapshot_strains, {0, p.max_strain, false, "loading.max_strain"}, 1000, "-",
            "axial strains at which snapshots are taken (at most loading.max_strain)");
  v.number("stress_drop_threshold", p.stress_drop_threshold, {0, 1, true}, "-",
           "a stick-slip event is a drop of the deviator by at least this times p0 while the platen compresses "
           "(summary stress_drops; docs/model.md, \"Stick-slip events\")");
}

std::optional<YieldEstimate> CrystalCompressionExperiment::yield_estimate() const {
  return compression_yield_estimate(params.lattice, direction_vector(params.lattice, params.axis, 1),
                                    params.material.friction);
}

Headline CrystalCompressionExperiment::headline() const {
  const Scale per_p0{1, "p0", "loading.confining_pressure"};
  Headline h{"strain",
          {"axial strain", {100, "%"}, {100, "%"}},
          {"stress", per_p0, {1e-3, "kPa"}},
          {{"deviator", "deviator"}, {"top platen", "stress_top"}, {"bottom platen", "stress_bottom"}},
          {{"first_yield.deviator_over_p0", "first yield", "p0", "first_yield.strain", "first_yield.deviator",
            "first_yield"},
           {"peak.deviator_over_p0", "peak", "p0", "peak.strain", "peak.deviator", "peak"}},
          {{"segments", "loading segments"}, {"cycles", "load-unload cycles"}},
          {},
          "platen stresses include p0",
          {}};
  h.events = {"stress_drops.events", "strain", "stress drops"};
  // The rigid-grain estimate of the first yield (dashed, in the deviator's colour), when there is one.
  if (const auto e = yield_estimate(); e && e->found) {
    const double deviator = e->axial_over_p0 - 1, p0 = params.confining_pressure;
    h.references.push_back({"rigid-grain yield estimate, " + e->plane_text,
                            0,
                            {0, params.max_strain},
                            {deviator, deviator},
                            {1e-3 * deviator * p0, 1e-3 * deviator * p0}});
  }
  return h;
}

Workload CrystalCompressionExperiment::workload() const {
  Workload w = confinement_workload(params);
  if (params.confinement == Confinement::face_forces) w.steps = 0, w.phases.clear();  // no confinement phase
  else w.phases.front().steps = expected_compression_confinement_steps(params);
  // The bound: loading a sample no longer than rows_z grain sizes (the paper's rows are 0.61 a apart; other
  // lattices and axes can space them wider, so theirs is at least the crystal's own length), a program at its
  // longest (budgets rely on it); the expected phases: the crystal's own length, each segment as planned.
  const double length = crystal_length_estimate(params);  // builds the lattice: once
  double bound_length = params.rows_z * params.grain.size;
  if (!papers_crystal(params.lattice, params.axis, params.lateral)) bound_length = std::max(bound_length, length);
  w.steps += loading_steps_bound(params, bound_length);
  for (WorkPhase& phase : loading_phases(params, length, crystal_time_step(params)))
    w.phases.push_back(std::move(phase));
  // One compression: curve_points rows and the start. A program: up to curve_points over its travel (more
  // when it travels further than planned: twice, as a bound), 2 curve_points per segment for the deviator
  // releases, and a row at each segment's end.
  const double n = double(params.program.size()), points = double(params.curve_points);
  w.curve_rows = n == 0 ? points + 1 : 1 + n + points * (2 * n + 2);
  w.snapshots = double(params.snapshot_strains.size());
  return w;
}

std::unique_ptr<ExperimentResult> CrystalCompressionExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  auto out = std::make_unique<CrystalSummary>();
  CrystalCompression experiment(params);
  out->r = experiment.run(sink, resume);
  out->p0 = params.confining_pressure;
  out->params = params;
  out->estimate = yield_estimate();
  out->affine_modulus = affine_axial_modulus(params);
  return out;
}

std::unique_ptr<Experiment> make_crystal_compression() { return std::make_unique<CrystalCompressionExperiment>(); }

}  // namespace granulab
