// The elastic tensor of a confined crystal (docs/model.md, "Crystal stiffness"): small homogeneous strains imposed
// on its boundary grains while the interior relaxes, the stresses from the contact forces.
//  1. build and confine: a CrystalSample at p0 (confinement.h), as every crystal experiment; the platens step back.
//  2. affine: every grain moves with the imposed strain u = eps (x - x_c) (no grain relaxes), for each of the six
//     Voigt components to +delta, to -delta and back to zero, each reached over a smooth ramp of a few steps (the
//     tangential springs load with the motion, as they would in a run, rather than being teleported unloaded).
//  3. relaxed: the grains short of a full set of face neighbours (the sample's surface) follow the imposed strain;
//     the interior is free and relaxes, each state held until the interior's stress stops changing.
// Each set runs twice, measured the second time. After confinement some contacts are at the Coulomb limit or barely
// touch; the first small strains slide or reopen them once (they lose their tangential history), which shifted the
// states' stresses by up to 9 % of the response (measured), and not on the second pass.
// The stress of a state is the Love-Weber average over the interior grains, sigma = -(1/V) sum (l (x) f) over their
// contacts (a contact with a boundary grain counts half), tension positive; V their lattice cells. Each column of C
// is (sigma(+delta) - sigma(-delta)) / (2 delta): central differences, so the pre-stress p0 and any quadratic term
// drop out.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/analysis/elastic_tensor.h"
#include "engine/crystal/affine_stiffness.h"
#include "engine/crystal/confinement.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/framework/result_sink.h"

namespace granulab {

struct StiffnessParams : CrystalSampleParams {
  StiffnessParams();
  double strain_amplitude = 0;    ///< delta (-); 0: eps0 / 4, which keeps every face closed and stuck
  double ramp_transits = 10;      ///< a relaxed state's ramp, in wave transits L / c of the sample's largest size (-)
  int affine_ramp_steps = 10;     ///< an affine state's ramp (-): no grain is free, so no inertia to wait for
  double relax_tolerance = 1e-3;  ///< the interior stress's change between checks over C11 delta, at most (-)
  int relax_checks = 3;           ///< consecutive checks, 4 transits apart, meeting it (-)
  double max_relax_transits = 400;  ///< a state's hold is cut here (in L / c), reported as not converged (-)
};

/// The six Voigt strains (xx, yy, zz, yz, xz, xy) each to +delta, -delta and 0: the states, in order, after the
/// reference (index 0 of each set).
constexpr int kStiffnessStates = 18;

struct StiffnessRow {
  int set = 0;                ///< 0 affine, 1 relaxed
  int state = 0;              ///< 0 the reference, then 1..18: component (state - 1) / 3 + 1 to +delta, -delta, 0
  int component = 0;          ///< the Voigt component strained (1..6), 0 for the reference
  double imposed_strain = 0;  ///< its value (-; shear components engineering)
  double stress[6] = {0, 0, 0, 0, 0, 0};  ///< the interior's stress less the set's reference, lab frame (Pa)
  double response = 0;        ///< stress[component - 1]: the strained component's stress change (Pa)
  double relax_steps = 0;     ///< steps held before it was measured (-)
  bool converged = true;      ///< the hold met the tolerance (affine states: always)
  double kinetic_elastic_ratio = 0;
  std::size_t contacts = 0, sliding_contacts = 0;

  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

struct StiffnessResult {
  std::vector<StiffnessRow> curve;
  ConfinementReport confinement;
  RunStats run;
  double amplitude = 0;            ///< delta (-)
  double reference_stress[2][6] = {};  ///< each set's reference state, lab frame, tension positive (Pa)
  std::size_t boundary_grains = 0, interior_grains = 0;
  double interior_volume = 0;      ///< (m^3)
  double sample_size = 0;          ///< the sample's largest extent L (m)
  std::uint64_t stiffness_steps = 0;
};

/// delta's default (-): eps0 / 4, at most 1e-3.
double default_strain_amplitude(const CrystalSampleParams& p);
/// Per site of `lattice` (the sample's, as built), 1 when it has a neighbour across every face of its grain: the
/// interior, whose stress is measured and which relaxes.
std::vector<std::uint8_t> interior_sites(const CrystalSampleParams& p, const CrystalLattice& lattice);

/// The tensors of a run's rows (lab frame, Pa): column k from the states k to +delta and -delta of `set`.
Voigt stiffness_of(const std::vector<StiffnessRow>& rows, int set, double amplitude);
/// |sigma(+) + sigma(-) - 2 sigma(0)| / |sigma(+) - sigma(-)|, the largest over the components of `set` (-): 0 when
/// linear.
double stiffness_nonlinearity(const std::vector<StiffnessRow>& rows, int set);
/// |sigma back at zero| / |sigma(+) - sigma(-)|, the largest over the components (-): 0 when reversible.
double stiffness_hysteresis(const std::vector<StiffnessRow>& rows, int set);

/// The sample's largest extent (m) and the steps of the two sets' ramps and holds, expected and at most.
struct StiffnessSchedule {
  double size = 0, transit_steps = 0, ramp_steps = 0, check_steps = 0, expected_steps = 0, max_steps = 0;
};
StiffnessSchedule stiffness_schedule(const StiffnessParams& p);

class CrystalStiffness {
 public:
  explicit CrystalStiffness(const StiffnessParams& params);
  const CrystalSample& sample() const { return sample_; }
  StiffnessResult run(ResultSink& sink, const CheckpointSource* resume = nullptr);

 private:
  struct Position {
    bool begun = false;
    ConfinementState confinement;
    std::uint64_t first = 0;        ///< world step at which the probing began
    int pass = 0, state = 0;        ///< what is being reached: pass 0 conditions affine, 1 measures it, 2 and 3 relaxed
    bool ramping = true;
    std::uint64_t stage_first = 0;  ///< world step at which its ramp (or hold) began
    double from[6] = {}, to[6] = {};  ///< the imposed Voigt strain at the ramp's start and end (-)
    double last[6] = {};            ///< the stress at the last check of the hold (Pa)
    int good = 0;                   ///< consecutive checks meeting the tolerance
    double scale = 0;               ///< C11 delta from the affine set, what the tolerance is relative to (Pa)
  };
  struct Run;

  template <class Archive, class Self, class At, class Result>
  static void state(Archive& a, Self& self, At& at, Result& r);
  void save(CheckpointWriter& out, const Position& at, const StiffnessResult& r) const;
  void restore(const CheckpointSource& checkpoint, Position& at, StiffnessResult& r);
  void confine_and_begin(Run& run);
  void begin_set(Run& run);
  void target(Position& at) const;
  void step_state(Run& run);
  void record(Run& run, bool converged);
  void advance(Run& run);
  void safe_point(Run& run) const;
  Mat3 interior_stress() const;

  StiffnessParams params_;
  CrystalSample sample_;
  std::vector<std::uint8_t> interior_;  ///< per body: 1 when it has every face neighbour
  std::vector<Vec3> reference_;         ///< every grain's centre when probing began (m)
  Vec3 centre_ = Vec3::Zero();
  double volume_ = 0;  ///< the interior grains' lattice cells (m^3)
};

}  // namespace granulab
