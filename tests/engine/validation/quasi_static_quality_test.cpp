// How quasi-static a crystal compression was (quasi_static_quality.h), on a 4 x 8 x 3 crystal (N_e = 4) to
// 0.3 % strain, past its first yield: at the default rate 1.5 p0/E the job carries no warning and its platens
// agree; at 5 p0/E it carries the calibration's expected bias, and its first yield is indeed stronger than
// at p0/(2E), by an amount of that order.
#include <gtest/gtest.h>

#include <tuple>

#include "engine/experiments/crystal_compression/quasi_static_quality.h"

namespace granulab {
namespace {

CrystalParams crystal(double rate_over_quasi_static) {
  CrystalParams p;
  p.grain.edge_spheres = 4;
  p.grains_x = 4, p.rows_z = 8, p.layers_y = 3;
  p.confining_pressure = 30e3;
  p.rate_number = rate_over_quasi_static * quasi_static_rate_number(p.confining_pressure, p.material.youngs_modulus);
  p.max_strain = 3e-3;
  p.curve_points = 80;
  p.snapshot_strains = {};
  return p;
}

struct RateRun {
  CrystalResult result;
  QuasiStaticQuality quality;
  double first_yield = 0;  // Pa
};

RateRun run(double ratio) {
  const CrystalParams p = crystal(ratio);
  CrystalCompression experiment(p);
  RateRun out;
  out.result = experiment.run();
  out.quality = assess_quasi_static(p, out.result);
  out.first_yield = first_yield_peak(out.result.curve, p.confining_pressure).second;
  return out;
}

TEST(QuasiStaticQuality, TheCalibrationInterpolatesBetweenMeasuredRatios) {
  EXPECT_DOUBLE_EQ(expected_rate_bias(0), 0);
  EXPECT_LT(expected_rate_bias(1.5), 0.022);  // the default: within about 2 % (2.09 % at worst, measured)
  EXPECT_GT(expected_rate_bias(5), 0.02);
  for (double r = 0.1; r < 40; r *= 1.3) EXPECT_LE(expected_rate_bias(r), expected_rate_bias(r * 1.3)) << r;
}

TEST(QuasiStaticQuality, ADefaultRateJobCarriesNoWarningAFiveTimesFasterOneItsBias) {
  const RateRun slow = run(0.5), fine = run(1.5), fast = run(5);
  EXPECT_DOUBLE_EQ(fine.quality.rate_over_quasi_static, 1.5);
  EXPECT_TRUE(fine.quality.warnings.empty()) << fine.quality.warnings.front();
  EXPECT_LT(fine.quality.platen_imbalance_rms, 0.02);
  EXPECT_LT(fine.quality.kinetic_elastic_mean, 0.05);
  // The default's first yield is within 2 % of p0/(2E)'s: no warning was right.
  EXPECT_NEAR(fine.first_yield / slow.first_yield, 1, 0.02);

  ASSERT_FALSE(fast.quality.warnings.empty());
  EXPECT_NE(fast.quality.warnings.front().find("5 x p0/E"), std::string::npos) << fast.quality.warnings.front();
  EXPECT_NE(fast.quality.warnings.front().find("about 7 %"), std::string::npos) << fast.quality.warnings.front();
  // The bias it announces is the right size: measured against p0/(2E), within a factor 2.
  const double bias = fast.first_yield / slow.first_yield - 1;
  EXPECT_GT(bias, fast.quality.expected_bias / 2) << bias;
  EXPECT_LT(bias, fast.quality.expected_bias * 2) << bias;
}

}  // namespace
}  // namespace granulab
