#include "engine/framework/energy_report.h"

#include <cmath>

namespace granulab {

const std::vector<CurveColumn>& energy_columns() {
  static const std::vector<CurveColumn> c = {
      {"platen_work", "J", "work the platens did on the grains since loading began"},
      {"confinement_work", "J", "work the confinement (bag or fixed forces) did on the grains since loading began"},
      {"elastic_energy", "J", "energy stored in the contacts (sphere-sphere and sphere-platen) now"},
      {"friction_dissipation", "J", "energy lost to sliding contacts since loading began"},
      {"damping_dissipation", "J",
       "energy taken by the contacts' viscous damping (and the grains' run.local_damping) since loading began"},
      {"kinetic_energy", "J", "kinetic energy of the grains now"},
      {"energy_residual", "J",
       "platen_work + confinement_work - (elastic_energy, kinetic_energy gained since loading began) - the two "
       "dissipations: the balance's error"},
  };
  return c;
}

void append_energy_values(const EnergyBalance& e, std::vector<double>& row) {
  row.insert(row.end(), {e.platen_work, e.confinement_work, e.elastic_energy, e.friction_dissipation,
                         e.damping_dissipation, e.kinetic_energy, e.energy_residual});
}

void write_energy_change(SummaryWriter& w, const char* key, const EnergyBalance& from, const EnergyBalance& to) {
  const double platen = to.platen_work - from.platen_work, confinement = to.confinement_work - from.confinement_work;
  const double elastic = to.elastic_energy - from.elastic_energy, kinetic = to.kinetic_energy - from.kinetic_energy;
  const double friction = to.friction_dissipation - from.friction_dissipation;
  const double damping = to.damping_dissipation - from.damping_dissipation;
  const double residual = to.energy_residual - from.energy_residual;
  w.begin_group(key);
  w.number("platen_work", platen, "J");
  w.number("confinement_work", confinement, "J");
  w.number("elastic_energy", elastic, "J");
  w.number("friction_dissipation", friction, "J");
  w.number("damping_dissipation", damping, "J");
  w.number("kinetic_energy", kinetic, "J");
  w.number("energy_residual", residual, "J");
  // Shares of the work put in; left out when (nearly) none was (a hold).
  const double in = platen + confinement;
  const double scale = std::abs(platen) + std::abs(confinement) + std::abs(elastic) + friction + damping;
  if (std::abs(in) > 1e-3 * scale && scale > 0) {
    w.number("elastic_share", elastic / in, "-");
    w.number("friction_share", friction / in, "-");
    w.number("damping_share", damping / in, "-");
  }
  w.end_group();
}

}  // namespace granulab
