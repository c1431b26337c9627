// The DIC-like map of a snapshot's front face (engine/analysis/dic_map.h), on synthetic snapshots of an FCC block of
// sites (cubic axes, 6 x 4 x 8 cells, layers normal to y a/2 apart):
//  - a uniform deformation x = F X (stretch, shear and a turn, with out-of-plane terms) gives a uniform map equal to
//    it: at every node measured the in-plane Green-Lagrange strain of F to 1e-12 and the displacement
//    (F - I) X of the node to 1e-15 m;
//  - a rigid rotation gives zero strain;
//  - nodes in a hole (beyond a neighbour distance of every grain) are NaN, as are the few corner nodes whose subset
//    holds fewer than three grains; a grid too fine or a step of 0 is refused.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/analysis/dic_map.h"
#include "engine/analysis/grain_kinematics.h"

namespace granulab {
namespace {

constexpr double kA = 0.01;

GrainSnapshot deformed_block(const Mat3& F, bool hole = false) {
  const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<Vec3> ref;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 8; ++k)
        for (const Vec3& b : basis) {
          const Vec3 x = kA * (Vec3(i, j, k) + b);
          // The hole: the front face's grains within 1.2 a of (3a, 0, 4a).
          if (hole && x.y() < 0.1 * kA && std::hypot(x.x() - 3 * kA, x.z() - 4 * kA) < 1.2 * kA) continue;
          ref.push_back(x);
        }
  GrainSnapshot s;
  s.grain_size = kA;
  s.layer_spacing = kA / 2;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    s.id.push_back(GrainId(std::uint32_t(i)));
    s.position.push_back(F * ref[i]);
    s.displacement.push_back(F * ref[i] - ref[i]);
    s.orientation.push_back(Quat::Identity());
  }
  for (const auto& [a, b] : neighbour_pairs(ref, 1.1 * kA / std::sqrt(2.0)))
    s.interfaces.push_back({GrainId(std::uint32_t(a)), GrainId(std::uint32_t(b))});
  return s;
}

TEST(DicMap, AUniformDeformationGivesAUniformMapEqualToIt) {
  Mat3 F;
  F << 1.01, 0.004, 0.003,  //
      0.002, 0.995, -0.001,  //
      -0.002, 0.001, 0.98;
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Mat3::Identity());
  const GrainSnapshot s = deformed_block(F);
  const DicMap m = dic_map(s, 0.25 * kA);
  EXPECT_EQ(m.grains, 6u * 8u * 2u);  // two sites per cell on y = 0
  EXPECT_DOUBLE_EQ(m.step, 0.25 * kA);
  ASSERT_GT(m.nx, 20);
  ASSERT_GT(m.nz, 28);
  EXPECT_NEAR(m.y, 0.0, 1e-15);
  std::size_t measured = 0;
  for (int k = 0; k < m.nz; ++k)
    for (int i = 0; i < m.nx; ++i) {
      const std::size_t n = std::size_t(k) * m.nx + i;
      if (std::isnan(m.exx[n])) continue;
      ++measured;
      EXPECT_NEAR(m.exx[n], E(0, 0), 1e-12) << i << " " << k;
      EXPECT_NEAR(m.ezz[n], E(2, 2), 1e-12);
      EXPECT_NEAR(m.exz[n], E(0, 2), 1e-12);
      EXPECT_NEAR(m.gamma_max[n], std::sqrt(0.25 * std::pow(E(0, 0) - E(2, 2), 2) + E(0, 2) * E(0, 2)), 1e-12);
      const Vec3 X(m.x0 + i * m.step, m.y, m.z0 + k * m.step);
      const Vec3 u = (F - Mat3::Identity()) * X;
      EXPECT_NEAR(m.ux[n], u.x(), 1e-15);
      EXPECT_NEAR(m.uy[n], u.y(), 1e-15);
      EXPECT_NEAR(m.uz[n], u.z(), 1e-15);
    }
  // The nodes span the face's grain centres. At the corners a subset holds fewer than three grains, as a DIC subset
  // hanging off the sample does: those few are blank, every other node is measured.
  EXPECT_GT(double(measured), 0.98 * m.nx * m.nz);
}

