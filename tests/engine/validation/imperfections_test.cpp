// Imperfect grains (engine/crystal/imperfections.h) on small crystals (N_e = 4, 4 x 8 x 4 grains):
//  - the same seed gives the same crystal, bit for bit, and another seed another one;
//  - the draws have the statistics asked for (size shortfall sigma_s sqrt(2/pi) on average, rms tilt
//    sigma_r), no grain is larger than the template, and no two grains overlap more than in the perfect
//    crystal (tilted grains are shrunk into their sites);
//  - the apparent modulus (secant over the first 0.05 % of strain) of an imperfect crystal is lower.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/experiments/crystal_compression/crystal_compression.h"

namespace granulab {
namespace {

CrystalParams small_crystal(double size_dispersion, double misorientation, std::uint64_t seed = 7) {
  CrystalParams p;
  p.grain.edge_spheres = 4;
  p.grains_x = 4, p.rows_z = 8, p.layers_y = 4;
  p.confining_pressure = 30e3;
  p.max_strain = 0.001;
  p.rate_number = 2e-5;
  p.curve_points = 80;  // 20 rows over the first 2.5e-5, then every 1.7e-5
  p.snapshot_strains = {};
  p.imperfections.size_dispersion = size_dispersion;
  p.imperfections.misorientation = misorientation;
  p.imperfections.seed = seed;
  return p;
}

TEST(Imperfections, TheSameSeedGivesTheSameCrystalAnotherSeedAnother) {
  const CrystalSample a(small_crystal(0.01, 2)), b(small_crystal(0.01, 2)), c(small_crystal(0.01, 2, 8));
  EXPECT_EQ(a.world().bodies().scale, b.world().bodies().scale);
  EXPECT_EQ(a.world().bodies().position, b.world().bodies().position);
  for (std::size_t i = 0; i < a.world().bodies().size(); ++i)
    EXPECT_EQ(a.world().bodies().orientation[i].coeffs(), b.world().bodies().orientation[i].coeffs());
  EXPECT_NE(a.world().bodies().scale, c.world().bodies().scale);
}

TEST(Imperfections, DrawsHaveTheirStatisticsAndFitTheirSites) {
  const double sigma_s = 0.02, sigma_r = 3;
  const CrystalSample sized(small_crystal(sigma_s, 0)), tilted(small_crystal(0, sigma_r)), perfect(small_crystal(0, 0));
  const std::size_t n = sized.world().bodies().size();
  ASSERT_EQ(n, 128u);
  // Sizes: 1 - sigma_s |z|; E|z| = sqrt(2/pi), sd(|z|) = 0.60, so the mean of 128 is within 0.053 sigma_s
  // of it at one standard deviation: 0.25 sigma_s is nearly 5 of them.
  double mean = 0;
  for (double s : sized.world().bodies().scale) {
    EXPECT_LE(s, 1.0);
    mean += s / n;
  }
  EXPECT_NEAR(1 - mean, sigma_s * std::sqrt(2 / M_PI), 0.25 * sigma_s);
  // Tilts: the rms angle of the drawn rotations is sigma_r (to 15 %: the estimate's relative sd is about
  // 1 / sqrt(2 x 3 x 128) = 3.6 %); each tilted grain is shrunk, by its fit_scale exactly.
  double square = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const GrainImperfection& g = tilted.imperfections()[i];
    const double angle = Eigen::AngleAxisd(g.rotation).angle() * 180 / M_PI;
    square += angle * angle / n;
    EXPECT_DOUBLE_EQ(g.scale, fit_scale(tilted.grain(), g.rotation));
    EXPECT_LT(g.scale, 1.0);
  }
  EXPECT_NEAR(std::sqrt(square), sigma_r, 0.15 * sigma_r);
  // Fitted into their sites: no grain overlaps its neighbours more than in the perfect crystal, whose
  // face overlaps carry p0.
  const auto deepest = [](const CrystalSample& s) {
    const std::vector<double>& o = s.world().overlap_sums();
    return *std::max_element(o.begin(), o.end());
  };
  EXPECT_GT(deepest(perfect), 0);
  EXPECT_LE(deepest(tilted), deepest(perfect) * (1 + 1e-9));
  EXPECT_LE(deepest(sized), deepest(perfect) * (1 + 1e-9));
}

// The secant deviator / strain at the first row past 0.05 % strain (Pa).
double apparent_modulus(const CrystalResult& r) {
  for (const CrystalRow& row : r.curve)
    if (row.strain >= 5e-4) return row.deviator / row.strain;
  return NAN;
}

TEST(Imperfections, LowerTheApparentModulus) {
  CrystalCompression perfect(small_crystal(0, 0)), sized(small_crystal(0.005, 0)), tilted(small_crystal(0, 1));
  const double e0 = apparent_modulus(perfect.run()), es = apparent_modulus(sized.run()),
               et = apparent_modulus(tilted.run());
  ASSERT_GT(e0, 0);
  EXPECT_LT(es, 0.8 * e0) << "perfect " << e0 << " Pa, sigma_s = 0.5 %: " << es;
  EXPECT_LT(et, 0.8 * e0) << "perfect " << e0 << " Pa, sigma_r = 1 deg: " << et;
}

}  // namespace
}  // namespace granulab
