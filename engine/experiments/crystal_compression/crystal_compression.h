// Experiment 2 of the paper (sections 4-6, Figs. 6-12): an FCC crystal of rhombic dodecahedra in the
// off-axis orientation, confined by a vacuum bag at p0 and compressed between two frictional walls
// (docs/model.md, "Crystal lattice", "Confinement", "Compression").
//  1. build and confine: a CrystalSample and confine() (engine/crystal/), shared by crystal experiments.
//  2. load: the top wall moves down at constant speed (the bottom one is fixed), strain rate from the rate number
//     R = L eps_dot / sqrt(E / rho) (rho with mass scaling), to max_strain or through a loading program
//     (loading_program.h); curve rows and snapshots on the way.
// The confinement: the bag wrapped over the sample (the default), the taut bag, or fixed forces (`confinement`,
// CrystalSample).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/analysis/stress_drops.h"
#include "engine/crystal/confinement.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/crystal/crystal_snapshot.h"
#include "engine/crystal/loading_program.h"
#include "engine/framework/result_sink.h"

namespace granulab {

/// How the crystal is held laterally while it is loaded (docs/model.md, "Confinement", "Fixed forces").
enum class Confinement {
  membrane,       ///< the vacuum bag wrapped over the sample: p0 on every exposed face, following it (CrystalSample::wrap_bag)
  fixed_forces,   ///< the taut bag confines it, then its forces are fixed (CrystalSample::fix_confining_forces)
  face_forces,    ///< no bag: the paper's LAMMPS set-up from the lattice as built (CrystalSample::fix_face_forces)
  taut_membrane,  ///< the taut bag (the model until 2026-12-07): p0 on each grain's footprint on the face plane
};

struct CrystalParams : CrystalSampleParams {
  double max_strain = 0.1;                                            ///< compression stops here (-)
  double rate_number = 0;                                             ///< R (-); 0: default_compression_rate_number()
  int curve_points = 400;                                             ///< curve rows after the start (-)
  std::vector<double> snapshot_strains{0.0, 0.01, 0.02, 0.04, 0.08};  ///< axial strains (-)
  std::vector<LoadSegment> program;                                   ///< empty: one compression to max_strain
  Confinement confinement = Confinement::membrane;
  double stress_drop_threshold = 0.02;  ///< the deviator drop a stick-slip event needs, over p0 (-)
};

/// The default rate number of a crystal compression (-), within [1e-8, 0.1]: 1.5 p0 / E, a constant rate whose curve
/// stays within 2 % of one at R = 5e-6 or slower (mean deviator and mean top against bottom over strain windows, first
/// yield), measured at 10, 30 and 60 kPa on N_e = 4 crystals to 3 % and on the reference crystal at N_e = 10 to 2 %;
/// with a loading program, Fig. 1c's cycles (peaks, residual strains, slopes, loop energies) stay within 1.01 %
/// (docs/results.md, "Quasi-static rate").
double default_compression_rate_number(double confining_pressure, double youngs_modulus);

struct CrystalRow {
  double strain;                     ///< wall approach / initial length (-)
  double stress_top, stress_bottom;  ///< wall force / initial cross-section, compressive positive (Pa)
  double deviator;                   ///< mean of the two - p0 (Pa)
  double lateral_strain_x;           ///< change of width / width (extension positive) (-)
  double lateral_strain_y;           ///< change of thickness / thickness (extension positive) (-)
  double lateral_stress;             ///< mean of the two lateral_stresses() (Pa)
  double kinetic_elastic_ratio;      ///< kinetic / elastic energy (-)
  std::size_t contacts;              ///< sphere pairs in contact (-)
  std::size_t sliding_contacts;      ///< of which at the Coulomb limit (-)
  std::size_t segment = 0;           ///< loading program segment (-)
  EnergyBalance energy;              ///< since the loading began (energy_report.h)