TEST(DicMap, ARigidRotationHasNoStrain) {
  const Mat3 R = Eigen::AngleAxisd(0.3, Vec3(1, 2, -1).normalized()).toRotationMatrix();
  const DicMap m = dic_map(deformed_block(R), 0.5 * kA);
  std::size_t measured = 0;
  for (std::size_t n = 0; n < m.exx.size(); ++n) {
    if (std::isnan(m.exx[n])) continue;
    ++measured;
    EXPECT_NEAR(m.exx[n], 0, 1e-12);
    EXPECT_NEAR(m.ezz[n], 0, 1e-12);
    EXPECT_NEAR(m.exz[n], 0, 1e-12);
  }
  EXPECT_GT(double(measured), 0.9 * double(m.exx.size()));
}

TEST(DicMap, AHoleInTheFaceIsLeftBlankAndTheStepIsBounded) {
  const DicMap m = dic_map(deformed_block(Mat3::Identity(), true), 0.25 * kA);
  // The node at the hole's centre: no grain within a neighbour distance.
  const int i = int(std::lround((3 * kA - m.x0) / m.step)), k = int(std::lround((4 * kA - m.z0) / m.step));
  EXPECT_TRUE(std::isnan(m.exx[std::size_t(k) * m.nx + i]));
  // ... and one between the hole and the face's corner is measured.
  const int i2 = int(std::lround((1.5 * kA - m.x0) / m.step)), k2 = int(std::lround((1.5 * kA - m.z0) / m.step));
  EXPECT_FALSE(std::isnan(m.exx[std::size_t(k2) * m.nx + i2]));
  // Grains that also move non-affinely (by up to 1e-3 of a grain) give strains of that order next to the hole too:
  // a subset whose grains hardly spread across (its rim) is left blank rather than amplifying their noise.
  GrainSnapshot noisy = deformed_block(Mat3::Identity(), true);
  std::uint32_t seed = 12345;
  for (std::size_t i = 0; i < noisy.id.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      seed = seed * 1664525u + 1013904223u;
      const double u = 1e-3 * kA * (double(seed >> 8) / double(1u << 24) - 0.5);
      noisy.position[i][k] += u, noisy.displacement[i][k] += u;
    }
  const DicMap rough = dic_map(noisy, 0.1 * kA);
  double worst = 0;
  for (double g : rough.gamma_max)
    if (!std::isnan(g)) worst = std::max(worst, g);
  EXPECT_LT(worst, 0.01);  // 1e-3 a of noise over subsets ~a across: ~1e-3, a decade of margin
  EXPECT_GT(worst, 0);
  EXPECT_THROW(dic_map(deformed_block(Mat3::Identity()), 1e-6 * kA), std::invalid_argument);
  EXPECT_THROW(dic_map(deformed_block(Mat3::Identity()), 0), std::invalid_argument);
}

// A face whose grains all but lie on one line (a hole's rim, a single row) cannot give a gradient across it: such
// subsets are left blank, not fitted with the grains' small motions divided by their tiny spread.
TEST(DicMap, GrainsAlmostOnALineGiveNoGradient) {
  const double D = kA / std::sqrt(2.0);
  GrainSnapshot s;
  s.grain_size = kA;
  s.layer_spacing = kA / 2;
  for (int i = 0; i < 11; ++i) {
    const Vec3 ref(i * D, 0, i == 5 ? 1e-4 * D : 0.0);  // one grain a hair off the row
    const Vec3 u(0, 0, i == 5 ? 1e-4 * D : 0.0);         // ... moving by as much again
    s.id.push_back(GrainId(std::uint32_t(i)));
    s.position.push_back(ref + u);
    s.displacement.push_back(u);
    s.orientation.push_back(Quat::Identity());
    if (i > 0) s.interfaces.push_back({GrainId(std::uint32_t(i - 1)), GrainId(std::uint32_t(i))});
  }
  const DicMap m = dic_map(s, 0.5 * D);
  for (std::size_t n = 0; n < m.gamma_max.size(); ++n)
    EXPECT_TRUE(std::isnan(m.gamma_max[n])) << n << ": " << m.gamma_max[n];
}

}  // namespace
}  // namespace granulab
