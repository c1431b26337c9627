// The speed probe read again while the machine is quiet (server/machine_speed.h), with a probe and a clock of the
// test's own: a low first reading (a busy machine at start) gives way to the next quiet one, the best recent
// reading stands, old readings expire, a failed one changes nothing, and nothing is read while jobs run or
// before its time.
#include "server/machine_speed.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace granulab::server {
namespace {

using std::chrono::hours;
using std::chrono::minutes;
using std::chrono::seconds;

struct Fake {
  MachineSpeed::Clock::time_point now{};
  std::vector<double> next;  // the readings to come, in order (NaN: the probe throws)
  int taken = 0;
  MachineSpeed speed{0.5, [this] { return take(); }, [this] { return now; }};

  double take() {
    const double v = next.at(taken++);
    if (v != v) throw std::runtime_error("no crystal");
    return v;
  }
};

TEST(MachineSpeed, ALowReadingAtStartGivesWayToTheNextQuietOne) {
  Fake f;
  f.next = {0.08, 0.3, 0.25};
  f.speed.measure();  // the daemon's, at start, on a busy machine
  EXPECT_DOUBLE_EQ(f.speed.probe(), 0.08);
  EXPECT_FALSE(f.speed.refresh(true)) << "not due yet";
  f.now += seconds(30);
  EXPECT_FALSE(f.speed.refresh(false)) << "a job runs: no reading";
  EXPECT_TRUE(f.speed.refresh(true));
  EXPECT_DOUBLE_EQ(f.speed.probe(), 0.3);
  // A later reading that a passing load slowed does not lower it: the best recent one stands.
  f.now += minutes(1);
  EXPECT_TRUE(f.speed.refresh(true));
  EXPECT_DOUBLE_EQ(f.speed.probe(), 0.3);
  EXPECT_EQ(f.taken, 3);
}

TEST(MachineSpeed, ReadingsComeAtDoublingIntervalsUpToFiveMinutes) {
  Fake f;
  f.next = std::vector<double>(20, 1.0);
  f.speed.measure();
  std::vector<long> waited;  // seconds from one reading to the next, polled every second
  long since = 0;
  while (waited.size() < 7) {
    f.now += seconds(1), ++since;
    if (f.speed.refresh(true)) waited.push_back(since), since = 0;
  }
  EXPECT_EQ(waited, (std::vector<long>{30, 60, 120, 240, 300, 300, 300}));
}

TEST(MachineSpeed, OldReadingsExpireSoASlowerMachineIsSeenAndAFailureChangesNothing) {
  Fake f;
  f.next = {2.0, NAN, 0.0, 1.0, 1.1};
  f.speed.measure();
  f.now += minutes(1);
  EXPECT_TRUE(f.speed.refresh(true));  // throws: no reading
  f.now += minutes(2);
  EXPECT_TRUE(f.speed.refresh(true));  // 0: no reading
  EXPECT_DOUBLE_EQ(f.speed.probe(), 2.0);
  EXPECT_EQ(f.speed.readings(), 3);
  // Six hours of jobs: no reading, and the last one still stands (the probe never falls back to nothing).
  f.now += hours(6);
  EXPECT_DOUBLE_EQ(f.speed.probe(), 2.0);
  EXPECT_TRUE(f.speed.refresh(true));
  EXPECT_DOUBLE_EQ(f.speed.probe(), 1.0) << "the 2.0 reading is over 6 hours older than the latest";
  f.now += minutes(5);
  EXPECT_TRUE(f.speed.refresh(true));
  EXPECT_DOUBLE_EQ(f.speed.probe(), 1.1);
}

TEST(MachineSpeed, OffMeansNoReadingAndNoWait) {
  int taken = 0;
  MachineSpeed off(
      0, [&] { return ++taken, 1.0; }, [] { return MachineSpeed::Clock::time_point{}; });
  off.measure();
  EXPECT_FALSE(off.refresh(true));
  EXPECT_EQ(off.probe(), 0);
  EXPECT_EQ(taken, 0);
  Fake f;
  EXPECT_FALSE(f.speed.refresh(true)) << "the first reading is the daemon's, at start";
}

}  // namespace
}  // namespace granulab::server
