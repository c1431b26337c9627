// Stick-slip events (engine/analysis/stress_drops.h) on synthetic signals: a sawtooth of three drops with wiggles
// below the threshold gives exactly those three drops, each from its peak to its trough (strain, size, duration);
// wiggles do not start or split one; a drop under way when the loading stretch ends is closed at its trough; after a
// close the running peak is forgotten, so an unloading is no event.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/analysis/stress_drops.h"

namespace granulab {
namespace {

constexpr double kDt = 1e-6;

std::vector<StressDrop> feed(StressDropTracker& t, const std::vector<double>& signal, std::uint64_t first = 0) {
  std::vector<StressDrop> out;
  for (std::size_t k = 0; k < signal.size(); ++k) {
    StressDrop d;
    const std::uint64_t step = first + k;
    if (t.add({step, step * kDt, step * 1e-5, signal[k]}, d)) out.push_back(d);
  }
  return out;
}

// Rises 100 Pa a step for 100 steps, then falls to `drop` below its top over 10 steps; a 3 Pa wiggle throughout.
std::vector<double> sawtooth(const std::vector<double>& drops) {
  std::vector<double> s;
  double v = 0;
  for (double drop : drops) {
    for (int k = 0; k < 100; ++k) s.push_back(v += 100);
    for (int k = 0; k < 10; ++k) s.push_back(v -= drop / 10);
  }
  for (int k = 0; k < 100; ++k) s.push_back(v += 100);
  for (std::size_t k = 0; k < s.size(); ++k) s[k] += 3 * std::sin(1.3 * double(k));
  return s;
}

TEST(StressDrops, ASawtoothsDropsAreFoundFromPeakToTrough) {
  StressDropTracker t;
  t.threshold = 500;
  const std::vector<double> sizes = {2000, 800, 5000};
  const std::vector<StressDrop> d = feed(t, sawtooth(sizes));
  ASSERT_EQ(d.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t top = 110 * k + 99, bottom = top + 10;
    EXPECT_NEAR(d[k].size, sizes[k], 6.0 + 1e-9) << k;  // the wiggle at both ends, at most 2 x 3 Pa
    EXPECT_NEAR(d[k].strain, top * 1e-5, 1.01e-5) << k;
    EXPECT_NEAR(d[k].end_strain, bottom * 1e-5, 1.01e-5) << k;
    EXPECT_NEAR(d[k].duration, 10 * kDt, 2.01 * kDt) << k;
    EXPECT_EQ(d[k].steps, std::uint64_t(std::llround(d[k].duration / kDt)));
  }
  // The same with a threshold above the middle drop: two.
  StressDropTracker high;
  high.threshold = 1000;
  EXPECT_EQ(feed(high, sawtooth(sizes)).size(), 2u);
  // Wiggles alone are nothing.
  StressDropTracker calm;
  calm.threshold = 10;
  std::vector<double> wiggle(1000);
  for (std::size_t k = 0; k < wiggle.size(); ++k) wiggle[k] = 1e5 + 3 * std::sin(1.3 * double(k));
  EXPECT_TRUE(feed(calm, wiggle).empty());
}

TEST(StressDrops, ADropUnderWayEndsWithTheStretchAndAnUnloadingIsNone) {
  StressDropTracker t;
  t.threshold = 500;
  std::vector<double> down;
  for (int k = 0; k < 100; ++k) down.push_back(100.0 * k);
  for (int k = 0; k < 20; ++k) down.push_back(9900 - 200.0 * k);  // falls 3,800 Pa and is still falling
  EXPECT_TRUE(feed(t, down).empty());
  StressDrop d;
  ASSERT_TRUE(t.close(d));
  EXPECT_DOUBLE_EQ(d.size, 3800);
  EXPECT_DOUBLE_EQ(d.peak, 9900);
  // The stretch is over: an unloading that follows (never fed while the platen releases) would start afresh, and
  // a new stretch starts from its first sample, not from the old peak.
  EXPECT_FALSE(t.close(d));
  std::vector<double> again;
  for (int k = 0; k < 50; ++k) again.push_back(6000 + 10.0 * k);
  EXPECT_TRUE(feed(t, again, 200).empty());
  EXPECT_FALSE(t.close(d));
}

}  // namespace
}  // namespace granulab
