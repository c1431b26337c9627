// A peak is found only where the curve falls after it; the apparent modulus is the secant of its 10-40 % window.
#include <gtest/gtest.h>

#include <vector>

#include "engine/analysis/apparent_modulus.h"
#include "engine/analysis/curve_peak.h"

using namespace granulab;

TEST(CurvePeak, ACurveStillRisingAtItsEndHasNoPeak) {
  const std::vector<double> rising = {0, 1, 2, 3, 4, 5, 6};
  const CurvePeak first = first_peak(rising, 0.5, 0.02), highest = highest_peak(rising, 0.5, 0.02);
  EXPECT_FALSE(first.found);
  EXPECT_FALSE(highest.found);
  EXPECT_EQ(first.highest, 6);
  EXPECT_EQ(highest.row, 6u);
  // Level within the drop at the end: a plateau, not a peak either.
  EXPECT_FALSE(first_peak({0, 1, 2, 3, 3, 2.95, 2.99}, 0.5, 0.02).found);
}

TEST(CurvePeak, TheFirstPeakIsTheMaximumBeforeTheFirstDropOfTwoPercent) {
  // Noise below the floor first (a dip of 100 % there counts for nothing), then 10 rises to a peak and drops 3 %.
  const std::vector<double> curve = {0.2, 0.0, 0.3, 1, 5, 10, 9.9, 9.7, 12, 20, 15};
  const CurvePeak first = first_peak(curve, 0.5, 0.02);
  ASSERT_TRUE(first.found);
  EXPECT_EQ(first.row, 5u);
  EXPECT_EQ(first.value, 10);
  EXPECT_EQ(first.highest, 20);
  const CurvePeak highest = highest_peak(curve, 0.5, 0.02);
  ASSERT_TRUE(highest.found);
  EXPECT_EQ(highest.row, 9u);
  EXPECT_EQ(highest.value, 20);
  // Never above the floor: nothing.
  EXPECT_FALSE(first_peak({0.1, 0.2, 0.1}, 0.5, 0.02).found);
  EXPECT_FALSE(highest_peak({0.1, 0.2, 0.1}, 0.5, 0.02).found);
}

TEST(ApparentModulus, IsTheSecantBetweenTenAndFortyPercentOfTheReference) {
  // A start-up of zero stress over 1e-4 strain, then a line of slope 2e8 Pa: the secant skips the start.
  std::vector<double> strain, stress;
  for (int k = 0; k <= 100; ++k) {
    const double e = 1e-5 * k;
    strain.push_back(e);
    stress.push_back(e < 1e-4 ? 0.0 : 2e8 * (e - 1e-4));
  }
  const ApparentModulus m = apparent_modulus(strain, stress, 1e5);
  ASSERT_TRUE(m.found);
  EXPECT_NEAR(m.value, 2e8, 2e8 * 1e-9);
  EXPECT_NEAR(m.from_strain, 1e-4 + 1e4 / 2e8, 1e-12);
  EXPECT_NEAR(m.to_strain, 1e-4 + 4e4 / 2e8, 1e-12);
  // A reference the curve never reaches 40 % of: none.
  EXPECT_FALSE(apparent_modulus(strain, stress, 1e6 * 1e3).found);
}
