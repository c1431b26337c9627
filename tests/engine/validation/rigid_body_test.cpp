// Rigid-body integration against closed forms: free asymmetric body (energy and angular momentum),
// uniform rotation about a principal axis, constant force, and a clump resting on a wall.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/dynamics/integrator.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

void verlet_step(Bodies& b, double dt) {  // forces are constant (or zero) in these tests
  kick(b, dt / 2);
  drift(b, dt);
  kick(b, dt / 2);
}

double kinetic_energy(const Bodies& b) { return b.translational_energy(0) + b.rotational_energy(0); }

// Torque-free asymmetric top (I = 1, 2, 3), tumbling near its unstable middle axis. The splitting
// integrator leaves world angular momentum untouched and has no secular energy drift.
TEST(RigidBody, FreeAsymmetricBodyConservesEnergyAndAngularMomentum) {
  Bodies b;
  b.add(Vec3::Zero(), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized())), 2.0, Vec3(1, 2, 3), Motion::dynamic);
  b.angular_momentum[0] = Vec3(0.05, 2.0, 0.1);
  b.velocity[0] = Vec3(0.1, -0.2, 0.3);
  update_angular_velocity(b);
  const Vec3 l0 = b.angular_momentum[0];
  const double e0 = kinetic_energy(b);
  const double dt = 1e-3;  // |omega| dt ~ 1e-3 rad
  double max_energy_error = 0, min_middle_axis_momentum = l0.norm();
  for (int k = 0; k < 100000; ++k) {
    verlet_step(b, dt);
    max_energy_error = std::max(max_energy_error, std::abs(kinetic_energy(b) - e0) / e0);
    const Vec3 lb = b.orientation[0].conjugate() * b.angular_momentum[0];
    min_middle_axis_momentum = std::min(min_middle_axis_momentum, lb.y());
  }
  std::printf("free body: max relative energy error %.3g over 1e5 steps\n", max_energy_error);
  // World angular momentum is never changed by a drift: only rounding.
  EXPECT_LT((b.angular_momentum[0] - l0).norm() / l0.norm(), 1e-14);
  // Energy: the splitting error is O((omega dt)^2) ~ 1e-6 and bounded; measured max 1.6e-7 over 1e5 steps.
  EXPECT_LT(max_energy_error, 1e-6);
  // The body really tumbled (the middle axis is unstable: body-frame L_y flipped sign), so the test
  // exercised all three axes.
  EXPECT_LT(min_middle_axis_momentum, -1.0);
  EXPECT_NEAR(b.orientation[0].norm(), 1.0, 1e-14);
}

// Spin about a principal axis is a steady rotation: angle = omega t, exactly for this splitting.
TEST(RigidBody, SpinAboutPrincipalAxisIsUniform) {
  Bodies b;
  b.add(Vec3::Zero(), Quat::Identity(), 1.0, Vec3(1, 2, 3), Motion::dynamic);
  const double omega = 0.7, dt = 1e-2;
  b.angular_momentum[0] = Vec3(0, 0, 3 * omega);
  const int steps = 1000;
  for (int k = 0; k < steps; ++k) verlet_step(b, dt);
  const Quat expected(Eigen::AngleAxisd(omega * dt * steps, Vec3::UnitZ()));
  EXPECT_NEAR(b.orientation[0].angularDistance(expected), 0, 1e-12);
}

// Velocity Verlet is exact for a constant force: x = x0 + v0 t + F t^2 / 2m.
TEST(RigidBody, ConstantForceGivesParabola) {
  Bodies b;
  const Vec3 x0(1, 2, 3), v0(0.5, -1, 2), f(3, 0, -9);
  const double m = 1.5, dt = 1e-3;
  b.add(x0, Quat::Identity(), m, Vec3(1, 1, 1), Motion::dynamic);
  b.velocity[0] = v0;
  b.force[0] = f;
  const int steps = 5000;
  for (int k = 0; k < steps; ++k) verlet_step(b, dt);
  const double t = steps * dt;
  EXPECT_NEAR((b.position[0] - (x0 + v0 * t + f * t * t / (2 * m))).norm(), 0, 1e-11);
  EXPECT_NEAR((b.velocity[0] - (v0 + f * t / m)).norm(), 0, 1e-11);
}

// A cube clump dropped onto a frictional wall under gravity comes to rest on it, and the wall then
// carries exactly its weight (static equilibrium: the contact forces balance m g).
TEST(RigidBody, ClumpRestingOnWallCarriesItsWeight) {
  const GrainTemplate cube({Shape::cube, 0.01, 4, 0.5});
  Material mat;
  mat.youngs_modulus = 1e6;
  mat.damping = 0.3;
  const double dt = 0.2 * contact_time_scale(cube, mat.youngs_modulus, mat.density);
  World world(cube, contact_law(cube, mat), {dt, 0.1 * cube.diameter(), Vec3(0, 0, -9.81)});
  Wall floor;
  world.add_wall(floor);
  // Slightly tilted so that first contact is on an edge and the clump has to rock into place.
  const BodyId c = world.add_grain(Vec3(0, 0, 0.0052), Quat(Eigen::AngleAxisd(0.02, Vec3::UnitX())), mat.density);
  world.compute_forces();
  for (int k = 0; k < 40000; ++k) world.step();
  const double weight = world.bodies().mass[c] * 9.81;
  EXPECT_NEAR(world.walls()[0].force.z(), -weight, 1e-6 * weight);  // force on the wall points down
  EXPECT_LT(world.bodies().velocity[c].norm(), 1e-6);
  // Resting flat: all 16 spheres of the bottom face touch.
  EXPECT_EQ(world.contact_stats().wall_contacts, 16u);
}

}  // namespace
}  // namespace granulab
