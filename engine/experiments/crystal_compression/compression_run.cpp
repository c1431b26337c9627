// CrystalCompression::run, carved: the loading schedule (where rows and snapshots fall), the progress
// estimate shared between confinement and loading, and one pass of the loading loop per program segment
// (the platen's speed, one crystal step, the rows due). Every step is a safe point for a checkpoint.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "engine/experiments/crystal_compression/crystal_compression.h"

namespace granulab {

namespace {

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

// Bounds on the rows of a noisy deviator: one per 10 steps, 2 x curve_points per segment.
constexpr std::uint64_t kMinStepsPerRow = 10, kDeviatorRowsPerPoint = 2;

}  // namespace

// Where the rows fall. Without a program, one compression to max_strain with its rows at curve_strains();
// a program's rows come every curve_points-th of its planned travel, every p0 / 20 of deviator change (so
// that the short elastic unloadings and reloadings have rows enough for their slopes) and at the end of
// each segment. Snapshots at the spec's strains, in order.
struct CrystalCompression::Schedule {
  explicit Schedule(const CrystalParams& p)
      : monotonic(p.program.empty()),
        program(p.program),
        record_at(curve_strains(p.max_strain, p.curve_points)),
        snapshot_strains(p.snapshot_strains),
        deviator_per_row(p.confining_pressure / 20) {
    if (monotonic) program.push_back({LoadSegment::Kind::to_strain, p.max_strain, 0});
    travel_per_row = (planned_travel(program) > 0 ? planned_travel(program) : p.max_strain) / p.curve_points;
    std::sort(snapshot_strains.begin(), snapshot_strains.end());
  }
  bool monotonic;
  std::vector<LoadSegment> program;
  std::vector<double> record_at, snapshot_strains;
  double deviator_per_row, travel_per_row = 0;
};

// The progress bar is shared between the phases in proportion to their expected steps (the cost model the
// dry run gives: expected_confinement_steps, loading_phases), so that an ETA drawn from it holds from the start.
struct CrystalCompression::ProgressShare {
  ProgressShare(const CrystalParams& p, const CrystalSample& sample, double length) {
    const double dt = sample.world().settings().time_step;
    const double confinement_steps = expected_compression_confinement_steps(p);
    for (const WorkPhase& phase : loading_phases(p, length, dt)) compression_steps += phase.steps;
    share = confinement_steps / (confinement_steps + compression_steps);
    confinement_constants = confinement_steps / confinement_progress_steps(sample);
  }
  /// confine()'s fraction back to steps, of the expected ones.
  double confining(double f) const {
    return share * std::min(1.0, -std::log(std::max(1e-12, 1 - f)) / confinement_constants);
  }
  /// Monotonic: the strain reached of max_strain; a program: its steps of the expected ones.
  double loading(bool monotonic, double strain, double max_strain, std::uint64_t steps) const {
    const double fraction =
        monotonic ? std::min(1.0, std::max(0.0, strain) / max_strain) : std::min(0.99, steps / compression_steps);
    return share + (1 - share) * fraction;
  }
  double share = 0, compression_steps = 0, confinement_constants = 1;
};

// One run's moving parts: where the results go, where it stands, and its schedule.
struct CrystalCompression::Run {
  ResultSink& sink;
  CrystalResult& r;
  Position& at;
  Schedule schedule;
  ProgressShare progress;
  double speed = 0;      ///< the platen's full speed, R c (m/s)
  double ramp_time = 0;  ///< its acceleration time, ten wave transits (s)
};

double CrystalCompression::strain_now() const {
  const auto& walls = sample_.world().walls();
  return 1 - (walls[sample_.top_wall()].point.z() - walls[sample_.bottom_wall()].point.z()) / ref_length_;
}

void CrystalCompression::record(double strain, Run& run) {
  run.r.curve.push_back(measure(strain));
  run.r.curve.back().segment = run.at.segment;
  run.at.row_step = sample_.world().steps();
  run.sink.curve_row(run.r.curve.back().values());
}

void CrystalCompression::take_due_snapshots(Run& run) {
  const std::vector<double>& targets = run.schedule.snapshot_strains;
  while (run.at.next_snapshot < targets.size() && strain_now() >= targets[run.at.next_snapshot] - 1e-12) {
    run.r.snapshots.push_back(snapshot(targets[run.at.next_snapshot++]));
    run.sink.snapshot(run.r.snapshots.size() - 1, run.r.snapshots.back());
  }
}

void CrystalCompression::safe_point(Run& run) const {
  if (run.sink.checkpoint_due())
    run.sink.checkpoint([&](CheckpointWriter& out) { save(out, run.at, run.r); }, run.r.curve.size(),
                        run.r.snapshots.size());
}

void CrystalCompression::confine_and_begin(Run& run) {
  const auto progress = [&](double f) { return run.sink.progress(run.progress.confining(f)); };
  if (params_.confinement == Confinement::face_forces) {
    // No confinement phase: the lattice is built at the pre-strain that carries p0, and the fixed forces
    // hold it there.
    sample_.fix_face_forces();
    ConfinementReport& c = run.r.confinement;
    c.converged = true;
    c.stress_top = sample_.axial_stress(sample_.top_wall());
    c.stress_bottom = sample_.axial_stress(sample_.bottom_wall());
    std::tie(c.lateral_stress_x, c.lateral_stress_y) = sample_.lateral_stresses();
  } else {
    // The wrapped bag holds the lattice as built at its pre-strain, as the face forces do, and the phase only checks
    // that it is at rest, the platens servoed to bare contact. Smaller or tilted grains start apart: the taut bag
    // packs them (under the wrapped bag from the start such a crystal did not settle in 200,000 steps, kinetic/elastic
    // 7.8), and the wrapped bag takes over from it for the loading.
    const bool wrapped = bag_wraps(params_), packed_first = bag_packs_first(params_);
    if (wrapped && !packed_first && !run.at.confinement.begun) sample_.wrap_bag();
    run.r.confinement = granulab::confine(sample_, progress, nullptr, &run.at.confinement, [&] { safe_point(run); });
    require_confined(run.r.confinement, sample_.params());
    if (params_.confinement == Confinement::fixed_forces) sample_.fix_confining_forces();
    if (packed_first) sample_.wrap_bag();
  }
  // Reference state for strains, displacements and lateral strains.
  take_reference();
  run.at.compressing = true;
  run.at.drops.threshold = params_.stress_drop_threshold * params_.confining_pressure;
  record(0, run);
  take_due_snapshots(run);
  run.at.first = sample_.world().steps();
}

bool CrystalCompression::segment_done(const Run& run, const LoadSegment& segment) const {
  if (run.schedule.monotonic) return run.at.next_row >= run.schedule.record_at.size();
  const SegmentRecord& current = run.r.segments.back();
  const double eps = 1e-12 * params_.max_strain;
  switch (segment.kind) {
    case LoadSegment::Kind::to_strain:
      return current.direction > 0   ? strain_now() >= segment.value - eps
             : current.direction < 0 ? strain_now() <= segment.value + eps
                                     : true;
    // ... or once the platen has let go: nothing is left to release (with fixed forces the deviator is
    // the platens' own stress, which cannot fall below 0).
    case LoadSegment::Kind::to_deviator:
      return deviator() <= segment.value || sample_.world().walls()[sample_.top_wall()].contacts == 0;
    case LoadSegment::Kind::hold: return sample_.world().steps() - run.at.segment_first >= segment.steps;
  }
  return true;
}

void CrystalCompression::begin_segment(Run& run, const LoadSegment& segment) {
  Position& at = run.at;
  at.segment_begun = true;
  at.segment_first = sample_.world().steps();
  at.segment_strain = strain_now();
  SegmentRecord begun;
  begun.kind = segment.kind;
  begun.first_row = run.r.curve.size() - 1;
  if (segment.kind == LoadSegment::Kind::to_deviator) begun.direction = -1;
  if (segment.kind == LoadSegment::Kind::to_strain)
    begun.direction = segment.value > at.segment_strain ? 1 : segment.value < at.segment_strain ? -1 : 0;
  run.r.segments.push_back(begun);
}

// Where a release to a deviator ends is not known in advance: the strain left is extrapolated from the
// deviator left and the branch's slope between its last two rows (rows come every p0 / 20 of deviator
// change, so this is the local slope). Until the segment has two rows, or when the slope does not point
// to the target, it is taken as far (one ramp at full speed: no slowing down). Without this the platen
// reached the target at full speed and turned at once: the deviator read at the turn lacked the dashpots'
// share, and the reloading's secant from it came out 4 % stiff at p0 / E (docs/results.md).
double CrystalCompression::release_remaining(const Run& run, const LoadSegment& segment) const {
  const std::vector<CrystalRow>& rows = run.r.curve;
  const std::size_t n = rows.size();
  if (n < run.r.segments.back().first_row + 3) return run.ramp_time;
  const CrystalRow &a = rows[n - 2], &b = rows[n - 1];
  const double slope = (b.deviator - a.deviator) / (b.strain - a.strain);  // Pa per unit strain, > 0 releasing
  const double left = deviator() - segment.value;                           // Pa, > 0 until the target
  if (!(slope > 0) || !(left > 0)) return run.ramp_time;
  return std::min(run.ramp_time, left / slope * ref_length_ / run.speed);
}

// The top platen moves, the bottom one is fixed, as in a test machine: the stress wave then crosses the
// sample, so top and bottom forces agree only when the loading is quasi-static.
void CrystalCompression::drive_platen(const Run& run, const LoadSegment& segment, bool last) {
  World& world = sample_.world();
  Wall& top = world.walls()[sample_.top_wall()];
  const int direction = run.r.segments.back().direction;
  StageTimer c(world.stage_times().control);
  const double t = (world.steps() - run.at.segment_first) * world.settings().time_step;
  double remaining = run.ramp_time;  // a hold: the platen stands still anyway
  if (segment.kind == LoadSegment::Kind::to_strain)
    remaining = std::abs(segment.value - strain_now()) * ref_length_ / run.speed;
  else if (segment.kind == LoadSegment::Kind::to_deviator)
    remaining = release_remaining(run, segment);
  const bool slow_down = slows_down_at_end(segment, last);
  top.velocity = top.normal * (direction * run.speed *
                               (direction ? platen_speed_fraction(t, run.ramp_time, remaining, slow_down) : 0.0));
}

void CrystalCompression::record_due_rows(Run& run, const LoadSegment& segment) {
  Position& at = run.at;
  const Schedule& s = run.schedule;
  const double strain = strain_now();
  if (s.monotonic) {
    const double eps = 1e-12 * params_.max_strain;
    if (strain >= s.record_at[at.next_row] - eps) {
      while (at.next_row < s.record_at.size() && strain >= s.record_at[at.next_row] - eps) ++at.next_row;
      record(strain, run);
    }
    return;
  }
  const double travel = at.segment_travel + std::abs(strain - at.segment_strain);
  const bool travel_due = travel >= at.row_travel + s.travel_per_row;
  const bool deviator_due = std::abs(deviator() - run.r.curve.back().deviator) >= s.deviator_per_row &&
                            sample_.world().steps() >= at.row_step + kMinStepsPerRow &&
                            at.segment_rows < kDeviatorRowsPerPoint * std::uint64_t(params_.curve_points);
  if (travel_due || deviator_due) {
    at.segment_rows += !travel_due;
    record(strain, run), at.row_travel = travel;
  }
  if (segment.kind == LoadSegment::Kind::to_deviator && strain < -0.05)
    throw std::runtime_error("loading.program[" + std::to_string(at.segment) + "]: the deviator was still " +
                             std::to_string(deviator()) + " Pa, above the target " + std::to_string(segment.value) +
                             " Pa, when the platen had released the sample to a strain of -0.05");
}

// Stick-slip events (stress_drops.h): the deviator, every step the top platen compresses at more than half its
// speed (the ramps at the start and before a turn relax the stress without any slip: no events there).
void CrystalCompression::track_stress_drops(Run& run) {
  const World& world = sample_.world();
  const Wall& top = world.walls()[sample_.top_wall()];
  const double speed = top.velocity.dot(top.normal);  // along its inward normal: compressing
  StressDrop d;
  if (run.r.segments.back().direction > 0 && speed > 0.5 * run.speed) {
    if (run.at.drops.add({world.steps(), world.time(), strain_now(), deviator()}, d)) run.r.stress_drops.push_back(d);
  } else if (run.at.drops.close(d)) {
    run.r.stress_drops.push_back(d);
  }
}

void CrystalCompression::run_segment(Run& run) {
  Position& at = run.at;
  const LoadSegment& segment = run.schedule.program[at.segment];
  const bool last = at.segment + 1 == run.schedule.program.size();
  World& world = sample_.world();
  if (!at.segment_begun) begin_segment(run, segment);
  while (!segment_done(run, segment)) {
    drive_platen(run, segment, last);
    sample_.step(at.first);
    StageTimer recording(world.stage_times().record);
    track_stress_drops(run);
    take_due_snapshots(run);
    record_due_rows(run, segment);
    // Every step (milliseconds to a second on a crystal; the sink's calls cost a clock read): a cancel or
    // a shutdown stops the run at once, and a checkpoint may be taken.
    const double fraction =
        run.progress.loading(run.schedule.monotonic, strain_now(), params_.max_strain, world.steps() - at.first);
    if (!run.sink.progress(fraction)) throw Cancelled();
    if (!segment_done(run, segment)) safe_point(run);
  }
  if (!run.schedule.monotonic && at.row_step != world.steps())
    record(strain_now(), run), at.row_travel = at.segment_travel + std::abs(strain_now() - at.segment_strain);
  if (StressDrop d; at.drops.close(d)) run.r.stress_drops.push_back(d);
  SegmentRecord& current = run.r.segments.back();
  current.last_row = run.r.curve.size() - 1;
  current.steps = world.steps() - at.segment_first;
  at.segment_travel += std::abs(strain_now() - at.segment_strain);
  at.segment_begun = false;
  at.segment_rows = 0;
  ++at.segment;
}

CrystalResult CrystalCompression::run(ResultSink& sink, const CheckpointSource* resume) {
  const auto start = std::chrono::steady_clock::now();
  CrystalResult r;
  Position at;
  if (resume) restore(*resume, at, r);
  World& world = sample_.world();
  const auto& walls = world.walls();
  const double gap = walls[sample_.top_wall()].point.z() - walls[sample_.bottom_wall()].point.z();
  const double length = ref_length_ > 0 ? ref_length_ : gap;  // before confinement: about it
  const double wave_speed = crystal_wave_speed(params_);
  Run run{sink, r, at, Schedule(params_), ProgressShare(params_, sample_, length)};
  run.speed = params_.rate_number * wave_speed;  // wall approach speed, R = L eps_dot / c
  if (!at.compressing) confine_and_begin(run);
  // The platen accelerates smoothly over ten wave transits of the sample: a sudden start would send a
  // stress wave of amplitude E R (1.5 p0 at the default R = 1.5 p0 / E) through it. Between segments, and
  // at the end of a release to a deviator, it also slows down (platen_speed_fraction).
  run.ramp_time = 10 * ref_length_ / wave_speed;
  while (at.segment < run.schedule.program.size()) run_segment(run);
  sink.progress(1.0);
  world.walls()[sample_.top_wall()].velocity.setZero();

  r.prestrain = hydrostatic_prestrain(params_);
  r.strain_rate = run.speed / ref_length_;
  r.initial_length = ref_length_;
  r.cross_section = sample_.cross_section();
  r.knocked_out = sample_.lattice().knocked_out;
  r.fixed = sample_.fixed_forces();
  r.compression_steps = world.steps() - at.first;
  r.run = world.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return r;
}

}  // namespace granulab
