// The world's energy balance (energy_balance.h): the works of the walls, the prescribed grains and the fixed
// per-grain forces, integrated over each step by the trapezoid rule, half with the forces of the step's start
// and half with those of its end, on the displacements of the step's drift.
#include "engine/world/world.h"

namespace granulab {

// Called twice a step between the drift and the last kick, when velocity and angular_velocity are those the
// drift used (v_n+1/2; a prescribed body's given ones) and walls_[].velocity that of their move.
void World::add_half_step_work(double dt) {
  const double h = 0.5 * dt;
  double platen = 0, confinement = 0;
  // A wall's force is what it receives from the spheres, so the work it does on them is -F . dx.
  for (const Wall& w : walls_) platen -= w.force.dot(w.velocity);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Vec3& v = bodies_.velocity[b];
    const Vec3& omega = bodies_.angular_velocity[b];
    if (bodies_.motion[b] == Motion::prescribed) {
      // A prescribed grain does on the others minus the work their contacts do on it.
      platen -= (bodies_.force[b] - applied_force_[b]).dot(v) + (bodies_.torque[b] - applied_torque_[b]).dot(omega);
    } else {
      confinement += applied_force_[b].dot(v) + applied_torque_[b].dot(omega);
    }
  }
  energy_.platen_work += h * platen;
  energy_.confinement_work += h * confinement;
}

void World::start_energy_balance() {
  energy_ = EnergyTotals{};
  energy_.elastic_start = elastic_energy() + stats_.wall_elastic_energy;
  energy_.kinetic_start = kinetic_energy();
}

EnergyBalance World::energy_balance() const {
  EnergyBalance e;
  e.platen_work = energy_.platen_work;
  e.confinement_work = energy_.confinement_work;
  e.elastic_energy = elastic_energy() + stats_.wall_elastic_energy;
  e.friction_dissipation = energy_.friction;
  e.damping_dissipation = energy_.damping;
  e.kinetic_energy = kinetic_energy();
  e.energy_residual = e.platen_work + e.confinement_work - (e.elastic_energy - energy_.elastic_start) -
                      (e.kinetic_energy - energy_.kinetic_start) - e.friction_dissipation - e.damping_dissipation;
  return e;
}

}  // namespace granulab
