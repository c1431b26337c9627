// The velocity the dashpots see (WorldSettings::damping_velocity, docs/model.md "Damping velocity"), on a cube clump
// resting on a floor: its 16 bottom spheres are 16 parallel springs k and dashpots c = 2 zeta sqrt(k m) (each wall
// contact is damped with the body's mass), so its vertical mode is a damped oscillator of w = sqrt(16 k / m) and
// damping ratio Z = 16 c / (2 sqrt(16 k m)) = 4 zeta. For x'' = -w^2 x - 2 Z w u, stepped by velocity Verlet with
// the dashpot's u
//  - the half-step velocity v(t + h/2) (as LAMMPS): stable only for w h < 2 (sqrt(1 + Z^2) - Z);
//  - v(t) + a(t) h/4: stable for w h < 2 (sqrt(1 + Z^2/4) - Z/2), the same bound at half the damping.
// (Both from the characteristic polynomial of the one-step map, derived in docs/model.md.) At Z = 0.5 the bounds are
// w h < 1.236 and 1.562: at w h = 1.4 the first grows and the second decays. At a small step both decay as the
// continuous oscillator, by exp(-2 pi Z / sqrt(1 - Z^2)) per damped period.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

struct Bounce {
  const GrainTemplate cube = GrainTemplate(GrainGeometry{Shape::cube, 0.01, 4, 0.5});
  double omega = 0, rest_z = 0, amplitude = 0;
  std::vector<double> z;  // the body's height after each step (m)

  // Runs `steps` steps of w h = `omega_h` from rest at 10 % of the static overlap below the equilibrium.
  Bounce(double zeta_mode, double omega_h, DampingVelocity dashpots, int steps) {
    Material mat;
    mat.youngs_modulus = 1e6;
    mat.damping = zeta_mode / 4;  // 16 contacts: Z = sqrt(16) zeta
    const ContactLaw law = contact_law(cube, mat);
    const double mass = mat.density * cube.volume();
    omega = std::sqrt(16 * law.normal_stiffness / mass);
    const double g = 1e-3 * cube.diameter() * 16 * law.normal_stiffness / mass;  // static overlap 1e-3 d
    WorldSettings s;
    s.time_step = omega_h / omega, s.skin = 0.1 * cube.diameter(), s.gravity = Vec3(0, 0, -g);
    s.damping_velocity = dashpots;
    World world(cube, law, s);
    const Wall floor;
    world.add_wall(floor);
    double lowest = 0;
    for (const Vec3& o : cube.offsets()) lowest = std::min(lowest, o.z());
    const double overlap = mass * g / (16 * law.normal_stiffness);
    rest_z = cube.radius() - lowest - overlap;
    amplitude = 0.1 * overlap;
    world.add_grain(Vec3(0, 0, rest_z - amplitude), Quat::Identity(), mat.density);
    world.compute_forces();
    for (int k = 0; k < steps; ++k) world.step(), z.push_back(world.bodies().position[0].z());
  }
  // The largest |z - rest| over steps [from, to) (m).
  double swing(std::size_t from, std::size_t to) const {
    double m = 0;
    for (std::size_t k = from; k < std::min(to, z.size()); ++k) m = std::max(m, std::abs(z[k] - rest_z));
    return m;
  }
  // The deepest dip below the rest height over steps [from, to) (m).
  double dip(std::size_t from, std::size_t to) const {
    double m = 0;
    for (std::size_t k = from; k < std::min(to, z.size()); ++k) m = std::max(m, rest_z - z[k]);
    return m;
  }
};

TEST(DampingVelocity, QuarterStepDashpotsStayStableWhereHalfStepOnesGrow) {
  // w h = 1.4 between the bounds at Z = 0.5; 400 steps are about 90 periods.
  const Bounce half(0.5, 1.4, DampingVelocity::half_step, 400), quarter(0.5, 1.4, DampingVelocity::quarter_step, 400);
  EXPECT_GT(half.swing(300, 400), 3 * half.amplitude) << "the half-step dashpots should be unstable at w h = 1.4";
  EXPECT_LT(quarter.swing(300, 400), 1e-6 * quarter.amplitude) << "the quarter-step ones should have damped it out";
  // Below both bounds (w h = 1.1) both decay.
  const Bounce half_below(0.5, 1.1, DampingVelocity::half_step, 400);
  EXPECT_LT(half_below.swing(300, 400), 1e-6 * half_below.amplitude);
  // Above the quarter-step bound (w h = 1.65) it grows too: the bound is the closed form's, not a lucky margin.
  const Bounce quarter_above(0.5, 1.65, DampingVelocity::quarter_step, 400);
  EXPECT_GT(quarter_above.swing(300, 400), 3 * quarter_above.amplitude);
}

TEST(DampingVelocity, BothDecayAsTheContinuousOscillatorAtASmallStep) {
  // w h = 0.01: the lag of either velocity changes the decay by O(Z w h) = 1e-3 of it (measured 3e-4 and 4e-4, with
  // the dips sampled at steps); 0.2 % is above that and far below what a wrong damping would make (10 % more of it
  // moves the ratio by 6 %).
  const double zeta_mode = 0.1, per_period = std::exp(-2 * M_PI * zeta_mode / std::sqrt(1 - zeta_mode * zeta_mode));
  for (DampingVelocity dashpots : {DampingVelocity::half_step, DampingVelocity::quarter_step}) {
    const Bounce b(zeta_mode, 0.01, dashpots, 3000);
    const std::size_t period = std::size_t(std::round(2 * M_PI / std::sqrt(1 - zeta_mode * zeta_mode) / 0.01));
    // Successive dips below the rest height (the start is one), a damped period apart.
    const double first = b.dip(0, period / 4), second = b.dip(3 * period / 4, period + period / 4);
    std::printf("%s: one damped period keeps %.5f of the dip (closed form %.5f)\n",
                dashpots == DampingVelocity::half_step ? "half step" : "quarter step", second / first, per_period);
    EXPECT_NEAR(second / first, per_period, 0.002 * per_period)
        << (dashpots == DampingVelocity::half_step ? "half step" : "quarter step");
  }
}

}  // namespace
}  // namespace granulab
