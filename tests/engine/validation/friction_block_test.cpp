// A friction block at the Coulomb limit: a cube clump on a frictional wall under gravity tilted by
// theta from the wall normal (an inclined plane). Closed form: it sticks when tan(theta) < f, and
// otherwise slides with acceleration g (sin theta - f cos theta).
#include <gtest/gtest.h>

#include <cmath>

#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

struct Incline {
  World world;
  BodyId block;
  /// `wall_f` < 0: the wall uses the contact law's f.
  Incline(double theta, double f, double wall_f = -1)
      : world(make_world(theta, f)), block(world.add_grain(Vec3(0, 0, 0.00499), Quat::Identity(), 1200)) {
    Wall wall;
    wall.friction = wall_f;
    world.add_wall(wall);
    world.compute_forces();
  }
  static World make_world(double theta, double f) {
    static const GrainTemplate cube({Shape::cube, 0.01, 3, 0.5});
    Material mat;
    mat.youngs_modulus = 1e6;
    mat.friction = f;
    mat.damping = 0.3;
    const double dt = 0.2 * contact_time_scale(cube, mat.youngs_modulus, mat.density);
    const double g = 9.81;
    return World(cube, contact_law(cube, mat),
                 {dt, 0.1 * cube.diameter(), Vec3(g * std::sin(theta), 0, -g * std::cos(theta))});
  }
  void run(int steps) {
    for (int k = 0; k < steps; ++k) world.step();
  }
  double vx() const { return world.bodies().velocity[block].x(); }
};

TEST(FrictionBlock, SticksBelowCoulombLimit) {
  const double f = 0.3, theta = std::atan(0.2);
  Incline incline(theta, f);
  incline.run(20000);
  const double x1 = incline.world.bodies().position[incline.block].x();
  incline.run(20000);
  // At rest: no creep between the two halves (elastic tangential springs hold the block).
  EXPECT_LT(std::abs(incline.world.bodies().position[incline.block].x() - x1), 1e-9);
  EXPECT_LT(std::abs(incline.vx()), 1e-7);
  EXPECT_EQ(incline.world.contact_stats().wall_contacts, 9u);
}

TEST(FrictionBlock, SlidesWithCoulombAccelerationAboveLimit) {
  const double f = 0.3, g = 9.81;
  for (double tan_theta : {0.4, 0.6}) {
    const double theta = std::atan(tan_theta);
    Incline incline(theta, f);
    incline.run(5000);  // landing and rocking die out (over-damped: zeta = 0.3 per pair, 9 pairs)
    const double t1 = incline.world.time(), v1 = incline.vx();
    incline.run(5000);
    const double a = (incline.vx() - v1) / (incline.world.time() - t1);
    const double expected = g * (std::sin(theta) - f * std::cos(theta));
    // Every contact slides, so friction is exactly f times the normal load; what remains is the
    // decaying normal oscillation, well under 0.1 % of the acceleration after 5000 steps.
    EXPECT_NEAR(a, expected, 1e-3 * expected) << "tan theta " << tan_theta;
    EXPECT_EQ(incline.world.contact_stats().wall_contacts, 9u);
  }
}

// A wall's own coefficient replaces the law's on that wall (the crystal's loading.wall_friction): the
// block slides at the acceleration of the wall's f, and sticks where the law's f alone would let it slide.
TEST(FrictionBlock, WallFrictionOverridesTheLaw) {
  const double g = 9.81, theta = std::atan(0.6);
  Incline sliding(theta, 0.3, 0.45);
  sliding.run(5000);
  const double t1 = sliding.world.time(), v1 = sliding.vx();
  sliding.run(5000);
  const double a = (sliding.vx() - v1) / (sliding.world.time() - t1);
  const double expected = g * (std::sin(theta) - 0.45 * std::cos(theta));
  EXPECT_NEAR(a, expected, 1e-3 * expected);

  Incline sticking(std::atan(0.4), 0.3, 0.5);  // slides at f = 0.3 (test above), sticks at 0.5
  sticking.run(20000);
  const double x1 = sticking.world.bodies().position[sticking.block].x();
  sticking.run(20000);
  EXPECT_LT(std::abs(sticking.world.bodies().position[sticking.block].x() - x1), 1e-9);
}

}  // namespace
}  // namespace granulab
