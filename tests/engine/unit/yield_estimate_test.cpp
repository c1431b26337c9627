// The rigid-grain yield estimate (engine/analysis/yield_estimate.h, docs/model.md "Yield estimate") against closed
// forms derived by hand:
//  - cubes under compression with p0 on the sides: on a {100} plane of normal m the traction is
//    R = p0 m + (s1 - p0)(z . m) z; it slides once its angle to m reaches atan f. Along [1 1 0] (m = x, z . m =
//    1/sqrt2) that is (s1 - p0)/2 = f (p0 + (s1 - p0)/2): s1/p0 = (1 + f)/(1 - f); along [1 1 1] (z . m = 1/sqrt3)
//    sqrt2 (s1 - p0)/3 = f (p0 + (s1 - p0)/3): s1/p0 = (sqrt2 + 2f)/(sqrt2 - f). Along [0 0 1] no cube plane has a
//    shear traction, and every other plane's faces lock: no mechanism.
//  - FCC sheared on (1 1 1): the faces crossing the cut are the three {110} faces [1 1 0], [1 0 1], [0 1 1], each at
//    35.26 degrees to the plane. Along [-2 1 1] the layer rides on the edge of [1 1 0] and [1 0 1], [-1 1 1], which
//    rises at asin([-1 1 1] . [1 1 1] / 3) = asin(1/3) = 19.47 degrees; the two faces' normal forces (60 degrees
//    apart) sum to sqrt3 N along their bisector, normal to the edge, and their friction to 2 f N along it:
//    tau/sigma_n = tan(19.47 deg + atan(2f/sqrt3)). Along [2 -1 -1] it rides up the face [0 1 1] itself, whose dip is that direction: tan(35.26 deg
//    + atan f). (The values: 0.884 and 1.405 at f = 0.35.)
//  - HCP's basal cuts alternate A|B and B|A, whose three faces are turned by 60 degrees: one of them offers the edge
//    ride in either sense, so the basal shear is the same both ways, at FCC's edge value.
//  - cubes sheared on (1 0 0) slide at tau/sigma_n = f with no dilation.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/analysis/yield_estimate.h"

namespace granulab {
namespace {

const double kEdge = std::asin(1.0 / 3.0), kFace = std::atan(1 / std::sqrt(2.0));  // 19.47 and 35.26 degrees

TEST(YieldEstimate, CubesGiveCoulombsClosedForms) {
  for (double f : {0.2, 0.35}) {
    const YieldEstimate along_110 = compression_yield_estimate(LatticeType::sc, Vec3(1, 1, 0), f);
    ASSERT_TRUE(along_110.found);
    EXPECT_NEAR(along_110.axial_over_p0, (1 + f) / (1 - f), 1e-12);
    EXPECT_NEAR(along_110.shear_over_normal, f, 1e-12);
    EXPECT_NEAR(along_110.dilation_angle, 0, 1e-9);
    const YieldEstimate along_111 = compression_yield_estimate(LatticeType::sc, Vec3(1, 1, 1), f);
    ASSERT_TRUE(along_111.found);
    EXPECT_NEAR(along_111.axial_over_p0, (std::sqrt(2.0) + 2 * f) / (std::sqrt(2.0) - f), 1e-12);
    EXPECT_FALSE(compression_yield_estimate(LatticeType::sc, Vec3(0, 0, 1), f).found);
  }
  // The plane found is a cube plane, and the slip lies in it.
  const YieldEstimate e = compression_yield_estimate(LatticeType::sc, Vec3(1, 1, 0), 0.35);
  EXPECT_EQ(e.plane.size(), 3u);
  EXPECT_EQ(std::abs(e.plane[0]) + std::abs(e.plane[1]) + std::abs(e.plane[2]), 1);
  EXPECT_NEAR(e.slip.dot(e.plane_normal), 0, 1e-12);
}

TEST(YieldEstimate, FccShearOnItsClosePackedPlaneRidesAnEdgeOneWayAndAFaceTheOther) {
  for (double f : {0.2, 0.35}) {
    const YieldEstimate edge = shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(-2, 1, 1), f);
    const YieldEstimate face = shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(2, -1, -1), f);
    ASSERT_TRUE(edge.found && face.found);
    EXPECT_NEAR(edge.shear_over_normal, std::tan(kEdge + std::atan(2 * f / std::sqrt(3.0))), 1e-12);
    EXPECT_NEAR(edge.dilation_angle, kEdge * 180 / M_PI, 1e-9);
    EXPECT_EQ(edge.closed_faces, 2);
    EXPECT_NEAR(face.shear_over_normal, std::tan(kFace + std::atan(f)), 1e-12);
    EXPECT_NEAR(face.dilation_angle, kFace * 180 / M_PI, 1e-9);
    EXPECT_EQ(face.closed_faces, 1);
  }
  EXPECT_NEAR(shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(-2, 1, 1), 0.35).shear_over_normal, 0.884, 5e-4);
  EXPECT_NEAR(shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(2, -1, -1), 0.35).shear_over_normal, 1.405, 5e-4);
  // A symmetry-equivalent system gives the same: the 90 degree turn about [0 0 1] takes (1 1 1) [-2 1 1] to
  // (-1 1 1) [-1 -2 1].
  EXPECT_NEAR(shear_yield_estimate(LatticeType::fcc, {-1, 1, 1}, Vec3(-1, -2, 1), 0.35).shear_over_normal,
              shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(-2, 1, 1), 0.35).shear_over_normal, 1e-12);
  EXPECT_THROW(shear_yield_estimate(LatticeType::fcc, {1, 1, 1}, Vec3(1, 0, 0), 0.35), std::invalid_argument);
}

