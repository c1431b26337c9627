// Phase 2 of every crystal experiment (docs/model.md, "Confinement"): the vacuum bag pushes the lateral
// faces with p0, both platens are servo-controlled to an axial stress of p0 (CrystalSample::axial_stress:
// with fixed forces, the ends' forces carry p0 and the platens servo to bare contact), until the equilibrium criterion holds (wall
// stresses within `equilibrium_tolerance` of p0 and kinetic energy below `kinetic_tolerance` of the
// elastic energy, at `equilibrium_checks` membrane intervals in a row; cohesive laws measure both against their own
// stress scale when it exceeds p0, see confine()) or max_confinement_steps pass.
// The platens are left at rest.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>

#include "engine/crystal/crystal_sample.h"
#include "engine/framework/result_sink.h"
#include "engine/framework/summary_writer.h"

namespace granulab {

struct ConfinementReport {
  std::uint64_t steps = 0;           ///< time steps taken (-)
  bool converged = false;            ///< the criterion held (false: stopped at max_confinement_steps)
  double stress_top = 0;             ///< axial stress at the top platen at the end (Pa)
  double stress_bottom = 0;          ///< at the bottom platen (Pa)
  double lateral_stress_x = 0;       ///< CrystalSample::lateral_stresses() at the end (Pa)
  double lateral_stress_y = 0;       ///< (Pa)
  double kinetic_elastic_ratio = 0;  ///< at the end (-)
};

/// A confinement that did not reach equilibrium: what follows would load a sample not at rest, and its numbers would
/// look like results (a simple cubic crystal along [1 1 0] whose platens stopped at 19 of 30 kPa reported a first
/// yield of 1.0 p0 at 0 % strain). The job fails with this, the numbers it reached in the message.
struct ConfinementFailed : std::runtime_error {
  ConfinementFailed(const ConfinementReport& r, const CrystalSampleParams& p);
};
/// A time step the damped modes cannot take: the grains' motion (their spins, or their velocities) reverses from step
/// to step at every check, so the confinement would never come to rest (docs/model.md, "Damping velocity"). The job fails with this at once.
struct UnstableTimeStep : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// Throws ConfinementFailed when the report did not converge and ended far from equilibrium: a platen off p0 by more
/// than 5 equilibrium tolerances, or kinetic/elastic above 10 kinetic tolerances (nothing with
/// params.require_equilibrium off). Nearer than that the run goes on, and write_confinement_warning() says so.
void require_confined(const ConfinementReport& r, const CrystalSampleParams& p);

/// Writes the report as the summary group "confinement".
void write_confinement(SummaryWriter& w, const ConfinementReport& r);
/// When the confinement did not converge, a sentence saying so; call inside the "warnings" list.
void write_confinement_warning(SummaryWriter& w, const ConfinementReport& r);

/// Called at each equilibrium check (every membrane_interval steps) with the steps taken so far.
using ConfinementCheck = std::function<void(std::uint64_t steps)>;

/// Where a confinement stands between two checks: with the sample's world, all a resumed one needs.
struct ConfinementState {
  bool begun = false;
  std::uint64_t start = 0;  ///< world step at which it began
  int good = 0;             ///< consecutive checks meeting the criterion
};

/// confine() reports its progress as 1 - exp(-steps / this) (-): twenty servo times, since how long it takes is not
/// known in advance. Who shares a progress bar with it turns the fraction back into steps.
double confinement_progress_steps(const CrystalSample& sample);

/// Confines the sample. `progress` gets a fraction that approaches 1 on the servo's time scale (the
/// length of the phase is not known in advance); returning false stops the run (throws Cancelled).
/// With `state`, continues from it (a restored sample and state resume a checkpointed confinement) and
/// calls `safe_point` after every step but the last: a checkpoint may be taken there.
ConfinementReport confine(CrystalSample& sample, const ProgressFn& progress = nullptr,
                          const ConfinementCheck& on_check = nullptr, ConfinementState* state = nullptr,
                          const std::function<void()>& safe_point = nullptr);

}  // namespace granulab
