// Simple shear of a crystal slab on a lattice plane along a direction in it (docs/model.md, "Shear"): the slip law
// of one slip system, which compression mixes with others and with the platens' constraint.
//  1. build and confine: a CrystalSample whose z axis is the plane's normal and x axis the shear direction,
//     confined by the bag and the platens at p0 (confinement.h), as every crystal experiment.
//  2. shear: the grains of the first and last layer become rigid platens (rough: they cannot slide on the
//     crystal, as grains glued to a plate). The bottom layer stays; the top layer moves along x at the speed of
//     the rate number, R = v / c, and is free along z under a constant normal load sigma_n x the cross-section
//     (a dead load, so the dilation does not lag a servo), its own grains' mass its inertia. The platens step
//     back; the bag keeps p0 on the four lateral faces. Through a loading program it moves back and forth.
// The shear stress is the contact force the top layer receives along -x over the cross-section; the normal stress
// the contact force along z.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/crystal/confinement.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/crystal/crystal_snapshot.h"
#include "engine/crystal/loading_program.h"
#include "engine/framework/result_sink.h"

namespace granulab {

struct ShearParams : CrystalSampleParams {
  ShearParams();
  Indices plane{1, 1, 1};          ///< the shear plane's Miller indices (HCP: of a1, a2, c); its normal is the axis
  double normal_stress = 0;        ///< sigma_n (Pa); 0: p0
  double max_shear_strain = 0.2;   ///< shearing stops here; with a program, the largest |strain| it may ask for (-)
  double rate_number = 0;          ///< R = v / c, v the top layer's speed (-); 0: p0 / E
  int curve_points = 400;          ///< curve rows over the planned travel (-)
  std::vector<double> snapshot_strains{0.0, 0.05, 0.1, 0.2};  ///< shear strains (-)
  std::vector<LoadSegment> program;  ///< to_strain (shear strain, either sign) and hold; empty: to max_shear_strain
};

struct ShearRow {
  double shear_strain;         ///< top layer travel along x / the gap between the two layers at the start (-)
  double shear_over_normal;    ///< tau / sigma_n (-)
  double dilation;             ///< gap change / gap at the start (-)
  double shear_stress;         ///< tau: contact force on the top layer along -x / cross-section (Pa)
  double normal_stress;        ///< sigma_n: contact force on the top layer along +z / cross-section (Pa)
  double shear_stress_bottom;  ///< the bottom layer's along +x (Pa): equals tau when quasi-static
  double kinetic_elastic_ratio;
  std::size_t contacts, sliding_contacts, segment = 0;
  EnergyBalance energy;  ///< since the shearing began (energy_report.h)

  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

/// Where a snapshot's sliding concentrates: of the interfaces between neighbouring layers sliding more than twice
/// the mean of all interfaces (the paper's Fig. 11 threshold), the gap between two layers holding most of their slip.
struct SlidingPlane {
  double strain = 0;    ///< the snapshot's shear strain (-)
  int gap = -1;         ///< between layers gap and gap + 1, counted from the bottom platen's (0); -1: none slides
  double height = 0;    ///< that gap's mid-plane above the bottom layer's centres, at the start of shearing (m)
  double share = 0;     ///< its part of the selected interfaces' slip (-)
  std::size_t interfaces = 0;  ///< interfaces selected, all gaps (-)
};

struct ShearResult {
  std::vector<ShearRow> curve;
  std::vector<GrainSnapshot> snapshots;
  std::vector<SegmentRecord> segments;
  std::vector<SlidingPlane> sliding_planes;  ///< one per snapshot
  ConfinementReport confinement;
  RunStats run;
  double gap = 0;            ///< between the two layers' centre planes when shearing began (m)
  double cross_section = 0;  ///< (m^2)
  double speed = 0;          ///< the top layer's full speed (m/s)
  std::size_t layer_grains[2] = {0, 0};  ///< grains of the bottom and top layer (-)
  std::size_t layers = 0;                 ///< layers along the normal, the two platens included (-)
  std::uint64_t shear_steps = 0;
};

/// The layers of the slab along the plane's normal (the sites' distinct heights), and the gap between the first and
/// the last (m), from the lattice alone (no world built).
struct SlabLayers {
  std::size_t count = 0;
  double gap = 0;
};
SlabLayers slab_layers(const ShearParams& p);
/// The expected steps of each segment (one without a program) of a slab whose gap is `gap` (m).
std::vector<WorkPhase> shear_phases(const ShearParams& p, double gap, double time_step);
/// At most how many steps the shearing may take (-).
double shear_steps_bound(const ShearParams& p, double gap);
/// The largest tau / sigma_n before the curve first falls `drop` (relative) below its running maximum, once it
/// exceeds a tenth of its largest value; returns the row's index.
std::size_t shear_peak_row(const std::vector<ShearRow>& curve, double drop = 0.02);

/// The dilation angle as the layer moves on from the peak at shear strain `at` (degrees): atan of the slope of the
/// dilation against the shear strain (the gap's change over the travel), fitted over the rows from `at` to `window`
/// further along the travel.
double shear_dilation_angle(const std::vector<ShearRow>& curve, double at, double window);

class CrystalShear {
 public:
  explicit CrystalShear(const ShearParams& params);
  const CrystalSample& sample() const { return sample_; }
  World& world() { return sample_.world(); }
  ShearResult run(ResultSink& sink, const CheckpointSource* resume = nullptr);

 private:
  struct Position {
    bool shearing = false;
    ConfinementState confinement;
    std::uint64_t first = 0;  ///< world step at which shearing began
    std::size_t next_snapshot = 0, segment = 0;
    bool segment_begun = false;
    std::uint64_t segment_first = 0;
    double segment_strain = 0, segment_travel = 0, row_travel = 0;
    std::uint64_t row_step = 0;  ///< world step of the last row
  };
  struct Run;

  template <class Archive, class Self, class At, class Result>
  static void state(Archive& a, Self& self, At& at, Result& r);
  void save(CheckpointWriter& out, const Position& at, const ShearResult& r) const;
  void restore(const CheckpointSource& checkpoint, Position& at, ShearResult& r);
  void confine_and_begin(Run& run);
  void run_segment(Run& run);
  void drive(const Run& run, const LoadSegment& segment, bool last);
  void record(Run& run);
  void take_due_snapshots(Run& run);
  void safe_point(Run& run) const;
  double strain_now() const;
  Vec3 layer_force(int layer) const;  ///< contact force the layer's grains receive (N)
  ShearRow measure() const;
  GrainSnapshot snapshot(double strain) const;
  SlidingPlane sliding_plane(const GrainSnapshot& s) const;

  ShearParams params_;
  CrystalSample sample_;
  std::vector<BodyId> layer_[2];  ///< bottom, top
  double top_mass_ = 0;
  CrystalReference ref_;
  std::vector<double> layer_heights_;  ///< each layer's centre height at the start of shearing, ascending (m)
  Vec3 ref_top_ = Vec3::Zero();
  double ref_gap_ = 0;
};

}  // namespace granulab
