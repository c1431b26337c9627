// The dry run's speed (server/speed_model.h): the benchmark table at a job's size, scaled by how this
// server's most similar finished jobs ran against it.
#include "server/speed_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace granulab::server {
namespace {

const RunSize kSmallCrystal{"crystal_compression", 23760, 216, 2};
const RunSize kLargeCrystal{"crystal_compression", 841536, 864, 2};

TEST(SpeedModel, WithoutHistoryItIsTheTableAndSaysSo) {
  const SpeedEstimate s = estimate_speed(kSmallCrystal, {});
  EXPECT_DOUBLE_EQ(s.sphere_steps_per_second, benchmark_speed(kSmallCrystal));
  EXPECT_NE(s.basis.find("no finished jobs"), std::string::npos) << s.basis;
}

TEST(SpeedModel, AFreshServerScalesTheTableByItsSpeedProbe) {
  // A machine that ran the probe at 1.5x the table's machine is expected 1.5x faster at every size.
  const double probe = 1.5 * table_machine_probe();
  for (const RunSize& job : {kSmallCrystal, kLargeCrystal}) {
    const SpeedEstimate s = estimate_speed(job, {}, probe);
    EXPECT_NEAR(s.sphere_steps_per_second, 1.5 * benchmark_speed(job), 1e-9 * s.sphere_steps_per_second);
    EXPECT_NE(s.basis.find("speed probe"), std::string::npos) << s.basis;
    EXPECT_NE(s.basis.find("1.50"), std::string::npos) << s.basis;
  }
  // Once a job has finished here, its measured speed rules and the probe no longer counts.
  const SpeedEstimate s = estimate_speed(kLargeCrystal, {{kSmallCrystal, 0.6 * benchmark_speed(kSmallCrystal)}}, probe);
  EXPECT_NEAR(s.sphere_steps_per_second, 0.6 * benchmark_speed(kLargeCrystal), 1e-9 * s.sphere_steps_per_second);
}

TEST(SpeedModel, ARunOfTheSameSizeGivesItsOwnSpeed) {
  const SpeedEstimate s = estimate_speed(kSmallCrystal, {{kSmallCrystal, 3.0e7}});
  EXPECT_NEAR(s.sphere_steps_per_second, 3.0e7, 1e-6 * 3.0e7);
}

TEST(SpeedModel, ASlowerMachineScalesTheTableAtOtherSizes) {
  // This server ran a small crystal at 0.6 of the table: a large one is expected at 0.6 of the table too.
  const double small = 0.6 * benchmark_speed(kSmallCrystal);
  const SpeedEstimate s = estimate_speed(kLargeCrystal, {{kSmallCrystal, small}});
  EXPECT_NEAR(s.sphere_steps_per_second, 0.6 * benchmark_speed(kLargeCrystal), 1e-9 * s.sphere_steps_per_second);
  EXPECT_NE(s.basis.find("0.60"), std::string::npos) << s.basis;
}

TEST(SpeedModel, TheSameExperimentAndTheNearestSizesCountFirst) {
  const RunSize cubes{"two_cube_sliding", 976, 2, 2};
  const RunSize medium{"crystal_compression", 95040, 864, 2};
  // Another experiment's runs are ignored while the job's own has any; of its own, the 5 nearest count.
  std::vector<MeasuredRun> history{{cubes, 0.1 * benchmark_speed(cubes)}};
  for (int k = 0; k < 3; ++k) history.push_back({medium, 0.8 * benchmark_speed(medium)});
  for (int k = 0; k < 3; ++k) history.push_back({kLargeCrystal, 1.2 * benchmark_speed(kLargeCrystal)});
  // A small crystal is nearer the medium ones (3 of its 5 nearest): their 0.8 is the median.
  EXPECT_NEAR(estimate_speed(kSmallCrystal, history).sphere_steps_per_second,
              0.8 * benchmark_speed(kSmallCrystal), 1e-9 * benchmark_speed(kSmallCrystal));
}

TEST(SpeedModel, TheTableGrowsWithThreadsAndIsExactAtItsPoints) {
  RunSize one = kSmallCrystal;
  one.threads = 1;
  EXPECT_NEAR(benchmark_speed(one) / benchmark_speed(kSmallCrystal), std::pow(0.5, 0.85), 1e-12);
  // Between two points the table lies between their speeds.
  const RunSize between{"crystal_compression", 50000, 432, 2};
  const double lo = std::min(benchmark_speed(kSmallCrystal), benchmark_speed({"", 95040, 864, 2}));
  const double hi = std::max(benchmark_speed(kSmallCrystal), benchmark_speed({"", 95040, 864, 2}));
  EXPECT_GE(benchmark_speed(between), lo);
  EXPECT_LE(benchmark_speed(between), hi);
}

}  // namespace
}  // namespace granulab::server
