// The contact law against closed forms: head-on Hooke force, stick then slip at the Coulomb limit,
// shear history carried by a rotating contact plane, and the restitution coefficient of the linear
// spring-dashpot measured on a real collision of two clumps integrated by the engine.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/contact/contact_law.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

// Hooke ignores the pair's effective radius.
constexpr double kRadius = 5e-4;

ContactLaw law(double kn, double ratio, double zeta, double f) { return {kn, ratio * kn, zeta, f}; }

TEST(ContactLaw, HeadOnForceIsStiffnessTimesOverlap) {
  const ContactLaw l = law(3e5, 2.0 / 7, 0.05, 0.3);
  const Vec3 n = Vec3(1, 2, -2).normalized();
  Vec3 xi = Vec3::Zero();
  for (double delta : {1e-9, 1e-6, 1e-4}) {
    const ContactForce cf = contact_force(l, n, delta, Vec3::Zero(), kRadius, 1e-3, 1e-7, xi);
    // At rest the only force is the spring: exact up to rounding.
    EXPECT_NEAR((cf.force - 3e5 * delta * n).norm(), 0, 1e-12 * 3e5 * delta);
    EXPECT_FALSE(cf.sliding);
  }
}

// Constant normal load, constant tangential sliding velocity: F_t = k_t v t + c_t v while it sticks,
// then exactly f F_n. No normal velocity, so F_n = k_n delta throughout.
TEST(ContactLaw, StickThenSlipAtCoulombLimit) {
  for (double zeta : {0.0, 0.2}) {
    const double kn = 1e5, f = 0.4, delta = 1e-5, m = 2e-3, dt = 1e-6, v = 1e-3;  // slips at step ~14,000
    const ContactLaw l = law(kn, 2.0 / 7, zeta, f);
    const double kt = l.tangential_stiffness, ct = zeta * std::sqrt(kn * m);
    const Vec3 n = Vec3::UnitZ(), vt = Vec3(v, 0, 0);
    const double fn = kn * delta, cap = f * fn;
    Vec3 xi = Vec3::Zero();
    bool slipped = false;
    for (int k = 1; k <= 20000; ++k) {
      const ContactForce cf = contact_force(l, n, delta, vt, kRadius, m, dt, xi);
      EXPECT_NEAR(cf.force.z(), fn, 1e-12 * fn);
      const double stick = kt * v * k * dt + ct * v;  // |F_t| of the elastic branch
      if (stick < cap * (1 - 1e-9)) {
        ASSERT_FALSE(cf.sliding) << "step " << k;
        EXPECT_NEAR(-cf.force.x(), stick, 1e-9 * cap);
      } else if (stick > cap * (1 + 1e-9)) {
        ASSERT_TRUE(cf.sliding) << "step " << k;
        EXPECT_NEAR(-cf.force.x(), cap, 1e-12 * cap);
        slipped = true;
      }
      EXPECT_NEAR(cf.force.y(), 0, 1e-15);
    }
    EXPECT_TRUE(slipped);
    // Reversing the slide first unloads the spring elastically: the force drops by 2 c_t v + k_t v dt.
    const ContactForce back = contact_force(l, n, delta, -vt, kRadius, m, dt, xi);
    EXPECT_FALSE(back.sliding);
    EXPECT_NEAR(-back.force.x(), cap - 2 * ct * v - kt * v * dt, 1e-9 * cap);
  }
}

// Rigid co-rotation of the pair (no relative tangential velocity): the shear spring must turn with
// the contact plane and keep its length. Here the normal turns by 90 degrees about y in 1000 steps.
TEST(ContactLaw, HistoryFollowsRotatingContactPlane) {
  const ContactLaw l = law(1e5, 2.0 / 7, 0.0, 100.0);  // no slip: the spring force is k_t |xi|
  const double xi0 = 2e-6;
  Vec3 xi(xi0, 0, 0);
  const int steps = 1000;
  for (int k = 1; k <= steps; ++k) {
    const double phi = M_PI / 2 * k / steps;
    const Vec3 n(std::sin(phi), 0, std::cos(phi));
    const ContactForce cf = contact_force(l, n, 1e-6, Vec3::Zero(), kRadius, 1e-3, 1e-7, xi);
    // xi stays in the plane spanned by n and itself, so the projection is an exact rotation.
    EXPECT_NEAR(xi.dot(n), 0, 1e-12 * xi0);
    EXPECT_NEAR(xi.norm(), xi0, 1e-12 * xi0);
    EXPECT_NEAR((xi - xi0 * Vec3(std::cos(phi), 0, -std::sin(phi))).norm(), 0, 1e-12 * xi0);
    EXPECT_NEAR((cf.force - cf.normal * n).norm(), l.tangential_stiffness * xi0, 1e-9 * l.tangential_stiffness * xi0);
  }
}

