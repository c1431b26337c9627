// Velocity Verlet for rigid bodies, split into kick (momenta from forces) and drift (poses from momenta).
// Rotation uses the symplectic, time-reversible splitting of the free rotor into rotations about the
// principal axes (x/2, y/2, z, y/2, x/2), the scheme of NO_SQUISH (Miller et al. 2002, J. Chem. Phys.
// 116, 8649) written with quaternions. World angular momentum is untouched by a drift, so a free body
// conserves it to rounding; energy error stays bounded (no drift) as for any symplectic scheme.
#pragma once

#include "engine/dynamics/bodies.h"

namespace granulab {

/// v += F/m h and L += tau h for dynamic bodies.
void kick(Bodies& bodies, double h);
/// x += v dt and the free-rotor rotation for dynamic bodies; prescribed bodies move with their
/// given velocity and angular velocity. Refreshes angular_velocity of dynamic bodies.
void drift(Bodies& bodies, double dt);
/// angular_velocity = R I^-1 R^T L for dynamic bodies.
void update_angular_velocity(Bodies& bodies);

}  // namespace granulab
