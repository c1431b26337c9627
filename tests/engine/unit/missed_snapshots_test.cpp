// Snapshot strains a run never reached are named in a warning, not silently dropped (crystal_snapshot.h).
#include <gtest/gtest.h>

#include "engine/crystal/crystal_snapshot.h"

namespace granulab {
namespace {

GrainSnapshot at(double strain) {
  GrainSnapshot s;
  s.strain = strain;
  return s;
}

TEST(MissedSnapshots, TheStrainsNotReachedAreNamedWithTheLargestReached) {
  const std::vector<double> asked = {0.0, 0.01, 0.02, 0.04};
  EXPECT_EQ(missed_snapshots_warning(asked, {at(0), at(0.01), at(0.02), at(0.04)}, 0.05), "");
  EXPECT_EQ(missed_snapshots_warning(asked, {at(0), at(0.01)}, 0.015),
            "output.snapshot_strains 0.02, 0.04 were never reached, so no snapshot was taken there; the largest "
            "strain the run reached was 0.015");
  EXPECT_EQ(missed_snapshots_warning({0.05}, {}, 0.03),
            "output.snapshot_strains 0.05 was never reached, so no snapshot was taken there; the largest strain the "
            "run reached was 0.03");
  // A shear's snapshots may be labelled with either sense of the strain.
  EXPECT_EQ(missed_snapshots_warning({0.05}, {at(-0.05)}, 0.05), "");
}

}  // namespace
}  // namespace granulab
