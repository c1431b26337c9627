// Rigid-body state, one array per field (SoA) so the integrator and the sphere update stream through
// memory. Angular momentum is kept in the world frame; inertia is principal, in the body frame.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

enum class Motion : std::uint8_t {
  dynamic,     ///< integrated from forces and torques
  prescribed,  ///< moves with its given velocity and angular velocity; forces are only measured
};

struct Bodies {
  std::vector<Vec3> position;          ///< centre of mass (m)
  std::vector<Quat> orientation;       ///< body -> world rotation (unit quaternion)
  std::vector<Vec3> velocity;          ///< m/s
  std::vector<Vec3> angular_momentum;  ///< world frame (kg m^2/s), dynamic bodies
  std::vector<Vec3> angular_velocity;  ///< world frame (rad/s): derived for dynamic, given for prescribed
  std::vector<Vec3> force;             ///< N, accumulated each step
  std::vector<Vec3> torque;            ///< N m about the centre of mass, accumulated each step
  std::vector<double> mass;            ///< kg
  std::vector<Vec3> inertia;           ///< principal moments (kg m^2)
  std::vector<Motion> motion;
  /// Size of each body's sphere clump over its template's (-): offsets and radii scale with it (1 for
  /// every body but the imperfect grains of a crystal).
  std::vector<double> scale;

  std::size_t size() const { return position.size(); }

  BodyId add(const Vec3& x, const Quat& q, double m, const Vec3& principal_inertia, Motion mo, double s = 1) {
    position.push_back(x);
    orientation.push_back(q.normalized());
    velocity.push_back(Vec3::Zero());
    angular_momentum.push_back(Vec3::Zero());
    angular_velocity.push_back(Vec3::Zero());
    force.push_back(Vec3::Zero());
    torque.push_back(Vec3::Zero());
    mass.push_back(m);
    inertia.push_back(principal_inertia);
    motion.push_back(mo);
    scale.push_back(s);
    return BodyId(position.size() - 1);
  }

  /// Rotational kinetic energy 1/2 L.I^-1.L of body b (J).
  double rotational_energy(BodyId b) const {
    const Vec3 lb = orientation[b].conjugate() * angular_momentum[b];
    return 0.5 * lb.cwiseProduct(lb).cwiseQuotient(inertia[b]).sum();
  }
  double translational_energy(BodyId b) const { return 0.5 * mass[b] * velocity[b].squaredNorm(); }
};

}  // namespace granulab
