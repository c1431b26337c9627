// The energy balance (engine/world/energy_balance.h) as every crystal experiment reports it: the same seven
// curve columns, named once here, and the change of each over a stretch of the curve (a loading segment, a
// load-unload cycle) as a summary group.
#pragma once

#include <vector>

#include "engine/framework/result_sink.h"
#include "engine/framework/summary_writer.h"
#include "engine/world/energy_balance.h"

namespace granulab {

/// platen_work, confinement_work, elastic_energy, friction_dissipation, damping_dissipation, kinetic_energy,
/// energy_residual (J), in the order of energy_values().
const std::vector<CurveColumn>& energy_columns();
/// Appends the balance's values to a curve row's.
void append_energy_values(const EnergyBalance& e, std::vector<double>& row);
/// A group `key` with each quantity's change from `from` to `to` (J), and what share of the work put in
/// (platens plus confinement) went to each destination.
void write_energy_change(SummaryWriter& w, const char* key, const EnergyBalance& from, const EnergyBalance& to);

}  // namespace granulab
