// Snapshot kinematics (docs/model.md, "Snapshots and local strain") on an FCC block of sites, 4 x 4 x 4 cells:
//  - an imposed affine deformation x -> F x gives every grain with a full neighbourhood the imposed Green-Lagrange
//    strain E = (F^T F - I)/2 to 1e-12 and D^2_min = 0 (to 1e-24 of the neighbour distance squared);
//  - a rigid rotation gives zero strain, D^2_min = 0, and each grain turned with it has the imposed angle and axis
//    as its misorientation to 1e-9;
//  - one grain displaced off the affine field makes its neighbourhood non-affine: D^2_min > 0 there and for it.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/analysis/grain_kinematics.h"

namespace granulab {
namespace {

constexpr double kA = 0.01;  // cubic cell (m)

std::vector<Vec3> fcc_block(int cells) {
  const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<Vec3> out;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (const Vec3& b : basis) out.push_back(kA * (Vec3(i, j, k) + b));
  return out;
}

// The sites with all 12 neighbours in the block.
std::vector<std::size_t> inner(const std::vector<Vec3>& x, const std::vector<BodyPair>& pairs) {
  std::vector<int> count(x.size(), 0);
  for (const auto& [a, b] : pairs) ++count[a], ++count[b];
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (count[i] == 12) out.push_back(i);
  return out;
}

TEST(GrainKinematics, AnAffineDeformationIsItsOwnStrainWithNoResidual) {
  const std::vector<Vec3> ref = fcc_block(4);
  const auto pairs = neighbour_pairs(ref, 1.1 * kA / std::sqrt(2.0));
  Mat3 f;
  f << 1.002, 0.003, -0.001, 0.0005, 0.998, 0.002, -0.0015, 0.001, 1.004;
  std::vector<Vec3> cur;
  for (const Vec3& x : ref) cur.push_back(f * x + Vec3(1e-3, -2e-3, 5e-4));
  const Mat3 e = 0.5 * (f.transpose() * f - Mat3::Identity());
  const auto strains = local_strains(ref, cur, pairs);
  const auto full = inner(ref, pairs);
  ASSERT_GT(full.size(), 20u);
  const double l2 = kA * kA / 2;
  for (std::size_t i : full) {
    EXPECT_LT((strains[i].green_lagrange - e).cwiseAbs().maxCoeff(), 1e-12) << i;
    EXPECT_LT(strains[i].d2min, 1e-24 * l2) << i;
  }
}

TEST(GrainKinematics, ARigidRotationIsNoStrainAndItsOwnMisorientation) {
  const std::vector<Vec3> ref = fcc_block(4);
  const auto pairs = neighbour_pairs(ref, 1.1 * kA / std::sqrt(2.0));
  const Vec3 axis = Vec3(1, -2, 0.5).normalized();
  const double angle = 37.0;
  const Quat turn(Eigen::AngleAxisd(angle * M_PI / 180, axis));
  std::vector<Vec3> cur;
  for (const Vec3& x : ref) cur.push_back(turn * x);
  const auto strains = local_strains(ref, cur, pairs);
  for (std::size_t i : inner(ref, pairs)) {
    EXPECT_LT(strains[i].green_lagrange.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(strains[i].d2min, 1e-24 * kA * kA);
  }
  // Each grain turned with the block, from orientations of its own.
  for (const Quat& start : {Quat::Identity(), Quat(Eigen::AngleAxisd(1.1, Vec3(0, 1, 1).normalized())),
                            Quat(Eigen::AngleAxisd(3.0, Vec3::UnitX()))}) {
    const Misorientation m = misorientation(start, turn * start);
    EXPECT_NEAR(m.angle, angle, 1e-9);
    EXPECT_LT((m.axis - axis).norm(), 1e-9);
  }
  const Misorientation none = misorientation(turn, turn);
  EXPECT_NEAR(none.angle, 0, 1e-9);
  EXPECT_EQ(none.axis, Vec3::Zero());
  // More than half a turn reads as the shorter way round.
  const Misorientation back = misorientation(Quat::Identity(), Quat(Eigen::AngleAxisd(250 * M_PI / 180, axis)));
  EXPECT_NEAR(back.angle, 110, 1e-9);
  EXPECT_LT((back.axis + axis).norm(), 1e-9);
}

TEST(GrainKinematics, AGrainOffTheAffineFieldIsNonAffine) {
  const std::vector<Vec3> ref = fcc_block(4);
  const auto pairs = neighbour_pairs(ref, 1.1 * kA / std::sqrt(2.0));
  const auto full = inner(ref, pairs);
  const std::size_t moved = full[full.size() / 2];
  std::vector<Vec3> cur = ref;
  cur[moved] += Vec3(2e-5, 0, 0);
  const auto strains = local_strains(ref, cur, pairs);
  EXPECT_GT(strains[moved].d2min, 1e-12);
  std::size_t affected = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) affected += strains[i].d2min > 1e-14;
  EXPECT_EQ(affected, 13u);  // the grain and its 12 neighbours
}

}  // namespace
}  // namespace granulab
