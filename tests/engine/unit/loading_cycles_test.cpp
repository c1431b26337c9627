// loading_cycles() on curves whose answers are known in closed form: a parallelogram loop (linear
// branches), so the slopes are the branches' and the loop area is base x height.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/analysis/loading_cycles.h"

namespace granulab {
namespace {

// Straight branches, as rows every n-th of each:
//  load:    (0, 0) -> (0.01, 1)          slope 100
//  unload:  (0.01, 1) -> (0.006, 0)      slope 250
//  reload:  (0.006, 0) -> (0.012, 3)     slope 500, crossing the peak strain 0.01 at 2
void branch(std::vector<double>& e, std::vector<double>& s, double e1, double s1, int n) {
  const double e0 = e.back(), s0 = s.back();
  for (int k = 1; k <= n; ++k) e.push_back(e0 + (e1 - e0) * k / n), s.push_back(s0 + (s1 - s0) * k / n);
}

TEST(LoadingCycles, SlopesResidualAndLoopAreaOfAParallelogram) {
  std::vector<double> e{0}, s{0};
  branch(e, s, 0.01, 1, 10);
  branch(e, s, 0.006, 0, 10);
  branch(e, s, 0.012, 3, 20);
  const std::vector<CurveSegment> segments = {{1, 0, 10}, {-1, 10, 20}, {1, 20, 40}};
  const std::vector<LoadingCycle> cycles = loading_cycles(e, s, segments);
  ASSERT_EQ(cycles.size(), 1u);
  const LoadingCycle& c = cycles[0];
  EXPECT_EQ(c.unloading_segment, 1u);
  EXPECT_DOUBLE_EQ(c.peak_strain, 0.01);
  EXPECT_DOUBLE_EQ(c.peak_deviator, 1);
  EXPECT_DOUBLE_EQ(c.residual_strain, 0.006);
  EXPECT_DOUBLE_EQ(c.residual_deviator, 0);
  EXPECT_NEAR(c.loading_slope, 100, 1e-9);
  EXPECT_NEAR(c.unloading_slope, 250, 1e-9);
  EXPECT_NEAR(c.reloading_slope, 500, 1e-9);
  EXPECT_NEAR(c.unloading_slope_end, 250, 1e-9);  // straight branches: the same at both ends
  EXPECT_NEAR(c.reloading_slope_end, 500, 1e-9);
  // The loop lies between the reloading line s = 500 (e - 0.006) above and the unloading line
  // s = 250 (e - 0.006) below, from e = 0.006 to 0.01: a triangle of base 0.004 and height 2 - 1.
  EXPECT_NEAR(c.dissipated_energy, 0.5 * 0.004 * 1, 1e-12);
}

TEST(LoadingCycles, HoldsBetweenBranchesAreSkippedAndAMissingReloadIsNaN) {
  std::vector<double> e{0}, s{0};
  branch(e, s, 0.01, 1, 10);
  branch(e, s, 0.01, 0.9, 3);  // a hold: the deviator relaxes at constant strain
  branch(e, s, 0.009, 0, 10);
  const std::vector<CurveSegment> segments = {{1, 0, 10}, {0, 10, 13}, {-1, 13, 23}};
  const std::vector<LoadingCycle> cycles = loading_cycles(e, s, segments);
  ASSERT_EQ(cycles.size(), 1u);
  EXPECT_DOUBLE_EQ(cycles[0].peak_deviator, 0.9);  // where the unloading began
  EXPECT_NEAR(cycles[0].unloading_slope, 900, 1e-9);
  EXPECT_TRUE(std::isnan(cycles[0].reloading_slope));
  EXPECT_TRUE(std::isnan(cycles[0].dissipated_energy));
}

TEST(LoadingCycles, AMonotonicCurveHasNoCycle) {
  std::vector<double> e{0}, s{0};
  branch(e, s, 0.01, 1, 10);
  EXPECT_TRUE(loading_cycles(e, s, {{1, 0, 10}}).empty());
}

}  // namespace
}  // namespace granulab
