// The interface laws (contact.normal) against their closed forms, through the whole engine (neighbour list, the
// vectorised kernel, the reduction into bodies): two aligned cubes face to face, held at rest at a set overlap of their
// facing sphere layers, so every force is the law's elastic part (no velocity, no damping). n_c aligned sphere pairs
// act in parallel, each with R* = d / 4.
//   hertz/material  P = n_c 4/3 E* sqrt(R*) delta^1.5, E* = E / (2 (1 - nu^2)): log-log slope 1.5
//   dmt             attraction 4 pi gamma R* per pair while delta > 0, nothing apart
//   jkr             most tensile 3 pi gamma R* per pair, made at delta = 0, broken at delta = -a_c^2 / (3 R*) with
//                   a_c^3 = 9 pi gamma R*^2 / (4 E*) (docs/model.md, "Interface laws")
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct TwoCubes {
  GrainTemplate cube{GrainGeometry{Shape::cube, 0.01, 4, 0.75}};
  Material material;
  World world;
  double face_x = 0;   // the facing layer's body-frame x (m)
  int aligned = 0;     // spheres in it: the aligned pairs n_c
  double r_eff = 0;    // R* = d / 4 (m)

  static Material with(NormalModel normal, double gamma) {
    Material m;
    m.contact.normal = normal;
    m.contact.poisson_ratio = 0.3;
    m.contact.surface_energy = gamma;
    m.friction = 0.3;
    return m;
  }
  TwoCubes(NormalModel normal, double gamma)
      : material(with(normal, gamma)),
        world(cube, contact_law(cube, material),
              {1e-7, 0.05 * cube.diameter(), Vec3::Zero()}) {
    for (const Vec3& o : cube.offsets()) face_x = std::max(face_x, o.x());
    for (const Vec3& o : cube.offsets()) aligned += std::abs(o.x() - face_x) < 1e-12 * face_x;
    r_eff = cube.diameter() / 4;
    world.add_grain(Vec3::Zero(), Quat::Identity(), material.density);
    world.add_grain(Vec3(2 * face_x + cube.diameter(), 0, 0), Quat::Identity(), material.density);
  }
  /// Holds the cubes at rest with the facing layers overlapping by `delta` (m; negative: apart) and returns the
  /// force pressing them together (N, compressive positive).
  double press(double delta) {
    world.bodies().position[1] = Vec3(2 * face_x + cube.diameter() - delta, 0, 0);
    world.compute_forces();
    return -world.bodies().force[0].x();
  }
  double effective_modulus() const { return material.youngs_modulus / (2 * (1 - 0.09)); }
};

TEST(InterfaceLaws, HertzCubesFollowTheThreeHalvesPower) {
  TwoCubes t(NormalModel::hertz_material, 0);
  ASSERT_EQ(t.aligned, 16);  // N_e^2
  const double d = t.cube.diameter(), e = t.effective_modulus();
  double first_p = 0, first_delta = 0, last_p = 0, last_delta = 0;
  for (double share = 1e-7; share < 2e-3; share *= 2) {
    const double delta = share * d, p = t.press(delta);
    ASSERT_EQ(t.world.contact_stats().contacts, std::size_t(t.aligned)) << "only the aligned pairs touch";
    // Sixteen equal terms summed: the closed form to rounding, and to the rounding of delta itself, a difference of
    // positions near 1e-2 m (ulp 1.7e-18 m; a few of them, times 1.5 in delta^1.5).
    EXPECT_NEAR(p, t.aligned * 4.0 / 3 * e * std::sqrt(t.r_eff) * std::pow(delta, 1.5), p * (1e-9 + 2e-17 / delta))
        << delta;
    if (first_p == 0) first_p = p, first_delta = delta;
    last_p = p, last_delta = delta;
  }
  const double slope = std::log(last_p / first_p) / std::log(last_delta / first_delta);
  EXPECT_NEAR(slope, 1.5, 0.01);
}

