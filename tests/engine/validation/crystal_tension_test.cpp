// Crystals pulled apart between grips of their own end grains (docs/model.md, "Crystal tension"), on a 4 x 4 x 6 slab
// of the paper's crystal at N_e = 3 taken out of its bag (loading.confinement "none") at p0 = 1 Pa:
//  - without cohesion a crystal carries no tension: hooke and hertz/material contacts only push. Undamped
//    (material.damping 0), every normal force is k delta >= 0 and the grips receive no tension at all: at most
//    rounding, measured 7e-14 Pa, bounded by 1e-9 p0. With the default damping the normal force k delta - c v_n turns
//    negative for a step as a pair opens: measured 0.74 Pa (hooke) and 0.009 Pa (hertz/material) at R = 1e-6, bounded
//    by 1e-3 of what the same crystal carries with cohesion at gamma = 1 J/m^2 (5.7 kPa), so that a law that pulled
//    would fail it;
//  - with dmt and jkr the strength scales with the surface energy: doubling gamma doubles every pair's pull-off force
//    (4 pi gamma R*, 3 pi gamma R*). With mindlin's tangential spring (k_t a) the quasi-static problem is then exactly
//    self-similar: every force doubles when the overlaps grow by 2^(2/3) (Hertz: F ~ delta^1.5, a ~ delta^0.5, so
//    k_t a delta_t doubles too, and so does the Coulomb cap f |F_ne + 2 F_pulloff|), p0 = 1 Pa being negligible. So
//    the strength ratio is 2 and the failure strain's 2^(2/3) = 1.587, up to the finite rate; measured here (jkr +
//    mindlin, N_e = 3) 2.0016 and 1.590. With linear_history k_t is a constant and the ratio is not exact: measured
//    2.0097 (dmt). The tolerance, 2 %, holds the default rate's bias (R = sigma / (10 E) put a slab's strength 0.7 %
//    above its value at a tenth of that rate, docs/results.md).
//  - the strength is tracked every step (a row's worth of strain holds a cohesive crystal's whole failure): no curve
//    row exceeds it; the pull stops once the crystal is apart (jkr; a dmt crystal keeps a ligament at 2 % of its peak
//    to loading.max_strain).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/experiments/crystal_tension/crystal_tension.h"

namespace granulab {
namespace {

TensionParams bare_slab(NormalModel normal, TangentialModel tangential, double gamma) {
  TensionParams p;
  p.grain.edge_spheres = 3;
  p.grains_x = 4, p.layers_y = 4, p.rows_z = 6;
  p.confining_pressure = 1;
  p.bag = false;
  p.material.contact.normal = normal;
  p.material.contact.tangential = tangential;
  p.material.contact.surface_energy = gamma;
  p.max_strain = 3e-4;  // some five times the failure strain
  p.curve_points = 100;
  p.snapshot_strains = {};
  return p;
}

TensionResult run(const TensionParams& p) {
  ResultSink none;
  return CrystalTension(p).run(none);
}

void report(const char* what, const TensionParams& p, const TensionResult& r) {
  std::printf("%s: strength %.6g Pa (%.4g p0) at strain %.4g, %s after %llu steps; failure plane gap %d (%s), "
              "share %.2f\n",
              what, r.peak.stress, r.peak.stress / p.confining_pressure, r.peak.strain, r.apart ? "apart" : "max strain",
              (unsigned long long)r.tension_steps, r.failure.gap, r.failure.where, r.failure.share);
}

TEST(CrystalTension, WithoutCohesionACrystalCarriesNoTension) {
  TensionParams cohesive = bare_slab(NormalModel::dmt, TangentialModel::linear_history, 1);
  cohesive.confining_pressure = 1e3;
  cohesive.rate_number = 1e-6;
  const double cohesive_strength = run(cohesive).peak.stress;
  for (double damping : {0.0, 0.05})
    for (NormalModel normal : {NormalModel::hooke, NormalModel::hertz_material}) {
      TensionParams p = bare_slab(normal, TangentialModel::linear_history, 0);
      p.confining_pressure = 1e3;
      p.rate_number = 1e-6;
      p.max_strain = 2e-4;
      p.material.damping = damping;
      const TensionResult r = run(p);
      report((to_string(normal) + (damping > 0 ? ", damped" : ", undamped")).c_str(), p, r);
      const double bound = damping > 0 ? 1e-3 * cohesive_strength : 1e-9 * p.confining_pressure;
      EXPECT_LT(r.peak.stress, bound) << to_string(normal) << ", damping " << damping;
      for (const TensionRow& row : r.curve) {
        EXPECT_LT(row.tensile_stress, bound) << to_string(normal);
        EXPECT_LT(row.tensile_stress_bottom, bound) << to_string(normal);
      }
    }
  std::printf("dmt at gamma = 1 J/m^2: %.4g Pa\n", cohesive_strength);
}

struct Pair {
  TensionResult once, twice;
};

Pair pull_at_gamma_and_twice(NormalModel normal, TangentialModel tangential) {
  return {run(bare_slab(normal, tangential, 1)), run(bare_slab(normal, tangential, 2))};
}

void expect_strength_scales_with_gamma(const char* what, const Pair& r, double strain_ratio_tolerance, bool apart) {
  const TensionParams p = bare_slab(NormalModel::dmt, TangentialModel::mindlin, 1);
  report(what, p, r.once);
  report(what, p, r.twice);
  ASSERT_GT(r.once.peak.stress, 1e3 * p.confining_pressure) << what << ": cohesion holds the crystal together";
  EXPECT_NEAR(r.twice.peak.stress / r.once.peak.stress, 2.0, 0.04) << what;
  if (strain_ratio_tolerance > 0) {
    EXPECT_NEAR(r.twice.peak.strain / r.once.peak.strain, std::cbrt(4.0), strain_ratio_tolerance) << what;
  }
  for (const TensionResult* t : {&r.once, &r.twice}) {
    if (apart) {
      EXPECT_TRUE(t->apart) << what << ": the pull stops once the crystal is apart";
    }
    for (const TensionRow& row : t->curve) EXPECT_LE(row.tensile_stress, t->peak.stress) << what;
    // It comes apart between the grips, on one gap or two neighbours sharing the opening.
    EXPECT_GE(t->failure.gap, t->grip_layers[0] - 1) << what;
    EXPECT_LE(t->failure.gap, int(t->layers) - t->grip_layers[1] - 1) << what;
    EXPECT_GT(t->failure.share, 0.3) << what;
  }
}

TEST(CrystalTension, DmtStrengthScalesWithTheSurfaceEnergy) {
  expect_strength_scales_with_gamma("dmt, linear_history",
                                    pull_at_gamma_and_twice(NormalModel::dmt, TangentialModel::linear_history), 0,
                                    false);
}

TEST(CrystalTension, JkrWithMindlinIsSelfSimilarInTheSurfaceEnergy) {
  expect_strength_scales_with_gamma("jkr, mindlin", pull_at_gamma_and_twice(NormalModel::jkr, TangentialModel::mindlin),
                                    0.05, true);
}

}  // namespace
}  // namespace granulab
