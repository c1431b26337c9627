// A crystal pulled apart along its axis between grips of its own grains (docs/model.md, "Crystal tension"): the
// cohesive crystals of Karuriya, Simoes & Barthelat (2024) carry tension; one whose interfaces only push does not.
//  1. build and confine: a CrystalSample (any lattice, along loading.axis), confined by the bag and the platens at p0
//     (confinement.h), as every crystal experiment.
//  2. grip and pull: the end layers become rigid grips (end_layers.h), the platens step back, and with
//     loading.confinement "none" the bag goes too. The bottom grip stays; the top one moves along +z at the rate
//     number's speed R c, ramped up over ten wave transits, to loading.max_strain.
// The tensile stress is the contact force the top grip receives against the pull over the cross-section (and the
// bottom grip's along it, the same when quasi-static); the strain the change of the grips' separation over the gauge
// length, the distance between their inner layers (the rigid grips do not stretch).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/crystal/confinement.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/crystal/crystal_snapshot.h"
#include "engine/framework/result_sink.h"

namespace granulab {

struct TensionParams : CrystalSampleParams {
  TensionParams();
  double max_strain = 0.002;   ///< the pull stops here, or earlier once the crystal is apart (-)
  double rate_number = 0;      ///< R = v / c, v the top grip's speed (-); 0: tension_default_rate_number
  bool bag = true;             ///< the bag keeps p0 on the lateral faces while pulling
  double grip_depth = 0.5;     ///< each grip holds the grains within this depth of its end, in grain sizes a (-)
  int curve_points = 200;      ///< curve rows over the pull (-)
  std::vector<double> snapshot_strains{0.0, 0.001, 0.002};  ///< axial strains (-)
};

struct TensionRow {
  double axial_strain;           ///< grip separation change / gap at the start (-)
  double tensile_stress;         ///< contact force the top grip receives against the pull / cross-section (Pa)
  double tensile_stress_bottom;  ///< the bottom grip's along the pull (Pa): equals the top's when quasi-static
  double kinetic_elastic_ratio;
  std::size_t contacts, sliding_contacts;
  EnergyBalance energy;  ///< since the pull began (energy_report.h)

  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

/// Where the crystal came apart: of the gaps between neighbouring layers along z, the one that opened most.
struct FailurePlane {
  int gap = -1;          ///< between layers gap and gap + 1, counted from the bottom grip's (0); -1: none opened
  double height = 0;     ///< that gap's mid-plane above the bottom layer's centres, at the start of the pull (m)
  double opening = 0;    ///< how much it opened (m)
  double share = 0;      ///< its part of all the gaps' opening (-)
  const char* where = "none";  ///< "bottom grip", "top grip" (the gap at a grip's face) or "inside"
};

/// The largest tension, tracked every step (a row's worth of strain can hold a cohesive crystal's whole failure).
struct TensionPeak {
  double stress = 0;  ///< the top grip's tensile stress at its largest, 0 until it pulls (Pa)
  double strain = 0;  ///< the axial strain there (-)
  std::uint64_t step = 0;
};

struct TensionResult {
  std::vector<TensionRow> curve;
  TensionPeak peak;
  bool apart = false;        ///< the pull stopped because the crystal came apart (else at loading.max_strain)
  std::vector<GrainSnapshot> snapshots;
  ConfinementReport confinement;
  RunStats run;
  FailurePlane failure;
  double gauge = 0;          ///< gauge length: between the grips' inner layers when the pull began (m)
  double cross_section = 0;  ///< (m^2)
  double speed = 0;          ///< the top grip's full speed (m/s)
  std::size_t grip_grains[2] = {0, 0};
  int grip_layers[2] = {0, 0};  ///< the layers each grip holds (-)
  std::size_t layers = 0;    ///< layers along z, the grips included (-)
  std::uint64_t tension_steps = 0;
};

/// The layers along z, those the grips leave free, and the gauge length between the grips' inner layers (m), from
/// the lattice alone.
struct TensionLayers {
  std::size_t count = 0, free = 0;
  double gap = 0;
};
TensionLayers tension_layers(const TensionParams& p);
/// The pull's expected steps and at most how many it may take (-).
double tension_steps_expected(const TensionParams& p, double gap);
double tension_steps_bound(const TensionParams& p, double gap);
/// The order of the crystal's tensile strength (Pa), which sets the default pulling rate: p0, or a cohesive law's
/// pull-off force of one sphere pair over the area a pair holds on a face, F_pulloff(d/4) / s^2, if larger.
double tension_stress_scale(const TensionParams& p);
/// R = sigma / (10 E), sigma = tension_stress_scale, within the field's range: the rate when loading.rate_number is 0.
double tension_default_rate_number(const TensionParams& p);
/// Whether a pull at `strain` with top and bottom tensile stresses (Pa) looks apart: the crystal carried tension once
/// (peak.stress > 0), the strain is past twice the peak's, and both grips hold under 1 % of the peak in magnitude. The
/// pull stops once this has held over a further strain equal to the peak's.
bool tension_apart(const TensionPeak& peak, double strain, double top, double bottom);

class CrystalTension {
 public:
  explicit CrystalTension(const TensionParams& params);
  const CrystalSample& sample() const { return sample_; }
  TensionResult run(ResultSink& sink, const CheckpointSource* resume = nullptr);

 private:
  struct Position {
    bool pulling = false;
    TensionPeak peak;
    ConfinementState confinement;
    std::uint64_t first = 0;  ///< world step at which the pull began
    std::size_t next_snapshot = 0;
    double row_strain = 0;    ///< strain of the last row
    double quiet_from = -1;   ///< strain since which tension_apart() has held, -1: it does not
    std::uint64_t row_step = 0;
  };
  struct Run;

  template <class Archive, class Self, class At, class Result>
  static void state(Archive& a, Self& self, At& at, Result& r);
  void save(CheckpointWriter& out, const Position& at, const TensionResult& r) const;
  void restore(const CheckpointSource& checkpoint, Position& at, TensionResult& r);
  void confine_and_grip(Run& run);
  void record(Run& run);
  void take_due_snapshots(Run& run);
  void safe_point(Run& run) const;
  double strain_now() const;
  double grip_force(int grip) const;  ///< contact force the grip's grains receive along z (N)
  TensionRow measure() const;
  FailurePlane failure_plane() const;

  TensionParams params_;
  CrystalSample sample_;
  std::vector<BodyId> grip_[2];  ///< bottom, top
  CrystalReference ref_;
  std::vector<double> layer_heights_;  ///< each layer's centre height at the start of the pull, ascending (m)
  int grip_layers_[2] = {0, 0};
  double ref_separation_ = 0;  ///< the grips' mean separation along z when the pull began (m)
  double gauge_ = 0;           ///< the gauge length (m)
};

}  // namespace granulab