TEST(InterfaceLaws, DmtAttractsWithItsPulloffWhileTouching) {
  const double gamma = 5;
  TwoCubes t(NormalModel::dmt, gamma);
  const double pulloff = t.aligned * 4 * kPi * gamma * t.r_eff;
  // Where the Hertz part is a thousandth of the attraction the pair pulls with (1 - 1e-3) n_c 4 pi gamma R*.
  const double e = t.effective_modulus(), hertz_scale = std::pow(4 * kPi * gamma * t.r_eff / (4.0 / 3 * e * std::sqrt(t.r_eff)), 2.0 / 3);
  double most_tensile = 0;
  for (double share = 1e-6; share <= 1; share *= 1.5) most_tensile = std::min(most_tensile, t.press(share * hertz_scale));
  EXPECT_NEAR(-most_tensile, pulloff, 0.01 * pulloff);
  EXPECT_LT(-most_tensile, pulloff);
  // Apart, nothing, however close.
  EXPECT_EQ(t.press(-1e-3 * hertz_scale), 0.0);
  EXPECT_EQ(t.world.contact_stats().contacts, 0u);
}

TEST(InterfaceLaws, JkrPullsOffAtThreePiGammaRAndHoldsPastContact) {
  const double gamma = 5;
  TwoCubes t(NormalModel::jkr, gamma);
  const double e = t.effective_modulus(), r = t.r_eff;
  const double ac = std::cbrt(9 * kPi * gamma * r * r / (4 * e)), break_depth = ac * ac / (3 * r);
  const double pulloff = t.aligned * 3 * kPi * gamma * r;
  // Approach from apart: no force until the layers touch (delta >= 0), then the snap onto the JKR curve, which at
  // delta = 0 pulls with 8/3 pi gamma R* per pair.
  const int n = 4000;
  for (int k = 0; k <= n; ++k) {
    const double delta = -2 * break_depth + 2 * break_depth * k / n;  // up to 0, exclusive of touching at 0
    if (delta >= 0) break;
    ASSERT_EQ(t.press(delta), 0.0) << "unbonded pairs do not attract at delta " << delta;
  }
  const double snap = t.press(1e-9 * break_depth);
  EXPECT_NEAR(-snap, t.aligned * 8.0 / 3 * kPi * gamma * r, 1e-3 * pulloff);
  // Pressed in, then pulled apart past contact: the bond holds, pulling hardest at 3 pi gamma R* per pair, and breaks
  // at -a_c^2 / (3 R*).
  t.press(break_depth);
  double most_tensile = 0, last_held = 0;
  for (int k = 0; k <= n; ++k) {
    const double delta = break_depth - 2.5 * break_depth * k / n;
    const double p = t.press(delta);
    most_tensile = std::min(most_tensile, p);
    if (p != 0) last_held = delta;
    if (delta < -0.5 * break_depth && delta > -0.9 * break_depth) {
      ASSERT_LT(p, 0.0) << "the bond holds apart at delta " << delta;  // the hysteresis: 0 on the way in
    }
  }
  EXPECT_NEAR(-most_tensile, pulloff, 0.01 * pulloff);
  EXPECT_LE(-most_tensile, pulloff * (1 + 1e-9));
  EXPECT_NEAR(last_held, -break_depth, 1.01 * 2.5 * break_depth / n);  // within one step of the pull
  EXPECT_EQ(t.world.contact_stats().contacts, 0u);
  // Broken, it does not attract again until it touches.
  EXPECT_EQ(t.press(-0.5 * break_depth), 0.0);
}

}  // namespace
}  // namespace granulab

namespace granulab {
namespace {

// jkr's contact radius is the root of a quartic found by Newton (contact_law.h): for contact radii from the pull-off
// point a_c to 100 a_c, the overlap delta(a) = a^2 / R* - 2 sqrt(pi gamma a / E*) fed to the law gives back
// F(a) = 4 E* a^3 / (3 R*) - 4 sqrt(pi gamma E* a^3) to 1e-9 of 3 pi gamma R* (the force scale).
TEST(InterfaceLaws, JkrContactRadiusInvertsItsOverlap) {
  ContactLaw law{4.0 / 3 * 1.65e9, 1e5, 0.0, 0.3};
  law.normal = NormalModel::jkr, law.effective_modulus = 1.65e9, law.surface_energy = 5;
  const double r = 2.5e-4, e = law.effective_modulus, g = law.surface_energy;
  const double ac = std::cbrt(9 * kPi * g * r * r / (4 * e)), scale = 3 * kPi * g * r;
  const PairLaw c = pair_law(law, r, 1e-3, 1e-7);
  for (double share = 1.0; share < 100; share *= 1.1) {
    const double a = share * ac, delta = a * a / r - 2 * std::sqrt(kPi * g * a / e);
    const double expected = 4 * e * a * a * a / (3 * r) - 4 * std::sqrt(kPi * g * e * a * a * a);
    Vec3 xi = Vec3::Zero();
    double bond = 1;  // bonded: holds at negative overlaps too
    const ContactForce f = contact_force(law, c, Vec3::UnitZ(), delta, Vec3::Zero(), xi, bond);
    EXPECT_NEAR(f.normal, expected, 1e-9 * std::max(scale, std::abs(expected))) << "a / a_c " << share;
  }
}

}  // namespace
}  // namespace granulab

