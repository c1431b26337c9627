// The confinement step on its own (the crystal_confinement experiment): it is the very step the
// compression runs first (same steps, same final state, bit for bit), and the curve it records shows the
// approach to equilibrium the criterion accepts.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/experiments/crystal_compression/crystal_compression.h"
#include "engine/experiments/crystal_confinement/crystal_confinement.h"

namespace granulab {
namespace {

struct Rows : ResultSink {
  std::vector<std::vector<double>> rows;
  void curve_row(const std::vector<double>& values) override { rows.push_back(values); }
};

TEST(CrystalConfinement, IsTheConfinementOfTheCompressionAndRecordsItsApproach) {
  CrystalConfinementExperiment e;
  CrystalSampleParams& p = e.params;
  p.grain.edge_spheres = 4;
  p.grains_x = 4, p.rows_z = 8, p.layers_y = 4;
  p.confining_pressure = 30e3;
  Rows sink;
  e.run(sink, "");

  CrystalParams compression;
  static_cast<CrystalSampleParams&>(compression) = p;
  CrystalCompression reference(compression);
  const ConfinementReport c = reference.confine();
  ASSERT_TRUE(c.converged);

  // One row at the start and one per check (every membrane_interval steps), in order.
  ASSERT_EQ(sink.rows.size(), 1 + c.steps / std::uint64_t(p.membrane_interval));
  for (std::size_t k = 0; k < sink.rows.size(); ++k) EXPECT_EQ(sink.rows[k][0], double(k * p.membrane_interval));
  // The last row is the state the compression starts from: the same arithmetic, bit-identical.
  const std::vector<double>& last = sink.rows.back();
  EXPECT_EQ(last[0], double(c.steps));
  EXPECT_EQ(last[1], c.stress_top);
  EXPECT_EQ(last[2], c.stress_bottom);
  EXPECT_EQ(last[3], c.lateral_stress_x);
  EXPECT_EQ(last[4], c.lateral_stress_y);
  EXPECT_EQ(last[5], c.kinetic_elastic_ratio);
  // The criterion held at the last checks: walls within 1 % of p0, kinetic energy below 1e-4 of elastic.
  for (std::size_t k = sink.rows.size() - std::size_t(p.equilibrium_checks); k < sink.rows.size(); ++k) {
    EXPECT_NEAR(sink.rows[k][1], p.confining_pressure, 0.01 * p.confining_pressure);
    EXPECT_NEAR(sink.rows[k][2], p.confining_pressure, 0.01 * p.confining_pressure);
    EXPECT_LT(sink.rows[k][5], p.kinetic_tolerance);
  }
  // ... and did not at the start: the walls begin just touching the crystal, carrying nothing like p0.
  EXPECT_GT(std::abs(sink.rows.front()[1] - p.confining_pressure), 0.01 * p.confining_pressure);
}

}  // namespace
}  // namespace granulab
