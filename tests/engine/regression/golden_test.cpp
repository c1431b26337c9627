// Golden regression data: a small crystal confined and compressed, its whole curve and the final
// poses of a few grains, stored in tests/engine/regression/golden/crystal_small.json with the
// tolerance they must be met to. A change to the kernel, the integrator, the bag or the loading that
// shifts the physics fails here, not in a reader's figure.
//
// The tolerance is set from the run's own sensitivity (ChaosIsBelowTheToleranceAndPhysicsAbove): a
// granular packing amplifies round-off, so results are compared to 1e-7 of their scale, about 10,000x
// the spread that a 1e-15 change of the time step leaves after the same run (measured 1.4e-11; a
// different summation order or vector width does the same), and far below a physical change (a 1e-4
// change of the friction coefficient moves them by 2e-2).
//
// To regenerate after a change that is meant to move the physics (and say so in the commit):
//   GRANULAB_WRITE_GOLDEN=1 build/tests/engine_regression_tests --gtest_filter='*Golden*'
// (the baseline kernel writes it; every kernel is compared to it)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/contact/pair_kernel.h"
#include "engine/experiments/crystal_compression/crystal_compression.h"
#include "engine/framework/energy_report.h"

namespace granulab {
namespace {

const std::string kGoldenFile = std::string(GRANULAB_SOURCE_DIR) + "/tests/engine/regression/golden/crystal_small.json";
constexpr double kTolerance = 1e-7;  // relative to each quantity's scale (see above)
const std::vector<std::size_t> kTrackedGrains = {0, 17, 35};

// 3 x 6 x 2 grains of N_e = 4 at 30 kPa, confined, then 1 % of strain at R = 1e-4, through
// the elastic part and the first slips. Any thread count gives the same answer (step_test).
CrystalParams golden_params(double friction = 0.35, double time_step_factor = 0.3) {
  CrystalParams p;
  p.grain.edge_spheres = 4;
  p.grains_x = 3, p.rows_z = 6, p.layers_y = 2;
  p.confining_pressure = 30e3;
  p.material.friction = friction;
  p.time_step_factor = time_step_factor;
  p.max_strain = 0.01;
  p.rate_number = 1e-4;
  p.curve_points = 40;
  p.snapshot_strains = {};
  return p;
}

struct Record {
  std::vector<std::vector<double>> curve;
  std::vector<Vec3> position;
  std::vector<Quat> orientation;
  std::uint64_t steps = 0;
};

Record run(const CrystalParams& p) {
  CrystalCompression crystal(p);
  const CrystalResult r = crystal.run();
  Record out;
  for (const CrystalRow& row : r.curve) out.curve.push_back(row.values());
  for (std::size_t b : kTrackedGrains) {
    out.position.push_back(crystal.world().bodies().position[b]);
    out.orientation.push_back(crystal.world().bodies().orientation[b]);
  }
  out.steps = r.run.steps;
  return out;
}

// Scale of each curve column (CrystalRow::columns()), every one of them: strains by max_strain, stresses
// by p0, the energy ratio by 1, counts by the contacts at the start, the program segment by 1 (any change of
// it is a failure), the energies (J) by the platens' work over the run.
std::vector<double> column_scales(const Record& r, const CrystalParams& p) {
  const double contacts = r.curve.front()[8];
  const double work = std::abs(r.curve.back()[11]);
  std::vector<double> scales = {p.max_strain,
                                      p.confining_pressure,
                                      p.confining_pressure,
                                      p.confining_pressure,
                                      p.max_strain,
                                      p.max_strain,
                                      p.confining_pressure,
                                      1.0,
                                      contacts,
                                      contacts,
                                      1.0};
  scales.insert(scales.end(), energy_columns().size(), work);
  EXPECT_EQ(scales.size(), CrystalRow::columns().size()) << "a curve column without a scale is never compared";
  return scales;
}

/// The largest difference between two records, each quantity over its scale; positions over the grain
/// size, orientations (unit quaternions) as they are. Infinite if their shapes differ.
double largest_difference(const Record& a, const Record& b, const CrystalParams& p) {
  if (a.curve.size() != b.curve.size() || a.position.size() != b.position.size()) return INFINITY;
  const std::vector<double> scale = column_scales(b, p);
  for (std::size_t i = 0; i < a.curve.size(); ++i)
    if (a.curve[i].size() != scale.size() || b.curve[i].size() != scale.size()) return INFINITY;
  double worst = 0;
  // A NaN anywhere is the worst difference (std::max would skip it).
  auto worse = [&worst](double d) { worst = d <= worst ? worst : (d == d ? d : INFINITY); };
  for (std::size_t i = 0; i < a.curve.size(); ++i)
    for (std::size_t c = 0; c < scale.size(); ++c) worse(std::abs(a.curve[i][c] - b.curve[i][c]) / scale[c]);
  for (std::size_t g = 0; g < a.position.size(); ++g) {
    worse((a.position[g] - b.position[g]).norm() / p.grain.size);
    // q and -q are the same rotation.
    const double dq = std::min((a.orientation[g].coeffs() - b.orientation[g].coeffs()).norm(),
                               (a.orientation[g].coeffs() + b.orientation[g].coeffs()).norm());
    worse(dq);
  }
  return worst;
}

nlohmann::json to_json(const Record& r) {
  nlohmann::json j;
  j["about"] =
      "granulab golden data: tests/engine/regression/golden_test.cpp (crystal 3 x 6 x 2, N_e = 4, "
      "30 kPa, 1 % strain at R = 1e-4); compared to a relative tolerance of 1e-7 of each quantity's scale";
  j["steps"] = r.steps;
  j["curve"] = r.curve;
  j["grains"] = nlohmann::json::array();
  for (std::size_t g = 0; g < r.position.size(); ++g)
    j["grains"].push_back({{"body", kTrackedGrains[g]},
                           {"position_m", {r.position[g].x(), r.position[g].y(), r.position[g].z()}},
                           {"orientation_wxyz",
                            {r.orientation[g].w(), r.orientation[g].x(), r.orientation[g].y(), r.orientation[g].z()}}});
  return j;
}

Record from_json(const nlohmann::json& j) {
  Record r;
  r.steps = j.at("steps").get<std::uint64_t>();
  r.curve = j.at("curve").get<std::vector<std::vector<double>>>();
  for (const auto& g : j.at("grains")) {
    const auto x = g.at("position_m").get<std::vector<double>>();
    const auto q = g.at("orientation_wxyz").get<std::vector<double>>();
    r.position.emplace_back(x.at(0), x.at(1), x.at(2));
    r.orientation.emplace_back(q.at(0), q.at(1), q.at(2), q.at(3));
  }
  return r;
}

// Every contact kernel of the binary (pair_kernels()) meets the same data: kernels differ in their sums' rounding
// only. Those this CPU lacks skip, and say so.
class GoldenKernel : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenKernel, SmallCrystalMatchesItsStoredCurveAndPoses) {
  for (const PairKernelInfo& k : pair_kernels())
    if (k.name == GetParam() && !k.runs_here) GTEST_SKIP() << "this CPU lacks the instructions of kernel " << k.name;
  CrystalParams p = golden_params();
  p.kernel = GetParam();
  const Record now = run(p);
  if (std::getenv("GRANULAB_WRITE_GOLDEN") && GetParam() == kBaselineKernel) {
    std::ofstream(kGoldenFile) << to_json(now).dump(1) << "\n";
    GTEST_SKIP() << "wrote " << kGoldenFile;
  }
  std::ifstream in(kGoldenFile);
  ASSERT_TRUE(in) << "missing " << kGoldenFile;
  const Record golden = from_json(nlohmann::json::parse(in));
  EXPECT_EQ(now.steps, golden.steps);
  ASSERT_EQ(now.curve.size(), golden.curve.size());
  const double worst = largest_difference(now, golden, p);
  EXPECT_LE(worst, kTolerance) << "the small crystal moved from its golden data; if the physics is meant to change, "
                                  "regenerate it (see the top of golden_test.cpp)";
  std::printf("%s kernel: largest difference from the golden data: %.3g of scale (tolerance %.0e)\n",
              GetParam().c_str(), worst, kTolerance);
}

std::vector<std::string> kernel_names() {
  std::vector<std::string> names;
  for (const PairKernelInfo& k : pair_kernels()) names.push_back(k.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Kernels, GoldenKernel, ::testing::ValuesIn(kernel_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

// The tolerance sits between round-off and physics: a 1e-15 change of dt stays far below it, a 1e-4
// change of the friction coefficient far above it.
TEST(Golden, ChaosIsBelowTheToleranceAndPhysicsAbove) {
  const Record base = run(golden_params());
  const double chaos = largest_difference(run(golden_params(0.35, 0.3 * (1 + 1e-15))), base, golden_params());
  const double physics = largest_difference(run(golden_params(0.35 * (1 + 1e-4))), base, golden_params());
  std::printf("round-off: %.3g, friction + 1e-4: %.3g (tolerance %.0e)\n", chaos, physics, kTolerance);
  EXPECT_LT(chaos, kTolerance / 100);
  EXPECT_GT(physics, kTolerance * 10);
}

}  // namespace
}  // namespace granulab
