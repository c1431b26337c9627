// Velocity Verlet for rigid bodies, split into kick (momenta from forces) and drift (poses from momenta).
// Rotation uses the symplectic, time-reversible splitting of the free rotor into rotations about the
// principal axes (x/2, y/2, z, y/2, x/2), the scheme of NO_SQUISH (Miller et al. 2002, J. Chem. Phys.
// 116, 8649) written with quaternions. World angular momentum is untouched by a drift, so a free body
// conserves it to rounding; energy error stays bounded (no drift) as for any symplectic scheme.
#pragma once

#include <vector>

#include "engine/dynamics/bodies.h"

namespace granulab {

/// v += F/m h and L += tau h for dynamic bodies.
void kick(Bodies& bodies, double h);

/// Local (non-viscous) damping of each body as a whole (Cundall's local damping; Yade's NewtonIntegrator.damping):
/// each component of the net force loses a fraction of its magnitude against that component of the velocity,
/// F_c - lambda |F_c| sgn(v_c), and each of the torque against the angular velocity with its own fraction. It takes
/// kinetic energy out where a body accelerates or brakes, and nothing from steady motion under balanced forces.
struct LocalDamping {
  double translational = 0;  ///< lambda (-)
  double rotational = 0;     ///< lambda of the torque (-)
  bool on() const { return translational > 0 || rotational > 0; }
};
/// kick() with local damping; returns the energy the damping took (J, >= 0): - F_d . (v before + v after)/2 h for
/// the force, - tau_d . omega h for the torque (omega as the kick finds it).
double kick(Bodies& bodies, double h, const LocalDamping& damping);
/// x += v dt and the free-rotor rotation for dynamic bodies; prescribed bodies move with their
/// given velocity and angular velocity. Refreshes angular_velocity of dynamic bodies.
void drift(Bodies& bodies, double dt);
/// The velocities a kick of h would give, without giving them: v + F/m h and R I^-1 R^T (L + tau h) for dynamic bodies,
/// the given ones for prescribed bodies (m/s, rad/s; resized to the bodies).
void kicked_velocities(const Bodies& bodies, double h, std::vector<Vec3>& velocity, std::vector<Vec3>& angular_velocity);
/// angular_velocity = R I^-1 R^T L for dynamic bodies.
void update_angular_velocity(Bodies& bodies);

}  // namespace granulab
