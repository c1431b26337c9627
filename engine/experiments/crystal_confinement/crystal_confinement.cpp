#include "engine/experiments/crystal_confinement/crystal_confinement.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "engine/crystal/sample_parameters.h"

namespace granulab {

namespace {

struct ConfinementSummary : ExperimentResult {
  ConfinementReport report;
  RunStats run;
  double prestrain = 0;  // -

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, run);
    w.number("prestrain", prestrain, "-");
    write_confinement(w, report);
    w.begin_list("warnings");
    write_confinement_warning(w, report);
    w.end_list();
  }
};

}  // namespace

const std::vector<CurveColumn>& ConfinementRow::columns() {
  static const std::vector<CurveColumn> c = {
      {"step", "-", "time steps since the start of confinement", 0},
      {"stress_top", "Pa", "top platen stress, compressive positive"},
      {"stress_bottom", "Pa", "bottom platen stress, compressive positive"},
      {"lateral_stress_x", "Pa", "lateral stress the packing carries along x (virial)"},
      {"lateral_stress_y", "Pa", "lateral stress the packing carries along y (virial)"},
      {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
  };
  return c;
}

std::vector<double> ConfinementRow::values() const {
  return {step, stress_top, stress_bottom, lateral_stress_x, lateral_stress_y, kinetic_elastic_ratio};
}

void CrystalConfinementExperiment::parameters(ParameterVisitor& v) { visit_crystal_sample(v, params); }

Headline CrystalConfinementExperiment::headline() const {
  const Scale per_p0{1, "p0", "loading.confining_pressure"};
  return {"step",
          {"time step", {1, "-"}, {1, "-"}},
          {"stress", per_p0, {1e-3, "kPa"}},
          {{"top platen", "stress_top"},
           {"bottom platen", "stress_bottom"},
           {"lateral x", "lateral_stress_x"},
           {"lateral y", "lateral_stress_y"}},
          {{"prestrain", "pre-strain", "-"}},
          {},
          {},
          nullptr,
          {}};
}

Workload CrystalConfinementExperiment::workload() const {
  Workload w = confinement_workload(params);
  w.curve_rows = w.steps / std::max(1, params.membrane_interval) + 2;  // a row per membrane interval
  return w;
}

std::unique_ptr<ExperimentResult> CrystalConfinementExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  const auto start = std::chrono::steady_clock::now();
  auto out = std::make_unique<ConfinementSummary>();
  CrystalSample sample(params);
  ConfinementState state;
  std::uint64_t rows = 0;
  auto record = [&](std::uint64_t steps) {
    const auto [sx, sy] = sample.lateral_stresses();
    const ConfinementRow row{double(steps),
                             sample.wall_stress(sample.top_wall()),
                             sample.wall_stress(sample.bottom_wall()),
                             sx,
                             sy,
                             sample.kinetic_elastic_ratio()};
    sink.curve_row(row.values());
    ++rows;
  };
  // What a checkpoint holds beyond the sample, one list for writing and reading.
  const auto saved = [&](auto& archive) {
    archive.section("crystal_confinement");
    archive.value(state);
    archive.value(rows);
  };
  if (!resume) {
    record(0);
  } else {
    CheckpointReader in(*resume);
    sample.restore(in);
    saved(in);
    in.finish();
  }
  const auto safe_point = [&] {
    if (!sink.checkpoint_due()) return;
    sink.checkpoint(
        [&](CheckpointWriter& w) {
          sample.save(w);
          saved(w);
        },
        rows, 0);
  };
  out->report = confine(
      sample, [&](double f) { return sink.progress(f); }, record, &state, safe_point);
  // Its approach to equilibrium is in the curve already (every check's row); a confinement that never got there
  // fails the job with the numbers it reached, as every crystal experiment's does.
  require_confined(out->report, sample.params());
  sink.progress(1.0);
  out->prestrain = hydrostatic_prestrain(params);
  out->run = sample.world().run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return out;
}

std::unique_ptr<Experiment> make_crystal_confinement() { return std::make_unique<CrystalConfinementExperiment>(); }

}  // namespace granulab