// Two cubes with one sphere at each corner (N_e = 2, kappa = 0) meet face to face: four in-line
// sphere pairs act in parallel, a linear spring 4 k_n with dashpot 4 c_n on the reduced mass m/2.
// The damping ratio of that oscillator is 2 zeta, so e = exp(-pi 2zeta / sqrt(1 - 4 zeta^2)).
TEST(ContactLaw, NormalRestitutionMatchesLinearSpringDashpot) {
  for (double zeta : {0.0, 0.05, 0.2}) {
    const GrainTemplate cube({Shape::cube, 0.01, 2, 0.0});
    Material mat;
    mat.youngs_modulus = 1e7;
    mat.damping = zeta;
    mat.friction = 0.0;
    const double t0 = contact_time_scale(cube, mat.youngs_modulus, mat.density);
    World world(cube, contact_law(cube, mat), {t0 / 400, 0.05 * cube.diameter(), Vec3::Zero()});
    const double l = 0.01, gap = 1e-5, v0 = 0.05;
    const BodyId a = world.add_grain(Vec3::Zero(), Quat::Identity(), mat.density);
    const BodyId b = world.add_grain(Vec3(0, 0, l + gap), Quat::Identity(), mat.density);
    world.bodies().velocity[a] = Vec3(0, 0, v0 / 2);
    world.bodies().velocity[b] = Vec3(0, 0, -v0 / 2);
    world.compute_forces();
    bool touched = false;
    for (int k = 0; k < 200000; ++k) {
      world.step();
      touched = touched || world.contact_stats().contacts > 0;
      if (touched && world.contact_stats().contacts == 0) break;
    }
    ASSERT_TRUE(touched);
    const double v_out = world.bodies().velocity[b].z() - world.bodies().velocity[a].z();
    const double z = 2 * zeta;
    const double e = std::exp(-M_PI * z / std::sqrt(1 - z * z));
    // ~900 steps per contact: the O(dt) error of detecting the first and last overlapping step and
    // evaluating damping on half-step velocities stays below 1e-3 of the impact speed.
    EXPECT_NEAR(v_out / v0, e, 1e-3) << "zeta " << zeta;
    // Momentum is exchanged, never created: the pair's total momentum is unchanged.
    EXPECT_NEAR(world.bodies().velocity[a].z() + world.bodies().velocity[b].z(), 0, 1e-12 * v0);
  }
}

}  // namespace
}  // namespace granulab

namespace granulab {
namespace {

// The losses the energy balance counts (contact_law.h): steady sliding at speed v loses the Coulomb force times the
// slip, f F_n v dt a step, to friction and nothing to the tangential dashpot; with no tangential spring (k_t = 0)
// all of v dt slips, the same loss.
TEST(ContactLaw, SteadySlidingLosesTheCoulombForceTimesTheSlip) {
  for (const double ratio : {2.0 / 7, 0.0}) {
    const ContactLaw l = law(1e5, ratio, 0.1, 0.3);
    const Vec3 n(0, 0, 1), v(0.1, 0, 0);  // fast enough that c_t v exceeds the cap when there is no spring
    const double delta = 1e-6, dt = 1e-7, m = 1e-3;
    Vec3 xi = Vec3::Zero();
    ContactForce cf{};
    for (int k = 0; k < 20000; ++k) cf = contact_force(l, n, delta, v, kRadius, m, dt, xi);  // well past the stick phase
    ASSERT_TRUE(cf.sliding) << ratio;
    EXPECT_NEAR(cf.friction, 0.3 * cf.normal * v.norm() * dt, 1e-9 * cf.friction) << ratio;
    EXPECT_DOUBLE_EQ(cf.damping, 0.0);  // v_n = 0, and the tangential dashpot counts only while sticking
  }
}

}  // namespace
}  // namespace granulab