  /// The curve's columns (docs/api.md), in the order of values().
  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

struct CrystalResult {
  std::vector<CrystalRow> curve;
  std::vector<GrainSnapshot> snapshots;
  std::vector<SegmentRecord> segments;  ///< one per program segment run (one without a program)
  ConfinementReport confinement;
  FixedForces fixed;                    ///< the fixed confining forces, when loading.confinement asked for them
  RunStats run;                         ///< steps (confinement included), timings, model numbers
  double prestrain = 0;                 ///< eps0 = sqrt2 p0 / E (-)
  double strain_rate = 0;               ///< platen speed / initial length (1/s)
  double initial_length = 0;            ///< platen gap at the end of confinement (m)
  double cross_section = 0;             ///< lattice cross-section normal to z (m^2)
  std::size_t knocked_out = 0;          ///< grains removed (-)
  std::uint64_t compression_steps = 0;  ///< time steps of the compression phase (-)
  std::vector<StressDrop> stress_drops;  ///< the deviator's drops while the platen compressed (stress_drops.h)
};

/// Whether the bag is wrapped over the crystal (docs/model.md, "Confinement"): with `membrane`, on every crystal
/// without knock-outs. The wrapped bag's pressure follows a grain wherever it goes, so a grain beside a hole, pushed
/// in by the pressure on its outer faces, never stops (measured: on the notched 4 x 3 x 8 crystal of the knock-out
/// test, a grain pushed through the hole and out of the sample at step 27,600); a crystal with knock-outs keeps the
/// taut bag, which spans its holes (Fig. 10's hole stays open under it).
bool bag_wraps(const CrystalParams& p);
/// Whether the taut bag packs the crystal before the wrapped bag takes over: smaller or tilted grains start apart.
bool bag_packs_first(const CrystalParams& p);

/// The expected time steps of the confinement phase (-): none with face forces; the criterion's checks alone with
/// the wrapped bag on perfect grains (the lattice as built is at rest under it); the bag's calibration otherwise.
double expected_compression_confinement_steps(const CrystalParams& p);
/// The expected time steps of each loading segment (one without a program) of a sample of `length` (m)
/// stepped by `time_step` (s).
std::vector<WorkPhase> loading_phases(const CrystalParams& p, double length, double time_step);
/// At most how many time steps the loading of a sample of `length` (m) may take (travel_bound()) (-).
double loading_steps_bound(const CrystalParams& p, double length);

/// The first yield peak of a crystal curve: once the deviator exceeds 0.1 p0, the largest deviator
/// before it first falls `drop` (relative) below its running maximum. Returns {strain (-), deviator (Pa)};
/// {0, 0} if the deviator never reaches 0.1 p0.
std::pair<double, double> first_yield_peak(const std::vector<CrystalRow>& curve, double p0, double drop = 0.02);

class CrystalCompression {
 public:
  explicit CrystalCompression(const CrystalParams& params);

  World& world() { return sample_.world(); }
  const CrystalSample& sample() const { return sample_; }
  const CrystalLattice& lattice() const { return sample_.lattice(); }
  const MembraneStats& membrane_stats() const { return sample_.membrane_stats(); }
  const std::vector<GrainId>& grain_ids() const { return sample_.grain_ids(); }
  std::pair<double, double> lateral_stresses() const { return sample_.lateral_stresses(); }

  /// The confinement phase alone (normally called by run()).
  ConfinementReport confine(const ProgressFn& progress = nullptr) { return granulab::confine(sample_, progress); }
  /// Confines, compresses, records: each curve row and snapshot goes to `sink` as it is made; the sink
  /// may stop the run (throws Cancelled).
  /// `resume`: a checkpoint this run's sink was given (ResultSink::checkpoint), or none.
  CrystalResult run(ResultSink& sink, const CheckpointSource* resume = nullptr);
  CrystalResult run() {
    ResultSink none;
    return run(none);
  }

 private:
  /// Where the run stands between two steps, beyond the sample: what a checkpoint holds.
  struct Position {
    bool compressing = false;  ///< false: still confining
    ConfinementState confinement;
    std::uint64_t first = 0;  ///< world step at which the compression began
    std::size_t next_row = 0, next_snapshot = 0;
    // The loading program: the segment running, since when, from which strain, and the platen's
    // travel (the strain it moved over in all, either way) at the segment's start and at the last row.
    std::size_t segment = 0;
    bool segment_begun = false;
    std::uint64_t segment_first = 0;
    double segment_strain = 0, segment_travel = 0, row_travel = 0;
    std::uint64_t row_step = 0;      ///< world step of the last row
    std::uint64_t segment_rows = 0;  ///< rows the deviator rule added in this segment
    StressDropTracker drops;         ///< the stick-slip detector between steps
  };
  struct Schedule;       // where rows and snapshots fall (compression_run.cpp)
  struct ProgressShare;  // the progress bar shared between confinement and loading
  struct Run;            // one run's sink, result, position, schedule and platen speeds

  /// save and restore's one list of what a checkpoint holds beyond the sample (as World::state).
  template <class Archive, class Self, class At, class Result>
  static void state(Archive& a, Self& self, At& at, Result& r);
  void save(CheckpointWriter& out, const Position& at, const CrystalResult& r) const;
  void restore(const CheckpointSource& checkpoint, Position& at, CrystalResult& r);
  // The run, carved (compression_run.cpp).
  void confine_and_begin(Run& run);
  void begin_segment(Run& run, const LoadSegment& segment);
  bool segment_done(const Run& run, const LoadSegment& segment) const;
  void drive_platen(const Run& run, const LoadSegment& segment, bool last);
  /// A release to a deviator: the time (s at full speed) left until it gets there, for the slowing down.
  double release_remaining(const Run& run, const LoadSegment& segment) const;
  void record_due_rows(Run& run, const LoadSegment& segment);
  void track_stress_drops(Run& run);
  void run_segment(Run& run);
  void record(double strain, Run& run);
  void take_due_snapshots(Run& run);
  void safe_point(Run& run) const;
  /// Platen approach since the reference state / its length (-).
  double strain_now() const;
  void take_reference();
  CrystalRow measure(double strain) const;
  /// The deviator from the two platens alone (Pa): cheap enough for every step.
  double deviator() const;
  GrainSnapshot snapshot(double strain) const;

  CrystalParams params_;
  CrystalSample sample_;
  // Reference state (end of confinement).
  CrystalReference ref_;
  double ref_length_ = 0, ref_width_ = 0, ref_thickness_ = 0;
};

}  // namespace granulab
