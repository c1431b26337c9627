// The elastic tensor of confined crystals (docs/model.md, "Crystal stiffness"), N_e = 4, 5 x 5 x 5 boxes, 30 kPa:
//  - FCC along its cube axes: the affine tensor is the face-spring closed form C11 = 2N(kn+kt)/a, C12 = N(kn-kt)/a,
//    C44 = N(kn+kt)/a (N = N_e^2 aligned sphere pairs per face) within 1 %; both tensors are cubic (C11 = C22 = C33,
//    C12 = C13 = C23, C44 = C55 = C66, the rest zero) within 1 %; a perfect Bravais crystal has nothing to relax (no
//    net force or torque on a grain under a uniform strain), so the relaxed tensor is the affine one within 1 %;
//  - SC and BCC: cubic within 1 %, relaxed = affine within 1 %, SC's affine tensor its closed form within 1 %, every
//    lattice's affine tensor the face-spring sum over its touching sphere pairs (affine_prediction) within 1 %;
//  - HCP: hexagonal within 1 % (C11 = C22, C13 = C23, C44 = C55, C66 = (C11 - C12) / 2); its two sublattices may
//    shift against each other under in-plane strains, so the relaxed C11 and C66 fall below the affine ones, by at
//    most the infinite crystal's P (kn - kt)^2 / (12 (kn + 5 kt)), while C33 and C44 do not move (within 0.2 %);
//  - imperfect grains (sigma_s = 0.1 %, the paper's crystal at 60 kPa): partial contacts make the affine modulus
//    along the axis less than half the perfect crystal's, and the relaxed one lower still (below 0.9 of affine).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/experiments/crystal_stiffness/crystal_stiffness.h"
#include "engine/model/model.h"

