// Where the energy goes (docs/model.md, "Energy balance"): the work put into the grains since a start, what
// the contacts store and dissipate, the grains' kinetic energy, and what of the work none of these accounts for.
//   W_platen + W_confinement = (E_el - E_el,0) + (K - K_0) + D_friction + D_damping + residual
// The works are integrated by the trapezoid rule over each step's displacements, which is what velocity Verlet's
// kinetic energy follows (dK = (F_n + F_n+1)/2 . dx + dt^2/8m (F_n+1^2 - F_n^2), the last term telescoping),
// and is exact for a linear spring; the losses are summed per contact and step (contact_law.h). The residual
// is therefore the integrator's second-order error plus what the law's slip reset leaves out (small for a
// quasi-static run; measured in tests/engine/validation/energy_balance_test.cpp).
#pragma once

namespace granulab {

struct EnergyBalance {
  double platen_work = 0;           ///< by the walls and the prescribed grains on the others, since the start (J)
  double confinement_work = 0;      ///< by the fixed per-grain forces (the bag, fixed face forces, gravity) (J)
  double elastic_energy = 0;        ///< stored in the sphere-sphere and sphere-wall contacts now (J)
  double friction_dissipation = 0;  ///< lost to sliding since the start (J)
  double damping_dissipation = 0;   ///< taken by the contacts' dashpots and the bodies' local damping since the start (J)
  double kinetic_energy = 0;        ///< of the dynamic grains now, translation and rotation (J)
  double energy_residual = 0;       ///< W_platen + W_confinement - dE_el - dK - D_friction - D_damping (J)
};

/// The running sums a World keeps for its EnergyBalance (checkpointed with it).
struct EnergyTotals {
  double platen_work = 0, confinement_work = 0, friction = 0, damping = 0;  ///< J since the start
  double elastic_start = 0, kinetic_start = 0;                              ///< J at the start
};

}  // namespace granulab