TEST(YieldEstimate, HcpBasalShearIsTheSameBothWays) {
  const double f = 0.35, edge = std::tan(kEdge + std::atan(2 * f / std::sqrt(3.0)));
  // [0 1 -1 0] in three indices is [1 2 0]; in the crystal frame it is along y.
  for (double sense : {1.0, -1.0}) {
    const YieldEstimate e = shear_yield_estimate(LatticeType::hcp, {0, 0, 1}, sense * Vec3(0, 1, 0), f);
    ASSERT_TRUE(e.found);
    EXPECT_NEAR(e.shear_over_normal, edge, 1e-12) << sense;
    EXPECT_EQ(e.plane_text, "(0 0 0 1)");
  }
  const YieldEstimate up = shear_yield_estimate(LatticeType::hcp, {0, 0, 1}, Vec3(1, 0, 0), f);
  const YieldEstimate down = shear_yield_estimate(LatticeType::hcp, {0, 0, 1}, Vec3(-1, 0, 0), f);
  EXPECT_NEAR(up.shear_over_normal, down.shear_over_normal, 1e-12);
  EXPECT_EQ(up.direction_text, "[2 -1 -1 0]");
}

TEST(YieldEstimate, CubesShearedOnACubeFaceSlideAtTheFrictionCoefficient) {
  for (double f : {0.2, 0.35}) {
    const YieldEstimate e = shear_yield_estimate(LatticeType::sc, {1, 0, 0}, Vec3(0, 1, 0), f);
    ASSERT_TRUE(e.found);
    EXPECT_NEAR(e.shear_over_normal, f, 1e-12);
    EXPECT_NEAR(e.dilation_angle, 0, 1e-9);
    EXPECT_EQ(e.direction_text, "[0 1 0]");
  }
}

TEST(YieldEstimate, LatticeIndicesOfPlanesAndDirections) {
  Indices d;
  ASSERT_TRUE(direction_indices(LatticeType::fcc, Vec3(2, 2, 4), 12, d));
  EXPECT_EQ(d, (Indices{1, 1, 2}));
  EXPECT_FALSE(direction_indices(LatticeType::sc, Vec3(1, std::sqrt(2.0), 0), 12, d));
  // HCP: the basal plane's normal is c; the prism plane (1 0 -1 0)'s normal is [2 1 0] of a1, a2 (= [1 0 -1 0]).
  EXPECT_EQ(normal_direction(LatticeType::hcp, {0, 0, 1}), (Indices{0, 0, 1}));
  EXPECT_EQ(normal_direction(LatticeType::hcp, {1, 0, 0}), (Indices{2, 1, 0}));
  EXPECT_EQ(normal_direction(LatticeType::fcc, {2, 2, 0}), (Indices{1, 1, 0}));
  EXPECT_NEAR(plane_normal(LatticeType::hcp, {1, 0, 0}).dot(Vec3(0, 1, 0).normalized()), 0.5, 1e-12);
}

}  // namespace
}  // namespace granulab
