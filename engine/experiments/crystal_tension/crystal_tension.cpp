#include "engine/experiments/crystal_tension/crystal_tension.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/crystal/end_layers.h"
#include "engine/crystal/loading_program.h"
#include "engine/framework/energy_report.h"

namespace granulab {

TensionParams::TensionParams() {
  // A small slab of the paper's crystal: 4 x 4 x 6 rows along [-1 -1 2].
  grains_x = 4, layers_y = 4, rows_z = 6;
}

const std::vector<CurveColumn>& TensionRow::columns() {
  static const std::vector<CurveColumn> c = [] {
    std::vector<CurveColumn> c = {
        {"axial_strain", "-",
         "change of the grips' separation / the gauge length (between the grips' inner layers at the start), "
         "opening positive"},
        {"tensile_stress", "Pa", "contact force the top grip receives against the pull / cross-section, tension positive"},
        {"tensile_stress_bottom", "Pa", "the bottom grip's contact force along the pull / cross-section"},
        {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
        {"contacts", "-", "sphere pairs in contact", 0},
        {"sliding_contacts", "-", "of which at the Coulomb limit", 0},
    };
    c.insert(c.end(), energy_columns().begin(), energy_columns().end());  // the grips are the platens
    return c;
  }();
  return c;
}

std::vector<double> TensionRow::values() const {
  std::vector<double> v = {axial_strain,          tensile_stress,   tensile_stress_bottom,
                           kinetic_elastic_ratio, double(contacts), double(sliding_contacts)};
  append_energy_values(energy, v);
  return v;
}

namespace {

TensionParams with_defaults(TensionParams p) {
  if (!(p.rate_number > 0)) p.rate_number = tension_default_rate_number(p);
  return p;
}

}  // namespace

double tension_stress_scale(const TensionParams& p) {
  return std::max(p.confining_pressure, cohesive_stress_scale(p));
}

// At R = 1e-5 (about sigma / E) a cohesive slab's strength came out 4.0 % above its value at R = 1e-7, at a tenth of
// it 0.7 % (a 4 x 4 x 6 dmt crystal at gamma = 2, docs/results.md).
double tension_default_rate_number(const TensionParams& p) {
  return quasi_static_rate_number(0.1 * tension_stress_scale(p), p.material.youngs_modulus);
}

bool tension_apart(const TensionPeak& peak, double strain, double top, double bottom) {
  return peak.stress > 0 && strain > 2 * peak.strain && std::abs(top) < 0.01 * peak.stress &&
         std::abs(bottom) < 0.01 * peak.stress;
}

TensionLayers tension_layers(const TensionParams& p) {
  const std::vector<double> heights = site_heights(sample_lattice(p).sites, p.grain.size);
  TensionLayers out;
  out.count = heights.size();
  if (heights.empty()) return out;
  const double reach = p.grip_depth * p.grain.size + 1e-9 * p.grain.size;
  double inner_bottom = heights.front(), inner_top = heights.back();
  for (double h : heights) {
    out.free += h >= heights.front() + reach && h <= heights.back() - reach;
    if (h < heights.front() + reach) inner_bottom = h;
    if (h > heights.back() - reach) inner_top = std::min(inner_top, h);
  }
  out.gap = inner_top - inner_bottom;
  return out;
}

// The travel at full speed and half the ramp of ten wave transits, as a compression segment.
double tension_steps_expected(const TensionParams& p, double gap) {
  const TensionParams q = with_defaults(p);
  const double c = crystal_wave_speed(q);
  return (q.max_strain * gap / (q.rate_number * c) + 5 * gap / c) / crystal_time_step(q);
}

double tension_steps_bound(const TensionParams& p, double gap) {
  const TensionParams q = with_defaults(p);
  const double c = crystal_wave_speed(q);
  return (q.max_strain * gap / (q.rate_number * c) + 40 * gap / c) / crystal_time_step(q);
}

struct CrystalTension::Run {
  ResultSink& sink;
  TensionResult& r;
  Position& at;
  std::vector<double> snapshot_strains;  // ascending
  double strain_per_row = 0, speed = 0, ramp_time = 0;
  double share = 0, confinement_steps = 0, tension_steps = 1;  // the progress bar's split
};

CrystalTension::CrystalTension(const TensionParams& params) : params_(with_defaults(params)), sample_(params_) {}

double CrystalTension::strain_now() const {
  const std::vector<Vec3>& x = sample_.world().bodies().position;
  return (mean_coordinate(grip_[1], x, 2) - mean_coordinate(grip_[0], x, 2) - ref_separation_) / gauge_;
}

double CrystalTension::grip_force(int grip) const {
  const World& world = sample_.world();
  double f = 0;
  // The contacts alone: less the bag's share on the grips' lateral faces.
  for (BodyId b : grip_[grip]) f += world.bodies().force[b].z() - world.external_force()[b].z();
  return f;
}

TensionRow CrystalTension::measure() const {
  TensionRow row;
  const World& world = sample_.world();
  const double area = sample_.cross_section();
  row.axial_strain = strain_now();
  row.tensile_stress = -grip_force(1) / area;
  row.tensile_stress_bottom = grip_force(0) / area;
  row.kinetic_elastic_ratio = sample_.kinetic_elastic_ratio();
  row.contacts = world.contact_stats().contacts;
  row.sliding_contacts = world.contact_stats().sliding;
  row.energy = world.energy_balance();
  return row;
}

// Each grain belongs to the layer whose height at the start is nearest its own; a gap opens by the change of the
// distance between its two layers' mean heights.
FailurePlane CrystalTension::failure_plane() const {
  FailurePlane out;
  const std::size_t n = layer_heights_.size();
  if (n < 2) return out;
  std::vector<double> sum(n, 0.0), count(n, 0.0);
  const std::vector<Vec3>& x = sample_.world().bodies().position;
  for (std::size_t b = 0; b < ref_.position.size(); ++b) {
    const double z0 = ref_.position[b].z();
    std::size_t k = std::size_t(std::lower_bound(layer_heights_.begin(), layer_heights_.end(), z0) - layer_heights_.begin());
    if (k == n || (k > 0 && z0 - layer_heights_[k - 1] < layer_heights_[k] - z0)) --k;
    sum[k] += x[b].z(), count[k] += 1;
  }
  double total = 0, best = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (!(count[k] > 0 && count[k + 1] > 0)) continue;
    const double opening =
        (sum[k + 1] / count[k + 1] - sum[k] / count[k]) - (layer_heights_[k + 1] - layer_heights_[k]);
    total += std::max(opening, 0.0);
    if (opening > best) best = opening, out.gap = int(k);
  }
  if (out.gap < 0) return out;
  out.height = 0.5 * (layer_heights_[out.gap] + layer_heights_[out.gap + 1]) - layer_heights_.front();
  out.opening = best;
  out.share = total > 0 ? best / total : 0;
  out.where = out.gap + 1 == grip_layers_[0]                 ? "bottom grip"
              : out.gap + 1 == int(n) - grip_layers_[1]      ? "top grip"
                                                             : "inside";
  return out;
}

void CrystalTension::record(Run& run) {
  run.r.curve.push_back(measure());
  run.at.row_step = sample_.world().steps();
  run.at.row_strain = run.r.curve.back().axial_strain;
  run.sink.curve_row(run.r.curve.back().values());
}

void CrystalTension::take_due_snapshots(Run& run) {
  const std::vector<double>& targets = run.snapshot_strains;
  while (run.at.next_snapshot < targets.size() && strain_now() >= targets[run.at.next_snapshot] - 1e-12) {
    run.r.snapshots.push_back(crystal_snapshot(sample_, ref_, targets[run.at.next_snapshot++]));
    run.sink.snapshot(run.r.snapshots.size() - 1, run.r.snapshots.back());
  }
}

void CrystalTension::safe_point(Run& run) const {
  if (run.sink.checkpoint_due())
    run.sink.checkpoint([&](CheckpointWriter& out) { save(out, run.at, run.r); }, run.r.curve.size(),
                        run.r.snapshots.size());
}

// After confinement: the end layers become the grips, the platens (and, without the bag, its forces) go.
void CrystalTension::confine_and_grip(Run& run) {
  const auto progress = [&](double f) {
    const double steps = -std::log(std::max(1e-12, 1 - f)) * confinement_progress_steps(sample_);
    return run.sink.progress(run.share * std::min(1.0, steps / run.confinement_steps));
  };
  run.r.confinement = confine(sample_, progress, nullptr, &run.at.confinement, [&] { safe_point(run); });
  require_confined(run.r.confinement, sample_.params());
  World& world = sample_.world();
  EndLayers grips = grip_end_layers(sample_, params_.grip_depth * params_.grain.size);
  grip_[0] = std::move(grips.layer[0]), grip_[1] = std::move(grips.layer[1]);
  grip_layers_[0] = grips.layers[0], grip_layers_[1] = grips.layers[1];
  if (!params_.bag) sample_.release_confinement();
  ref_.take(sample_);
  world.start_energy_balance();
  layer_heights_ = layer_heights(ref_.position, grips.spacing);
  const std::vector<Vec3>& x = world.bodies().position;
  ref_separation_ = mean_coordinate(grip_[1], x, 2) - mean_coordinate(grip_[0], x, 2);
  // The gauge: from the bottom grip's highest grain to the top grip's lowest (their inner layers).
  double inner_bottom = -HUGE_VAL, inner_top = HUGE_VAL;
  for (BodyId b : grip_[0]) inner_bottom = std::max(inner_bottom, x[b].z());
  for (BodyId b : grip_[1]) inner_top = std::min(inner_top, x[b].z());
  gauge_ = inner_top - inner_bottom;
  run.at.pulling = true;
  record(run);
  take_due_snapshots(run);
  run.at.first = world.steps();
}

TensionResult CrystalTension::run(ResultSink& sink, const CheckpointSource* resume) {
  const auto start = std::chrono::steady_clock::now();
  TensionResult r;
  Position at;
  if (resume) restore(*resume, at, r);
  World& world = sample_.world();
  Run run{sink, r, at, params_.snapshot_strains};
  std::sort(run.snapshot_strains.begin(), run.snapshot_strains.end());
  run.strain_per_row = params_.max_strain / params_.curve_points;
  const double c = crystal_wave_speed(params_);
  run.speed = params_.rate_number * c;
  const double gap_estimate = tension_layers(params_).gap;  // as the dry run has it, resumed or not
  run.confinement_steps = expected_confinement_steps(params_);
  run.tension_steps = std::max(1.0, tension_steps_expected(params_, gap_estimate));
  run.share = run.confinement_steps / (run.confinement_steps + run.tension_steps);
  if (!at.pulling) confine_and_grip(run);
  run.ramp_time = 10 * gauge_ / c;
  const double dt = world.settings().time_step, eps = 1e-12 * std::max(1.0, params_.max_strain);
  Bodies& bodies = world.bodies();
  const double area = sample_.cross_section();
  // The grips' strain, once per step (grains move only in the step).
  for (double strain = strain_now(); strain < params_.max_strain - eps && !r.apart;) {
    {
      StageTimer control(world.stage_times().control);
      const double t = double(world.steps() - at.first) * dt;
      const double remaining = (params_.max_strain - strain) * gauge_ / run.speed;
      const double v = run.speed * platen_speed_fraction(t, run.ramp_time, remaining, false);
      for (BodyId b : grip_[1]) bodies.velocity[b] = Vec3(0, 0, v);
    }
    sample_.step(at.first);
    StageTimer recording(world.stage_times().record);
    strain = strain_now();
    const double top = -grip_force(1) / area, bottom = grip_force(0) / area;
    if (top > at.peak.stress) at.peak = TensionPeak{top, strain, world.steps() - at.first};
    if (!tension_apart(at.peak, strain, top, bottom))
      at.quiet_from = -1;
    else if (at.quiet_from < 0)
      at.quiet_from = strain;
    r.apart = at.quiet_from >= 0 && strain - at.quiet_from >= at.peak.strain;
    take_due_snapshots(run);
    if (strain >= at.row_strain + run.strain_per_row) record(run);
    const double fraction = double(world.steps() - at.first) / run.tension_steps;
    if (!sink.progress(run.share + (1 - run.share) * std::min(0.99, fraction))) throw Cancelled();
    if (strain < params_.max_strain - eps && !r.apart) safe_point(run);
  }
  for (BodyId b : grip_[1]) bodies.velocity[b].setZero();
  if (at.row_step != world.steps()) record(run);
  sink.progress(1.0);

  r.peak = at.peak;
  r.failure = failure_plane();
  r.gauge = gauge_;
  r.cross_section = sample_.cross_section();
  r.speed = run.speed;
  r.grip_grains[0] = grip_[0].size(), r.grip_grains[1] = grip_[1].size();
  r.grip_layers[0] = grip_layers_[0], r.grip_layers[1] = grip_layers_[1];
  r.layers = layer_heights_.size();
  r.tension_steps = world.steps() - at.first;
  r.run = world.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return r;
}

template <class Archive, class Self, class At, class Result>
void CrystalTension::state(Archive& a, Self& self, At& at, Result& r) {
  a.section("crystal_tension");
  a.value(at);
  a.value(r.confinement);
  a.values(r.curve);
  snapshot_marks(a, r.snapshots);
  a.values(self.ref_.position);
  a.values(self.ref_.orientation);
  a.values(self.ref_.interfaces);
  a.values(self.grip_[0]);
  a.values(self.grip_[1]);
  a.values(self.layer_heights_);
  a.value(self.grip_layers_);
  a.value(self.ref_separation_), a.value(self.gauge_);
}

void CrystalTension::save(CheckpointWriter& out, const Position& at, const TensionResult& r) const {
  sample_.save(out);
  state(out, *this, at, r);
}

void CrystalTension::restore(const CheckpointSource& checkpoint, Position& at, TensionResult& r) {
  CheckpointReader in(checkpoint);
  sample_.restore(in);
  state(in, *this, at, r);
  in.finish();
}

}  // namespace granulab
