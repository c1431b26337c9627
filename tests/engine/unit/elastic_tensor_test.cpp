// The affine face-spring tensor and the tensor algebra (docs/derivations/affine_stiffness.md):
//  - the general sum over the grain's faces against the closed forms derived by hand for each lattice, to 1e-9
//    (exact sums; what is tested is the faces, their sphere counts, the branch lengths, the cell volumes and HCP's
//    turned B grains);
//  - rotations: a cubic tensor is unchanged by a quarter turn about a cube axis, any rotation and its inverse give
//    the tensor back, and Young's modulus along a direction does not depend on the frame it is computed in;
//  - Young's modulus against the cubic closed forms along [1 0 0], [1 1 0] and [1 1 1], and an isotropic tensor's E.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/analysis/elastic_tensor.h"
#include "engine/crystal/face_springs.h"
#include "engine/experiments/crystal_stiffness/crystal_stiffness.h"
#include "engine/model/model.h"

namespace granulab {
namespace {

struct Springs {
  double kn, kt, a;
  std::vector<FaceSpring> faces;
};

Springs springs_of(LatticeType lattice, int edge_spheres) {
  CrystalSampleParams p;
  p.lattice = lattice;
  p.grain.shape = grain_shape(lattice);
  p.grain.edge_spheres = edge_spheres;
  const GrainTemplate grain(p.grain);
  const ContactLaw law = contact_law(grain, p.material);
  return {law.normal_stiffness, law.tangential_stiffness, p.grain.size, face_springs(grain)};
}

Voigt prediction(LatticeType lattice, int edge_spheres) {
  CrystalSampleParams p;
  p.lattice = lattice;
  p.grain.shape = grain_shape(lattice);
  p.grain.edge_spheres = edge_spheres;
  return affine_prediction(p);
}

void expect_near_relative(double measured, double expected, double tolerance, const char* what) {
  EXPECT_NEAR(measured, expected, tolerance * std::abs(expected)) << what;
}

// Every face of FCC's rhombic dodecahedron holds the same N_e^2 spheres: C11 = 2N(kn+kt)/a, C12 = N(kn-kt)/a,
// C44 = N(kn+kt)/a, the rest zero.
TEST(ElasticTensor, FccAffineIsTheFaceSpringClosedForm) {
  for (int ne : {3, 4, 10}) {
    const Springs s = springs_of(LatticeType::fcc, ne);
    ASSERT_EQ(s.faces.size(), 12u);
    const double n = double(s.faces[0].pairs);
    for (const FaceSpring& f : s.faces) EXPECT_EQ(f.pairs, s.faces[0].pairs);
    EXPECT_EQ(s.faces[0].pairs, long(ne) * ne);
    const Voigt c = prediction(LatticeType::fcc, ne);
    for (int i = 0; i < 3; ++i) {
      expect_near_relative(c(i, i), 2 * n * (s.kn + s.kt) / s.a, 1e-9, "C11");
      expect_near_relative(c(i + 3, i + 3), n * (s.kn + s.kt) / s.a, 1e-9, "C44");
      expect_near_relative(c(i, (i + 1) % 3), n * (s.kn - s.kt) / s.a, 1e-9, "C12");
    }
    EXPECT_LT(cubic_off_pattern(c), 1e-12);
    // Zener: 2 (kn + kt) / (kn + 3 kt).
    expect_near_relative(zener_ratio(c), 2 * (s.kn + s.kt) / (s.kn + 3 * s.kt), 1e-9, "A");
  }
}

// Cubes: C11 = N kn / a, C12 = 0, C44 = N kt / (2a).
TEST(ElasticTensor, SimpleCubicAffineIsTheFaceSpringClosedForm) {
  const Springs s = springs_of(LatticeType::sc, 4);
  ASSERT_EQ(s.faces.size(), 6u);
  const double n = double(s.faces[0].pairs);
  const Voigt c = prediction(LatticeType::sc, 4);
  expect_near_relative(c(0, 0), n * s.kn / s.a, 1e-9, "C11");
  EXPECT_NEAR(c(0, 1), 0, 1e-9 * c(0, 0));
  expect_near_relative(c(3, 3), n * s.kt / (2 * s.a), 1e-9, "C44");
}

// Truncated octahedra: n_hex touching pairs on each of the 8 hexagons, n_sq on the 6 squares. At N_e = 4 a hexagon
// holds 22 spheres, but its sphere grid and the neighbour's do not line up (the truncated octahedron has no mirror
// plane normal to [1 1 1]): 7 pairs touch. A square's 9 all do.
TEST(ElasticTensor, BodyCentredCubicAffineIsTheFaceSpringClosedForm) {
  const Springs s = springs_of(LatticeType::bcc, 4);
  ASSERT_EQ(s.faces.size(), 14u);
  GrainGeometry g;
  g.shape = grain_shape(LatticeType::bcc);
  g.edge_spheres = 4;
  const GrainTemplate grain(g);
  double n_hex = 0, n_sq = 0;
  for (const FaceSpring& f : s.faces) {
    const bool square = std::abs(f.normal.cwiseAbs().maxCoeff() - 1) < 1e-9;
    const long touching = touching_pairs(grain, Quat::Identity(), Quat::Identity(), f.branch * f.normal);
    EXPECT_EQ(f.pairs, square ? 9 : 22);
    EXPECT_EQ(touching, square ? 9 : 7);
    (square ? n_sq : n_hex) = double(touching);
  }
  const double a = s.a, kn = s.kn, kt = s.kt;
  const Voigt c = prediction(LatticeType::bcc, 4);
  expect_near_relative(c(0, 0), 2 * n_hex / (3 * a) * (kn + 2 * kt) + 2 * n_sq * kn / a, 1e-9, "C11");
  expect_near_relative(c(0, 1), 2 * n_hex / (3 * a) * (kn - kt), 1e-9, "C12");
  expect_near_relative(c(3, 3), n_hex / (3 * a) * (2 * kn + kt) + n_sq * kt / a, 1e-9, "C44");
  EXPECT_LT(cubic_spread(c), 1e-12);
}

// Ideal HCP: P = N / (sqrt2 D), D = a / sqrt2 (the FCC cell of the same grains); exactly hexagonal, C66 = (C11 - C12)/2.
TEST(ElasticTensor, HexagonalAffineIsTheFaceSpringClosedForm) {
  const Springs s = springs_of(LatticeType::hcp, 4);
  ASSERT_EQ(s.faces.size(), 12u);
  const double n = double(s.faces[0].pairs);
  for (const FaceSpring& f : s.faces) EXPECT_EQ(f.pairs, s.faces[0].pairs);
  const double d = s.a / std::sqrt(2.0), p = n / (std::sqrt(2.0) * d), kn = s.kn, kt = s.kt;
  const Voigt c = prediction(LatticeType::hcp, 4);
  expect_near_relative(c(0, 0), p * (5 * kn + 3 * kt) / 2, 1e-9, "C11");
  expect_near_relative(c(1, 1), p * (5 * kn + 3 * kt) / 2, 1e-9, "C22");
  expect_near_relative(c(0, 1), 5 * p * (kn - kt) / 6, 1e-9, "C12");
  expect_near_relative(c(0, 2), 2 * p * (kn - kt) / 3, 1e-9, "C13");
  expect_near_relative(c(2, 2), 4 * p * (2 * kn + kt) / 3, 1e-9, "C33");
  expect_near_relative(c(3, 3), 2 * p * (kn + 2 * kt) / 3, 1e-9, "C44");
  expect_near_relative(c(5, 5), p * (5 * kn + 7 * kt) / 6, 1e-9, "C66");
  expect_near_relative(c(5, 5), (c(0, 0) - c(0, 1)) / 2, 1e-9, "C66 = (C11 - C12) / 2");
}

Voigt cubic(double c11, double c12, double c44) {
  Voigt c = Voigt::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c(i, j) = i == j ? c11 : c12;
    c(i + 3, i + 3) = c44;
  }
  return c;
}

Mat3 rotation(double angle, Vec3 axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

TEST(ElasticTensor, RotationsKeepCubicSymmetryAndInvert) {
  const Voigt c = cubic(3.0, 1.2, 0.7);
  EXPECT_LT((rotate_stiffness(c, rotation(M_PI / 2, Vec3::UnitZ())) - c).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((rotate_stiffness(c, rotation(M_PI / 2, Vec3::UnitX())) - c).cwiseAbs().maxCoeff(), 1e-12);
  const Mat3 q = rotation(0.7, Vec3(1, 2, -0.5));
  const Voigt turned = rotate_stiffness(c, q);
  EXPECT_GT((turned - c).cwiseAbs().maxCoeff(), 0.1);  // an anisotropic tensor does change
  EXPECT_LT((rotate_stiffness(turned, q.transpose()) - c).cwiseAbs().maxCoeff(), 1e-12);
  // E along d in the first frame equals E along q d in the turned one.
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 2, 3)})
    EXPECT_NEAR(directional_modulus(turned, q * d), directional_modulus(c, d), 1e-12);
}

TEST(ElasticTensor, YoungsModulusIsTheCubicClosedForm) {
  const double c11 = 3.0, c12 = 1.2, c44 = 0.7;
  const Voigt c = cubic(c11, c12, c44);
  EXPECT_NEAR(directional_modulus(c, Vec3(1, 0, 0)), (c11 - c12) * (c11 + 2 * c12) / (c11 + c12), 1e-12);
  EXPECT_NEAR(1 / directional_modulus(c, Vec3(1, 1, 1)), 1 / (3 * (c11 + 2 * c12)) + 1 / (3 * c44), 1e-12);
  EXPECT_NEAR(1 / directional_modulus(c, Vec3(1, 1, 0)), c11 / (2 * (c11 - c12) * (c11 + 2 * c12)) + 1 / (4 * c44),
              1e-12);
  // Isotropic (E = 2.5, nu = 0.25): E in every direction.
  const double e = 2.5, nu = 0.25, lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  const Voigt iso = cubic(lambda + 2 * mu, lambda, mu);
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0.3, -2, 1)}) EXPECT_NEAR(directional_modulus(iso, d), e, 1e-12);
  EXPECT_NEAR(zener_ratio(iso), 1, 1e-12);
}

}  // namespace
}  // namespace granulab