#include "engine/crystal/confinement.h"

namespace granulab {
namespace {

// A Hertz crystal is built at its own pre-strain (sum_f N_f F(eps0 l_f) l_f = 6 V p0, larger than Hooke's: softer
// contacts at these loads) and its platens' servo uses the Hertz contacts' stiffness at the load: it confines as a
// Hooke crystal does. (Built at Hooke's pre-strain with k_N taken for N/m, the platens had reached 9.9 of 30 kPa after
// the 200,000-step cap.)
TEST(InterfaceLaws, HertzCrystalConfinesLikeAHookeOne) {
  for (NormalModel normal : {NormalModel::hooke, NormalModel::hertz_material}) {
    CrystalSampleParams p;
    p.grain.edge_spheres = 3;
    p.grains_x = 4, p.layers_y = 4, p.rows_z = 6;
    p.confining_pressure = 30e3;
    p.material.contact.normal = normal;
    const double eps0 = hydrostatic_prestrain(p);
    if (normal != NormalModel::hooke) {
      CrystalSampleParams hooke = p;
      hooke.material.contact.normal = NormalModel::hooke;
      EXPECT_GT(eps0, 1.5 * hydrostatic_prestrain(hooke)) << "a Hertz face at p0 overlaps more";
    }
    CrystalSample sample(p);
    const ConfinementReport r = confine(sample);
    EXPECT_TRUE(r.converged) << to_string(normal);
    EXPECT_LT(r.steps, 20000u) << to_string(normal);
    EXPECT_NEAR(r.stress_top, 30e3, 0.01 * 30e3) << to_string(normal);
    EXPECT_NEAR(r.lateral_stress_x, 30e3, 0.1 * 30e3) << to_string(normal);
  }
}

}  // namespace
}  // namespace granulab

namespace granulab {
namespace {

// A cohesive crystal is quiet when its kinetic energy is small against what its own stress sigma = max(p0, the cohesive
// stress scale F_pulloff(d/4) / s^2) would store in its material, and its platens hold p0 within 1 % of sigma: its
// contacts' stored energy, cohesion's negative potential included, is no scale, and cohesion presses the contacts to
// sigma whatever p0 is (docs/model.md, "Interface laws"). With no floor a DMT crystal at 1 kPa with gamma = 2 J/m^2
// ran to the 200,000-step cap, its platens at p0 and at rest; with p0 in both checks, 18,400 steps; with sigma
// (25.8 kPa here), 1,000, the platens at 937 Pa.
TEST(InterfaceLaws, CohesiveCrystalConfines) {
  CrystalSampleParams p;
  p.grain.edge_spheres = 3;
  p.grains_x = 4, p.layers_y = 4, p.rows_z = 6;
  p.confining_pressure = 1e3;
  p.material.contact.normal = NormalModel::dmt;
  p.material.contact.surface_energy = 2;
  const double sigma = std::max(p.confining_pressure, cohesive_stress_scale(p));
  EXPECT_GT(sigma, 10 * p.confining_pressure) << "cohesion dominates here";
  CrystalSample sample(p);
  const ConfinementReport r = confine(sample);
  std::printf("sigma %.4g Pa: confined in %llu steps, platens at %.4g Pa\n", sigma, (unsigned long long)r.steps,
              r.stress_top);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.steps, 10000u);
  EXPECT_NEAR(r.stress_top, 1e3, 0.01 * sigma);
}

}  // namespace
}  // namespace granulab