namespace granulab {
namespace {

StiffnessParams cube_box(LatticeType lattice) {
  StiffnessParams p;
  p.lattice = lattice;
  p.axis = default_axis(lattice);
  p.lateral = lattice == LatticeType::hcp ? Indices{0, 0, 0} : Indices{1, 0, 0};
  if (lattice == LatticeType::fcc) p.axis = {0, 0, 1};
  p.grain.shape = grain_shape(lattice);
  p.grain.edge_spheres = 4;
  p.grains_x = 5, p.rows_z = 5, p.layers_y = 5;
  p.confining_pressure = 30e3;
  return p;
}

struct Tensors {
  Voigt affine, relaxed;
  StiffnessResult r;
};

Tensors measure(const StiffnessParams& p) {
  CrystalStiffness experiment(p);
  ResultSink none;
  Tensors t;
  t.r = experiment.run(none);
  const Mat3 to_crystal = experiment.sample().lattice().orientation.toRotationMatrix().transpose();
  t.affine = rotate_stiffness(stiffness_of(t.r.curve, 0, t.r.amplitude), to_crystal);
  t.relaxed = rotate_stiffness(stiffness_of(t.r.curve, 1, t.r.amplitude), to_crystal);
  EXPECT_TRUE(t.r.confinement.converged);
  return t;
}

double largest_difference(const Voigt& a, const Voigt& b) { return (a - b).cwiseAbs().maxCoeff() / b(0, 0); }

double mean_diagonal(const Voigt& c, int from) { return (c(from, from) + c(from + 1, from + 1) + c(from + 2, from + 2)) / 3; }
double mean_c12(const Voigt& c) { return (c(0, 1) + c(0, 2) + c(1, 2)) / 3; }

ContactLaw law_of(const StiffnessParams& p) { return contact_law(GrainTemplate(p.grain), p.material); }

TEST(CrystalStiffness, FccAffineTensorIsTheFaceSpringClosedFormAndCubic) {
  const StiffnessParams p = cube_box(LatticeType::fcc);
  const Tensors t = measure(p);
  const ContactLaw law = law_of(p);
  const double n = 16, kn = law.normal_stiffness, kt = law.tangential_stiffness, a = p.grain.size;
  std::printf("FCC affine C11 %.5g C12 %.5g C44 %.5g; closed form %.5g %.5g %.5g; relaxed C11 %.5g\n",
              mean_diagonal(t.affine, 0), mean_c12(t.affine), mean_diagonal(t.affine, 3), 2 * n * (kn + kt) / a,
              n * (kn - kt) / a, n * (kn + kt) / a, mean_diagonal(t.relaxed, 0));
  EXPECT_NEAR(mean_diagonal(t.affine, 0), 2 * n * (kn + kt) / a, 0.01 * 2 * n * (kn + kt) / a);
  EXPECT_NEAR(mean_c12(t.affine), n * (kn - kt) / a, 0.01 * n * (kn - kt) / a);
  EXPECT_NEAR(mean_diagonal(t.affine, 3), n * (kn + kt) / a, 0.01 * n * (kn + kt) / a);
  for (const Voigt* c : {&t.affine, &t.relaxed}) {
    EXPECT_LT(cubic_spread(*c), 0.01);
    EXPECT_LT(cubic_off_pattern(*c), 0.01);
    EXPECT_LT(symmetry_error(*c), 0.01);
  }
  EXPECT_LT(largest_difference(t.relaxed, t.affine), 0.01);
  EXPECT_LT(stiffness_nonlinearity(t.r.curve, 0), 0.01);
  EXPECT_LT(stiffness_nonlinearity(t.r.curve, 1), 0.01);
  EXPECT_GT(t.r.interior_grains, 20u);
}

TEST(CrystalStiffness, EveryLatticeHasItsSymmetryAndHcpRelaxesInPlane) {
  for (LatticeType lattice : {LatticeType::sc, LatticeType::bcc}) {
    SCOPED_TRACE(to_string(lattice));
    const StiffnessParams p = cube_box(lattice);
    const Tensors t = measure(p);
    std::printf("%s: affine C11 %.5g C12 %.5g C44 %.5g; relaxed C11 %.5g; spread %.2g\n", to_string(lattice).c_str(),
                mean_diagonal(t.affine, 0), mean_c12(t.affine), mean_diagonal(t.affine, 3),
                mean_diagonal(t.relaxed, 0), cubic_spread(t.relaxed));
    for (const Voigt* c : {&t.affine, &t.relaxed}) {
      EXPECT_LT(cubic_spread(*c), 0.01);
      EXPECT_LT(cubic_off_pattern(*c), 0.01);
    }
    EXPECT_LT(largest_difference(t.relaxed, t.affine), 0.01);
    EXPECT_LT(largest_difference(t.affine, affine_prediction(p)), 0.01);  // BCC: with its hexagons' 7 touching pairs
    if (lattice == LatticeType::sc) {
      const ContactLaw law = law_of(p);
      const double n = 16, a = p.grain.size;
      EXPECT_NEAR(mean_diagonal(t.affine, 0), n * law.normal_stiffness / a, 0.01 * n * law.normal_stiffness / a);
      EXPECT_NEAR(mean_diagonal(t.affine, 3), n * law.tangential_stiffness / (2 * a),
                  0.01 * n * law.tangential_stiffness / (2 * a));
    }
  }
  const StiffnessParams p = cube_box(LatticeType::hcp);
  const Tensors t = measure(p);
  const ContactLaw law = law_of(p);
  const double kn = law.normal_stiffness, kt = law.tangential_stiffness;
  const double d = p.grain.size / std::sqrt(2.0), pp = 16 / (std::sqrt(2.0) * d);
  const double full_shift = pp * (kn - kt) * (kn - kt) / (12 * (kn + 5 * kt));
  const Voigt &a = t.affine, &r = t.relaxed;
  std::printf("HCP affine C11 %.5g C12 %.5g C13 %.5g C33 %.5g C44 %.5g C66 %.5g\n", a(0, 0), a(0, 1), a(0, 2), a(2, 2),
              a(3, 3), a(5, 5));
  std::printf("HCP relaxed C11 %.5g C12 %.5g C13 %.5g C33 %.5g C44 %.5g C66 %.5g; sublattice shift at most %.4g\n",
              r(0, 0), r(0, 1), r(0, 2), r(2, 2), r(3, 3), r(5, 5), full_shift);
  for (const Voigt* c : {&a, &r}) {
    const Voigt& m = *c;
    const double scale = m(0, 0);
    EXPECT_NEAR(m(1, 1), m(0, 0), 0.01 * scale);
    EXPECT_NEAR(m(1, 2), m(0, 2), 0.01 * scale);
    EXPECT_NEAR(m(4, 4), m(3, 3), 0.01 * scale);
    EXPECT_NEAR(m(5, 5), (m(0, 0) - m(0, 1)) / 2, 0.01 * scale);
  }
  EXPECT_LT(largest_difference(a, affine_prediction(p)), 0.01);
  for (int k : {0, 5}) {
    EXPECT_LT(r(k, k), a(k, k));
    EXPECT_GT(r(k, k), a(k, k) - 1.1 * full_shift);
  }
  EXPECT_NEAR(r(2, 2), a(2, 2), 0.002 * a(2, 2));
  EXPECT_NEAR(r(3, 3), a(3, 3), 0.002 * a(3, 3));
}

TEST(CrystalStiffness, ImperfectGrainsAreSofterAndRelaxFurther) {
  StiffnessParams p;  // the paper's crystal, off axis, in its default 6 x 6 x 6 box
  p.grain.edge_spheres = 4;
  p.confining_pressure = 60e3;
  const Vec3 axis = direction_vector(p.lattice, p.axis, 1).normalized();
  const Tensors perfect = measure(p);
  p.imperfections.size_dispersion = 0.001;
  const Tensors imperfect = measure(p);
  const double e_perfect = directional_modulus(perfect.affine, axis);
  const double e_affine = directional_modulus(imperfect.affine, axis), e_relaxed = directional_modulus(imperfect.relaxed, axis);
  std::printf("along [-1 -1 2]: perfect %.4g Pa (relaxed %.4g); sigma_s = 0.1 %%: affine %.4g, relaxed %.4g\n", e_perfect,
              directional_modulus(perfect.relaxed, axis), e_affine, e_relaxed);
  EXPECT_LT(e_affine, 0.5 * e_perfect);
  EXPECT_LT(e_relaxed, 0.9 * e_affine);
  EXPECT_GT(e_relaxed, 0);
}

}  // namespace
}  // namespace granulab
