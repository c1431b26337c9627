#include "engine/experiments/crystal_compression/crystal_compression.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/analysis/grain_kinematics.h"

namespace granulab {

namespace {

double mean_coordinate(const std::vector<BodyId>& bodies, const std::vector<Vec3>& x, int axis) {
  double s = 0;
  for (BodyId b : bodies) s += x[b][axis];
  return bodies.empty() ? 0 : s / bodies.size();
}

// Strains at which curve rows are recorded: a quarter of the rows over the first 2.5 % of the run,
// where the crystal goes from elastic to its first yield at strains of order 10 p0 / E, and the rest
// evenly over the whole run.
std::vector<double> curve_strains(double max_strain, int points) {
  std::vector<double> at;
  const int early = std::max(1, points / 4), late = std::max(1, points - early);
  for (int k = 1; k <= early; ++k) at.push_back(0.025 * max_strain * k / early);
  for (int k = 1; k <= late; ++k) at.push_back(max_strain * k / late);
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

}  // namespace

const std::vector<CurveColumn>& CrystalRow::columns() {
  static const std::vector<CurveColumn> c = {
      {"strain", "-", "axial strain: platen approach / initial length"},
      {"stress_top", "Pa", "top platen force / initial cross-section, compressive positive"},
      {"stress_bottom", "Pa", "bottom platen force / initial cross-section, compressive positive"},
      {"deviator", "Pa", "mean of the two platen stresses - p0"},
      {"lateral_strain_x", "-", "change of width / width, extension positive"},
      {"lateral_strain_y", "-", "change of thickness / thickness, extension positive"},
      {"lateral_stress", "Pa", "mean lateral stress the packing carries (virial)"},
      {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
      {"contacts", "-", "sphere pairs in contact", 0},
      {"sliding_contacts", "-", "of which at the Coulomb limit", 0},
      {"segment", "-", "loading.program segment the row belongs to (0 without a program)", 0},
  };
  return c;
}

std::vector<double> CrystalRow::values() const {
  return {strain,           stress_top,           stress_bottom,
          deviator,         lateral_strain_x,     lateral_strain_y,
          lateral_stress,   kinetic_elastic_ratio, double(contacts),
          double(sliding_contacts), double(segment)};
}

std::pair<double, double> first_yield_peak(const std::vector<CrystalRow>& curve, double p0, double drop) {
  double best = 0, at = 0;
  for (const CrystalRow& row : curve) {
    if (best < 0.1 * p0 && row.deviator < 0.1 * p0) continue;  // still in the noise around zero
    if (row.deviator > best) best = row.deviator, at = row.strain;
    else if (row.deviator < best - drop * best) break;
  }
  return {at, best};
}

double quasi_static_rate_number(double confining_pressure, double youngs_modulus) {
  return std::clamp(confining_pressure / youngs_modulus, 1e-8, 0.1);  // the field's allowed range
}

namespace {
CrystalParams with_rate(CrystalParams p) {
  if (!(p.rate_number > 0)) p.rate_number = quasi_static_rate_number(p.confining_pressure, p.material.youngs_modulus);
  return p;
}
}  // namespace

CrystalCompression::CrystalCompression(const CrystalParams& params) : params_(with_rate(params)), sample_(params_) {}

CrystalRow CrystalCompression::measure(double strain) const {
  CrystalRow row;
  const World& world = sample_.world();
  const auto& x = world.bodies().position;
  row.strain = strain;
  row.stress_top = sample_.axial_stress(sample_.top_wall());
  row.stress_bottom = sample_.axial_stress(sample_.bottom_wall());
  row.deviator = (row.stress_top + row.stress_bottom) / 2 - params_.confining_pressure;
  const double width = mean_coordinate(sample_.side(1), x, 0) - mean_coordinate(sample_.side(0), x, 0);
  const double thickness = mean_coordinate(sample_.side(3), x, 1) - mean_coordinate(sample_.side(2), x, 1);
  row.lateral_strain_x = ref_width_ > 0 ? width / ref_width_ - 1 : 0;
  row.lateral_strain_y = ref_thickness_ > 0 ? thickness / ref_thickness_ - 1 : 0;
  const auto [sx, sy] = sample_.lateral_stresses();
  row.lateral_stress = (sx + sy) / 2;
  row.kinetic_elastic_ratio = sample_.kinetic_elastic_ratio();
  row.contacts = world.contact_stats().contacts;
  row.sliding_contacts = world.contact_stats().sliding;
  return row;
}

double CrystalCompression::deviator() const {
  return (sample_.axial_stress(sample_.top_wall()) + sample_.axial_stress(sample_.bottom_wall())) / 2 -
         params_.confining_pressure;
}

GrainSnapshot CrystalCompression::snapshot(double strain) const {
  const World& world = sample_.world();
  const std::vector<GrainId>& ids = sample_.grain_ids();
  const Bodies& b = world.bodies();
  GrainSnapshot s;
  s.strain = strain;
  s.step = world.steps();
  s.id = ids;
  s.position = b.position;
  s.orientation = b.orientation;
  s.displacement.resize(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) s.displacement[i] = b.position[i] - ref_position_[i];
  s.penetration = world.overlap_sums();
  double mean = 0;
  for (double d : s.penetration) mean += d;
  mean /= s.penetration.size();
  for (double d : s.penetration) s.penetration_ratio.push_back(mean > 0 ? d / mean : 0);
  for (const LocalStrain& e : local_strains(ref_position_, b.position, interfaces_)) {
    s.max_shear_strain.push_back(e.max_shear);
    s.equivalent_strain.push_back(e.equivalent);
  }
  for (const auto& [p, q] : interfaces_) s.interfaces.push_back({ids[p], ids[q]});
  s.sliding = interface_sliding(ref_position_, ref_orientation_, b.position, b.orientation, interfaces_);
  return s;
}

void CrystalCompression::take_reference() {
  const Bodies& b = sample_.world().bodies();
  ref_position_ = b.position;
  ref_orientation_ = b.orientation;
  interfaces_ = neighbour_pairs(ref_position_, 1.1 * params_.grain.size / std::sqrt(2.0));
  ref_width_ = mean_coordinate(sample_.side(1), ref_position_, 0) - mean_coordinate(sample_.side(0), ref_position_, 0);
  ref_thickness_ = mean_coordinate(sample_.side(3), ref_position_, 1) - mean_coordinate(sample_.side(2), ref_position_, 1);
  const auto& walls = sample_.world().walls();
  ref_length_ = walls[sample_.top_wall()].point.z() - walls[sample_.bottom_wall()].point.z();
}

// The snapshots are kept as (strain, step) only: the summary lists no more, and the sink has the rest.
std::string CrystalCompression::checkpoint(const Position& at, const CrystalResult& r) const {
  CheckpointWriter out;
  sample_.save(out);
  out.section("crystal_compression");
  out.value(at);
  out.value(r.confinement);
  out.values(r.curve);
  out.values(r.segments);
  out.value(std::uint64_t(r.snapshots.size()));
  for (const GrainSnapshot& s : r.snapshots) out.value(s.strain), out.value(s.step);
  out.values(ref_position_);
  out.values(ref_orientation_);
  out.values(interfaces_);
  out.value(ref_length_), out.value(ref_width_), out.value(ref_thickness_);
  return out.finish();
}

void CrystalCompression::restore(const std::string& checkpoint, Position& at, CrystalResult& r) {
  CheckpointReader in(checkpoint);
  sample_.restore(in);
  in.section("crystal_compression");
  in.value(at);
  in.value(r.confinement);
  in.values(r.curve);
  in.values(r.segments);
  r.snapshots.resize(in.value<std::uint64_t>());
  for (GrainSnapshot& s : r.snapshots) in.value(s.strain), in.value(s.step);
  in.values(ref_position_);
  in.values(ref_orientation_);
  in.values(interfaces_);
  in.value(ref_length_), in.value(ref_width_), in.value(ref_thickness_);
  in.finish();
}

double loading_steps(const CrystalParams& p, double length, bool bound) {
  const double wave_speed = std::sqrt(p.material.youngs_modulus / (p.material.density * p.mass_scaling));
  const double travel = p.program.empty() ? p.max_strain : bound ? travel_bound(p.program) : planned_travel(p.program);
  const double moves = p.program.empty() ? 1 : double(p.program.size());
  // The platen's travel at R c, and about 5 wave transits per segment for its ramps.
  return (travel * length / (p.rate_number * wave_speed) + moves * 5 * length / wave_speed) / crystal_time_step(p) +
         hold_steps(p.program);
}

CrystalResult CrystalCompression::run(ResultSink& sink, const std::string& resume) {
  const auto start = std::chrono::steady_clock::now();
  CrystalResult r;
  Position at;
  if (!resume.empty()) restore(resume, at, r);
  const auto safe_point = [&] {
    if (sink.checkpoint_due()) sink.checkpoint(checkpoint(at, r), r.curve.size(), r.snapshots.size());
  };
  World& world = sample_.world();
  Wall& top = world.walls()[sample_.top_wall()];
  Wall& bottom = world.walls()[sample_.bottom_wall()];

  // Without a program, one compression to max_strain with its rows at curve_strains(); a program's
  // rows come every curve_points-th of its planned travel, every p0 / 20 of deviator change (so that
  // the short elastic unloadings and reloadings have rows enough for their slopes) and at the end of
  // each segment.
  const bool monotonic = params_.program.empty();
  std::vector<LoadSegment> program = params_.program;
  if (monotonic) program.push_back({LoadSegment::Kind::to_strain, params_.max_strain, 0});
  const std::vector<double> record_at = curve_strains(params_.max_strain, params_.curve_points);
  const double travel_per_row =
      (planned_travel(program) > 0 ? planned_travel(program) : params_.max_strain) / params_.curve_points;
  const double deviator_per_row = params_.confining_pressure / 20;
  // Bounds on the rows of a noisy deviator: one per 10 steps, 2 x curve_points per segment.
  constexpr std::uint64_t kMinStepsPerRow = 10, kDeviatorRowsPerPoint = 2;
  std::vector<double> targets = params_.snapshot_strains;
  std::sort(targets.begin(), targets.end());
  auto strain_now = [&] { return 1 - (top.point.z() - bottom.point.z()) / ref_length_; };
  auto take_due_snapshots = [&] {
    while (at.next_snapshot < targets.size() && strain_now() >= targets[at.next_snapshot] - 1e-12) {
      r.snapshots.push_back(snapshot(targets[at.next_snapshot++]));
      sink.snapshot(r.snapshots.size() - 1, r.snapshots.back());
    }
  };
  auto record = [&](double strain) {
    r.curve.push_back(measure(strain));
    r.curve.back().segment = at.segment;
    at.row_step = world.steps();
    sink.curve_row(r.curve.back().values());
  };

  // The progress bar is shared between the phases in proportion to their expected steps, so that an ETA
  // drawn from it holds from the start. Confinement: about 4 of the servo's time constants (20 x 50 contact
  // times each; a 6 x 12 x 3 crystal took 4.4), at most its step limit; loading: loading_steps().
  const double wave_speed = std::sqrt(params_.material.youngs_modulus / (params_.material.density * params_.mass_scaling));
  const double dt = world.settings().time_step;
  constexpr double time_constants = 4;
  const double confinement_steps =
      std::min(double(params_.max_confinement_steps), time_constants * 20 * 50 * sample_.contact_time() / dt);
  const double length = ref_length_ > 0 ? ref_length_ : top.point.z() - bottom.point.z();  // before confinement: about it
  const double compression_steps = loading_steps(params_, length);
  const double share = confinement_steps / (confinement_steps + compression_steps);
  if (!at.compressing) {
    // confine() reports 1 - exp(-steps / time constant): back to time constants, linear in steps.
    const auto confinement_progress = [&](double f) {
      return sink.progress(share * std::min(1.0, -std::log(std::max(1e-12, 1 - f)) / time_constants));
    };
    r.confinement = granulab::confine(sample_, confinement_progress, nullptr, &at.confinement, safe_point);
    if (params_.fixed_forces) sample_.fix_confining_forces();
    // Reference state for strains, displacements and lateral strains.
    take_reference();
    at.compressing = true;
    record(0);
    take_due_snapshots();
    at.first = world.steps();
  }

  const double speed = params_.rate_number * wave_speed;  // wall approach speed, R = L eps_dot / c
  // The platen accelerates smoothly over ten wave transits of the sample: a sudden start would send a
  // stress wave of amplitude E R (p0 at the default R = p0 / E) through it. Between segments it also
  // slows down (platen_speed_fraction).
  const double ramp_time = 10 * ref_length_ / wave_speed;
  const std::uint64_t first = at.first;
  const double eps = 1e-12 * params_.max_strain;
  while (at.segment < program.size()) {
    const LoadSegment& segment = program[at.segment];
    const bool last = at.segment + 1 == program.size();
    if (!at.segment_begun) {
      at.segment_begun = true;
      at.segment_first = world.steps();
      at.segment_strain = strain_now();
      SegmentRecord begun;
      begun.kind = segment.kind;
      begun.first_row = r.curve.size() - 1;
      if (segment.kind == LoadSegment::Kind::to_deviator) begun.direction = -1;
      if (segment.kind == LoadSegment::Kind::to_strain)
        begun.direction = segment.value > at.segment_strain ? 1 : segment.value < at.segment_strain ? -1 : 0;
      r.segments.push_back(begun);
    }
    SegmentRecord& current = r.segments.back();
    const auto done = [&] {
      if (monotonic) return at.next_row >= record_at.size();
      switch (segment.kind) {
        case LoadSegment::Kind::to_strain:
          return current.direction > 0   ? strain_now() >= segment.value - eps
                 : current.direction < 0 ? strain_now() <= segment.value + eps
                                         : true;
        // ... or once the platen has let go: nothing is left to release (with fixed forces the deviator is
        // the platens' own stress, which cannot fall below 0).
        case LoadSegment::Kind::to_deviator: return deviator() <= segment.value || top.contacts == 0;
        case LoadSegment::Kind::hold: return world.steps() - at.segment_first >= segment.steps;
      }
      return true;
    };
    while (!done()) {
      // The top platen moves, the bottom one is fixed, as in a test machine: the stress wave then
      // crosses the sample, so top and bottom forces agree only when the loading is quasi-static.
      {
        StageTimer c(world.stage_times().control);
        const double t = (world.steps() - at.segment_first) * dt;
        const double remaining = segment.kind == LoadSegment::Kind::to_strain
                                     ? std::abs(segment.value - strain_now()) * ref_length_ / speed
                                     : ramp_time;  // where a release to a deviator ends is not known
        const bool slow_down = !last && segment.kind == LoadSegment::Kind::to_strain;
        top.velocity = top.normal * (current.direction * speed *
                                     (current.direction ? platen_speed_fraction(t, ramp_time, remaining, slow_down) : 0.0));
      }
      world.step();
      if ((world.steps() - first) % params_.membrane_interval == 0) {
        {
          StageTimer c(world.stage_times().control);
          sample_.check_finite();
        }
        sample_.update_membrane();
      }
      StageTimer recording(world.stage_times().record);
      take_due_snapshots();
      const double strain = strain_now();
      if (monotonic) {
        const bool row_due = strain >= record_at[at.next_row] - 1e-12 * params_.max_strain;
        if (row_due) {
          while (at.next_row < record_at.size() && strain >= record_at[at.next_row] - 1e-12 * params_.max_strain)
            ++at.next_row;
          record(strain);
        }
      } else {
        const double travel = at.segment_travel + std::abs(strain - at.segment_strain);
        const bool travel_due = travel >= at.row_travel + travel_per_row;
        const bool deviator_due = std::abs(deviator() - r.curve.back().deviator) >= deviator_per_row &&
                                  world.steps() >= at.row_step + kMinStepsPerRow &&
                                  at.segment_rows < kDeviatorRowsPerPoint * std::uint64_t(params_.curve_points);
        if (travel_due || deviator_due) {
          at.segment_rows += !travel_due;
          record(strain), at.row_travel = travel;
        }
        if (segment.kind == LoadSegment::Kind::to_deviator && strain < -0.05)
          throw std::runtime_error("loading.program[" + std::to_string(at.segment) + "]: the deviator was still " +
                                   std::to_string(deviator()) + " Pa, above the target " + std::to_string(segment.value) +
                                   " Pa, when the platen had released the sample to a strain of -0.05");
      }
      // Every step (milliseconds to a second on a crystal; the sink's calls cost a clock read): a cancel or
      // a shutdown stops the run at once, and a checkpoint may be taken.
      const double fraction = monotonic ? std::min(1.0, std::max(0.0, strain) / params_.max_strain)
                                        : std::min(0.99, (world.steps() - first) / compression_steps);
      if (!sink.progress(share + (1 - share) * fraction)) throw Cancelled();
      if (!done()) safe_point();
    }
    if (!monotonic && at.row_step != world.steps())
      record(strain_now()), at.row_travel = at.segment_travel + std::abs(strain_now() - at.segment_strain);
    current.last_row = r.curve.size() - 1;
    current.steps = world.steps() - at.segment_first;
    at.segment_travel += std::abs(strain_now() - at.segment_strain);
    at.segment_begun = false;
    at.segment_rows = 0;
    ++at.segment;
  }
  sink.progress(1.0);
  top.velocity.setZero();

  r.prestrain = hydrostatic_prestrain(params_.confining_pressure, params_.material.youngs_modulus);
  r.strain_rate = speed / ref_length_;
  r.initial_length = ref_length_;
  r.cross_section = sample_.cross_section();
  r.knocked_out = sample_.lattice().knocked_out;
  r.fixed = sample_.fixed_forces();
  r.compression_steps = world.steps() - first;
  r.run = world.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return r;
}

}  // namespace granulab
