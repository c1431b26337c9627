#include "engine/experiments/crystal_shear/crystal_shear.h"

#include "engine/analysis/curve_peak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "engine/crystal/end_layers.h"
#include "engine/framework/energy_report.h"


namespace granulab {

ShearParams::ShearParams() {
  axis = {1, 1, 1};
  lateral = {1, -1, 0};
  // Six (111) layers (two lattice repeats along [1 1 1]) of 6 x 20 periods: about 4 a x 4 a x 3.5 a.
  grains_x = 6, layers_y = 20, rows_z = 2;
}

const std::vector<CurveColumn>& ShearRow::columns() {
  static const std::vector<CurveColumn> c = [] {
    std::vector<CurveColumn> c = {
      {"shear_strain", "-", "top layer travel along the shear direction / gap between the two layers at the start"},
      {"shear_over_normal", "-", "tau / sigma_n"},
      {"dilation", "-", "change of the gap between the two layers / gap at the start, opening positive"},
      {"shear_stress", "Pa", "tau: contact force the top layer receives against the shear direction / cross-section"},
      {"normal_stress", "Pa", "sigma_n: contact force the top layer receives along the plane's normal / cross-section"},
      {"shear_stress_bottom", "Pa", "the bottom layer's contact force along the shear direction / cross-section"},
      {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
      {"contacts", "-", "sphere pairs in contact", 0},
      {"sliding_contacts", "-", "of which at the Coulomb limit", 0},
      {"segment", "-", "loading.program segment the row belongs to (0 without a program)", 0},
    };
    c.insert(c.end(), energy_columns().begin(), energy_columns().end());  // the end layers are the platens
    return c;
  }();
  return c;
}

std::vector<double> ShearRow::values() const {
  std::vector<double> v = {shear_strain,          shear_over_normal, dilation,
                           shear_stress,          normal_stress,     shear_stress_bottom,
                           kinetic_elastic_ratio, double(contacts),  double(sliding_contacts),
                           double(segment)};
  append_energy_values(energy, v);
  return v;
}

std::size_t shear_peak_row(const std::vector<ShearRow>& curve, double drop) {
  std::vector<double> ratio;
  double largest = 0;
  for (const ShearRow& row : curve) ratio.push_back(std::abs(row.shear_over_normal)), largest = std::max(largest, ratio.back());
  return first_peak(ratio, 0.1 * largest, drop).row;  // below a tenth of the largest: still rising from zero
}

// Forward, not centred: before the peak the gap changes elastically as the load builds.
double shear_dilation_angle(const std::vector<ShearRow>& curve, double at, double window) {
  const double sense = at < 0 ? -1 : 1, from = sense * at;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const ShearRow& row : curve) {
    const double x = sense * row.shear_strain, y = row.dilation;
    if (x < from - 1e-12 || x > from + window) continue;
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double d = n * sxx - sx * sx;
  if (n < 2 || !(std::abs(d) > 0)) return 0;
  return std::atan((n * sxy - sx * sy) / d) * 180 / M_PI;
}

namespace {

ShearParams with_defaults(ShearParams p) {
  if (!(p.rate_number > 0)) p.rate_number = quasi_static_rate_number(p.confining_pressure, p.material.youngs_modulus);
  if (!(p.normal_stress > 0)) p.normal_stress = p.confining_pressure;
  return p;
}

std::vector<LoadSegment> program_of(const ShearParams& p) {
  if (!p.program.empty()) return p.program;
  return {{LoadSegment::Kind::to_strain, p.max_shear_strain, 0}};
}

std::string percent(double strain) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", 100 * strain);
  return text;
}

}  // namespace

SlabLayers slab_layers(const ShearParams& p) {
  std::vector<double> heights;
  for (const LatticeSite& s : sample_lattice(p).sites) heights.push_back(s.position.z());
  std::sort(heights.begin(), heights.end());
  SlabLayers out;
  for (std::size_t k = 0; k < heights.size(); ++k)
    out.count += k == 0 || heights[k] - heights[k - 1] > 1e-9 * p.grain.size;
  if (!heights.empty()) out.gap = heights.back() - heights.front();
  return out;
}

// As a compression segment: its travel at full speed, and half a ramp of ten wave transits (plus three when
// it slows down for the next one).
std::vector<WorkPhase> shear_phases(const ShearParams& p, double gap, double time_step) {
  const ShearParams q = with_defaults(p);
  const double c = crystal_wave_speed(q), speed = q.rate_number * c, ramp = 10 * gap / c;
  const std::vector<LoadSegment> program = program_of(q);
  const std::vector<double> travel = planned_segment_travels(program, 0);
  std::vector<WorkPhase> out;
  for (std::size_t k = 0; k < program.size(); ++k) {
    const LoadSegment& s = program[k];
    if (s.kind == LoadSegment::Kind::hold) {
      out.push_back({"hold " + std::to_string(s.steps) + " steps", double(s.steps)});
      continue;
    }
    const double seconds = travel[k] * gap / speed + ramp * (0.5 + (k + 1 < program.size() ? 3.0 : 0.0));
    out.push_back({"to_shear_strain " + percent(s.value), seconds / time_step});
  }
  return out;
}

double shear_steps_bound(const ShearParams& p, double gap) {
  const ShearParams q = with_defaults(p);
  const std::vector<LoadSegment> program = program_of(q);
  const double c = crystal_wave_speed(q);
  return (travel_bound(program) * gap / (q.rate_number * c) + double(program.size()) * 40 * gap / c) /
             crystal_time_step(q) +
         hold_steps(program);
}

// One run's moving parts: where the results go, where it stands, and its schedule.
struct CrystalShear::Run {
  ResultSink& sink;
  ShearResult& r;
  Position& at;
  std::vector<LoadSegment> program;
  std::vector<double> snapshot_strains;  // ascending |strain|
  double travel_per_row = 0;
  double speed = 0, ramp_time = 0;
  double share = 0, confinement_steps = 0, shear_steps = 1;  // the progress bar's split
};

CrystalShear::CrystalShear(const ShearParams& params) : params_(with_defaults(params)), sample_(params_) {}

double CrystalShear::strain_now() const {
  return (mean_coordinate(layer_[1], sample_.world().bodies().position, 0) - ref_top_.x()) / ref_gap_;
}

Vec3 CrystalShear::layer_force(int layer) const {
  const World& world = sample_.world();
  Vec3 f = Vec3::Zero();
  // Less the bag's share: the contacts alone (the platens have stepped back).
  for (BodyId b : layer_[layer]) f += world.bodies().force[b] - world.external_force()[b];
  return f;
}

ShearRow CrystalShear::measure() const {
  ShearRow row;
  const World& world = sample_.world();
  const double area = sample_.cross_section();
  const Vec3 top = layer_force(1), bottom = layer_force(0);
  row.shear_strain = strain_now();
  row.normal_stress = top.z() / area;
  row.shear_stress = -top.x() / area;
  row.shear_stress_bottom = bottom.x() / area;
  row.shear_over_normal = row.normal_stress > 0 ? row.shear_stress / row.normal_stress : 0;
  row.dilation = (mean_coordinate(layer_[1], world.bodies().position, 2) - ref_top_.z()) / ref_gap_;
  row.kinetic_elastic_ratio = sample_.kinetic_elastic_ratio();
  row.contacts = world.contact_stats().contacts;
  row.sliding_contacts = world.contact_stats().sliding;
  row.energy = world.energy_balance();
  return row;
}

GrainSnapshot CrystalShear::snapshot(double strain) const { return crystal_snapshot(sample_, ref_, strain); }

SlidingPlane CrystalShear::sliding_plane(const GrainSnapshot& s) const {
  SlidingPlane out;
  out.strain = s.strain;
  if (s.sliding.empty() || layer_heights_.size() < 2) return out;
  double mean = 0;
  for (double d : s.sliding) mean += d;
  mean /= double(s.sliding.size());
  std::vector<double> slip(layer_heights_.size() - 1, 0.0);
  double total = 0;
  const double tolerance = 0.25 * (layer_heights_[1] - layer_heights_[0]);
  for (std::size_t k = 0; k < s.sliding.size(); ++k) {
    if (!(s.sliding[k] > 2 * mean)) continue;
    const auto [p, q] = ref_.interfaces[k];
    const double lo = std::min(ref_.position[p].z(), ref_.position[q].z());
    const double hi = std::max(ref_.position[p].z(), ref_.position[q].z());
    if (hi - lo < tolerance) continue;  // within a layer
    const double mid = (lo + hi) / 2;
    const std::size_t gap = std::size_t(
        std::upper_bound(layer_heights_.begin(), layer_heights_.end(), mid) - layer_heights_.begin());
    if (gap == 0 || gap >= layer_heights_.size()) continue;
    slip[gap - 1] += s.sliding[k], total += s.sliding[k], ++out.interfaces;
  }
  if (!(total > 0)) return out;
  const std::size_t best = std::size_t(std::max_element(slip.begin(), slip.end()) - slip.begin());
  out.gap = int(best);
  out.height = (layer_heights_[best] + layer_heights_[best + 1]) / 2 - layer_heights_.front();
  out.share = slip[best] / total;
  return out;
}

void CrystalShear::record(Run& run) {
  run.r.curve.push_back(measure());
  run.r.curve.back().segment = run.at.segment;
  run.at.row_step = sample_.world().steps();
  run.sink.curve_row(run.r.curve.back().values());
}

void CrystalShear::take_due_snapshots(Run& run) {
  const std::vector<double>& targets = run.snapshot_strains;
  while (run.at.next_snapshot < targets.size() && std::abs(strain_now()) >= targets[run.at.next_snapshot] - 1e-12) {
    run.r.snapshots.push_back(snapshot(targets[run.at.next_snapshot++]));
    run.r.sliding_planes.push_back(sliding_plane(run.r.snapshots.back()));
    run.sink.snapshot(run.r.snapshots.size() - 1, run.r.snapshots.back());
  }
}

void CrystalShear::safe_point(Run& run) const {
  if (run.sink.checkpoint_due())
    run.sink.checkpoint([&](CheckpointWriter& out) { save(out, run.at, run.r); }, run.r.curve.size(),
                        run.r.snapshots.size());
}

// After confinement: the end layers become the platens, the walls step back, and the reference is taken.
void CrystalShear::confine_and_begin(Run& run) {
  const auto progress = [&](double f) {
    const double steps = -std::log(std::max(1e-12, 1 - f)) * confinement_progress_steps(sample_);
    return run.sink.progress(run.share * std::min(1.0, steps / run.confinement_steps));
  };
  run.r.confinement = confine(sample_, progress, nullptr, &run.at.confinement, [&] { safe_point(run); });
  require_confined(run.r.confinement, sample_.params());
  World& world = sample_.world();
  Bodies& bodies = world.bodies();
  EndLayers grips = grip_end_layers(sample_);
  layer_[0] = std::move(grips.layer[0]), layer_[1] = std::move(grips.layer[1]);
  for (BodyId b : layer_[1]) top_mass_ += bodies.mass[b];
  ref_.take(sample_);
  world.start_energy_balance();
  layer_heights_ = layer_heights(ref_.position, grips.spacing);
  ref_top_ = Vec3(mean_coordinate(layer_[1], bodies.position, 0), mean_coordinate(layer_[1], bodies.position, 1),
                  mean_coordinate(layer_[1], bodies.position, 2));
  ref_gap_ = ref_top_.z() - mean_coordinate(layer_[0], bodies.position, 2);
  run.at.shearing = true;
  record(run);
  take_due_snapshots(run);
  run.at.first = world.steps();
}

// The top layer: along x at the program's speed (ramped as a compression platen), along z under the dead load.
void CrystalShear::drive(const Run& run, const LoadSegment& segment, bool last) {
  World& world = sample_.world();
  StageTimer c(world.stage_times().control);
  Bodies& bodies = world.bodies();
  const double dt = world.settings().time_step;
  const int direction = run.r.segments.back().direction;
  const double t = (world.steps() - run.at.segment_first) * dt;
  const double remaining = segment.kind == LoadSegment::Kind::to_strain
                               ? std::abs(segment.value - strain_now()) * ref_gap_ / run.speed
                               : run.ramp_time;
  const bool slow_down = !last && segment.kind == LoadSegment::Kind::to_strain;
  const double along =
      direction * run.speed * (direction ? platen_speed_fraction(t, run.ramp_time, remaining, slow_down) : 0.0);
  // Newton for the layer's normal motion (semi-implicit Euler on the last evaluation's forces).
  const double load = params_.normal_stress * sample_.cross_section();
  const double normal = bodies.velocity[layer_[1].front()].z() + dt * (layer_force(1).z() - load) / top_mass_;
  for (BodyId b : layer_[1]) bodies.velocity[b] = Vec3(along, 0, normal);
}

void CrystalShear::run_segment(Run& run) {
  Position& at = run.at;
  const LoadSegment& segment = run.program[at.segment];
  const bool last = at.segment + 1 == run.program.size();
  World& world = sample_.world();
  if (!at.segment_begun) {
    at.segment_begun = true;
    at.segment_first = world.steps();
    at.segment_strain = strain_now();
    SegmentRecord begun;
    begun.kind = segment.kind;
    begun.first_row = run.r.curve.size() - 1;
    if (segment.kind == LoadSegment::Kind::to_strain)
      begun.direction = segment.value > at.segment_strain ? 1 : segment.value < at.segment_strain ? -1 : 0;
    run.r.segments.push_back(begun);
  }
  const auto done = [&] {
    const double eps = 1e-12 * std::max(1.0, std::abs(segment.value));
    const int direction = run.r.segments.back().direction;
    if (segment.kind == LoadSegment::Kind::hold) return world.steps() - at.segment_first >= segment.steps;
    return direction > 0 ? strain_now() >= segment.value - eps : direction < 0 ? strain_now() <= segment.value + eps : true;
  };
  while (!done()) {
    drive(run, segment, last);
    sample_.step(at.first);
    StageTimer recording(world.stage_times().record);
    take_due_snapshots(run);
    const double travel = at.segment_travel + std::abs(strain_now() - at.segment_strain);
    if (travel >= at.row_travel + run.travel_per_row) record(run), at.row_travel = travel;
    const double fraction = std::min(1.0, double(world.steps() - at.first) / run.shear_steps);
    if (!run.sink.progress(run.share + (1 - run.share) * std::min(0.99, fraction))) throw Cancelled();
    if (!done()) safe_point(run);
  }
  if (at.row_step != world.steps()) record(run);  // its last row, unless the loop's last step made it
  at.row_travel = at.segment_travel + std::abs(strain_now() - at.segment_strain);
  SegmentRecord& current = run.r.segments.back();
  current.last_row = run.r.curve.size() - 1;
  current.steps = world.steps() - at.segment_first;
  at.segment_travel += std::abs(strain_now() - at.segment_strain);
  at.segment_begun = false;
  ++at.segment;
}

ShearResult CrystalShear::run(ResultSink& sink, const CheckpointSource* resume) {
  const auto start = std::chrono::steady_clock::now();
  ShearResult r;
  Position at;
  if (resume) restore(*resume, at, r);
  World& world = sample_.world();
  Run run{sink, r, at, program_of(params_), params_.snapshot_strains};
  for (double& s : run.snapshot_strains) s = std::abs(s);
  std::sort(run.snapshot_strains.begin(), run.snapshot_strains.end());
  const double planned = planned_travel(run.program);
  run.travel_per_row = (planned > 0 ? planned : params_.max_shear_strain) / params_.curve_points;
  const double c = crystal_wave_speed(params_);
  run.speed = params_.rate_number * c;
  // The progress bar, shared in proportion to the expected steps of the two phases.
  const double gap_estimate = slab_layers(params_).gap;  // as the dry run has it, resumed or not
  run.confinement_steps = expected_confinement_steps(params_);
  run.shear_steps = 0;
  for (const WorkPhase& p : shear_phases(params_, gap_estimate, world.settings().time_step)) run.shear_steps += p.steps;
  run.shear_steps = std::max(1.0, run.shear_steps);
  run.share = run.confinement_steps / (run.confinement_steps + run.shear_steps);
  if (!at.shearing) confine_and_begin(run);
  run.ramp_time = 10 * ref_gap_ / c;
  while (at.segment < run.program.size()) run_segment(run);
  sink.progress(1.0);
  for (BodyId b : layer_[1]) world.bodies().velocity[b].setZero();

  r.gap = ref_gap_;
  r.cross_section = sample_.cross_section();
  r.speed = run.speed;
  r.layer_grains[0] = layer_[0].size(), r.layer_grains[1] = layer_[1].size();
  r.layers = layer_heights_.size();
  r.shear_steps = world.steps() - at.first;
  r.run = world.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return r;
}

template <class Archive, class Self, class At, class Result>
void CrystalShear::state(Archive& a, Self& self, At& at, Result& r) {
  a.section("crystal_shear");
  a.value(at);
  a.value(r.confinement);
  a.values(r.curve);
  a.values(r.segments);
  snapshot_marks(a, r.snapshots);
  a.values(self.ref_.position);
  a.values(self.ref_.orientation);
  a.values(self.ref_.interfaces);
  a.values(self.layer_[0]);
  a.values(self.layer_[1]);
  a.values(self.layer_heights_);
  a.values(r.sliding_planes);
  a.value(self.top_mass_), a.value(self.ref_top_), a.value(self.ref_gap_);
}

void CrystalShear::save(CheckpointWriter& out, const Position& at, const ShearResult& r) const {
  sample_.save(out);
  state(out, *this, at, r);
}

void CrystalShear::restore(const CheckpointSource& checkpoint, Position& at, ShearResult& r) {
  CheckpointReader in(checkpoint);
  sample_.restore(in);
  state(in, *this, at, r);
  in.finish();
}

}  // namespace granulab
