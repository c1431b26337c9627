// The vectorised contact loop computes the same law as the scalar contact_force() (one evaluator, contact_terms, in
// two settings: the kernel builds each candidate's geometry from the grains' poses): random sphere pairs (touching and
// separated), random shear histories (some at the Coulomb limit, some rotated far out of the tangent plane), random
// rigid-body velocities, the dashpots' different from the motion's. Results agree to rounding, on both paths (one pass over every candidate; distances first,
// then the law on the touching ones), for every normal law and both tangential ones, in every instruction set's kernel.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <stdexcept>
#include <vector>

#include "engine/contact/neighbor_list.h"
#include "engine/contact/pair_kernel.h"

namespace granulab {
namespace {

struct KernelCase {
  const char* kernel;  // instruction set (pair_kernels())
  bool two_pass;
  NormalModel normal;
  TangentialModel tangential;
};

// Forces of about 1-10 N at overlaps of 1e-5..1e-4 m for every law: Hooke 2e5 N/m, Hertz E* = 1e9 Pa, the cohesive
// laws' pull-off 2-3 N (gamma = 1000 J/m^2 at R* = d / 4), mindlin 8 G* of nu = 0.3.
ContactLaw law_of(NormalModel normal, TangentialModel tangential) {
  ContactLaw law{2e5, 2.0 / 7 * 2e5, 0.1, 0.35};
  law.normal = normal, law.tangential = tangential;
  law.effective_modulus = 1e9;
  if (normal != NormalModel::hooke) law.normal_stiffness = 4.0 / 3 * law.effective_modulus;
  if (law.cohesive()) law.surface_energy = 1000;
  if (tangential == TangentialModel::mindlin) law.tangential_stiffness = 1.6e9;
  return law;
}

class PairKernel : public ::testing::TestWithParam<KernelCase> {};

TEST_P(PairKernel, MatchesScalarContactLaw) {
  const bool two_pass = GetParam().two_pass;
  for (const PairKernelInfo& k : pair_kernels())
    if (k.name == std::string(GetParam().kernel) && !k.runs_here)
      GTEST_SKIP() << "this CPU lacks the instructions of kernel " << k.name;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  const double d = 1e-3;
  const ContactLaw law = law_of(GetParam().normal, GetParam().tangential);
  const int n = 300;
  std::vector<Vec3> sa(n), sb(n), hist(n);
  std::vector<std::uint32_t> keys(n);
  // One template holds both grains' spheres: a's at 0..n-1, b's at n..2n-1, mapped by the poses below.
  const Quat qa(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())),
      qb(Eigen::AngleAxisd(-1.1, Vec3(3, -1, 2).normalized()));
  const Vec3 xa(0.001, -0.002, 0.003), xb(0.004, 0.001, -0.002);
  std::vector<Vec3> offsets(2 * n);
  for (int k = 0; k < n; ++k) {
    sa[k] = Vec3(u(rng), u(rng), u(rng)) * 1e-2;
    // Partners at 0.9 d .. 1.1 d: most touch, some do not.
    sb[k] = sa[k] + Vec3(u(rng), u(rng), u(rng)).normalized() * d * (1 + 0.1 * u(rng));
    // Histories from tiny to far beyond the cap (slip), in arbitrary directions.
    hist[k] = Vec3(u(rng), u(rng), u(rng)) * 1e-6 * std::pow(10.0, 2 * u(rng));
    keys[k] = sphere_pair_key(LocalSphereId(k), LocalSphereId(n + k));
    offsets[k] = qa.conjugate() * (sa[k] - xa);
    offsets[n + k] = qb.conjugate() * (sb[k] - xb);
  }
  PairKernelConstants c;
  c.diameter = d, c.radius = d / 2;
  const double m_eff = 1e-3;
  c.law = pair_law(law, d / 4, m_eff, 1e-6);
  c.xa = xa, c.xb = xb, c.ra = qa.toRotationMatrix(), c.rb = qb.toRotationMatrix();
  // The scalar reference sees the spheres where the kernel puts them (pose times offset), so the two differ by
  // rounding alone: ~1e-18 m in a centre, 1e-13 of an overlap.
  for (int k = 0; k < n; ++k) sa[k] = xa + c.ra * offsets[k], sb[k] = xb + c.rb * offsets[n + k];
  const Vec3 va(0.1, -0.05, 0.02), vb(-0.03, 0.04, 0.01), wa(3, -1, 2), wb(-2, 4, 1);
  c.v0 = va - vb - wb.cross(c.xa - xb);
  c.dw = wa - wb;
  // The dashpots see other velocities (World's quarter-step ones): the kernel must build both at each contact point.
  const Vec3 ua(0.08, -0.06, 0.03), ub(-0.02, 0.05, 0.0), oa(2.5, -1.5, 2.2), ob(-1.8, 3.5, 1.4);
  c.v0_damping = ua - ub - ob.cross(c.xa - xb);
  c.dw_damping = oa - ob;

  std::vector<Vec3> kernel_hist = hist, scalar_hist = hist;
  std::vector<double> hx(n), hy(n), hz(n);  // the kernel's layout: one array per component
  for (int k = 0; k < n; ++k) hx[k] = hist[k].x(), hy[k] = hist[k].y(), hz[k] = hist[k].z();
  // jkr: every third pair starts bonded, so that some bonds hold apart (within d + delta_c), some break beyond it and
  // leave their stored energy with the losses, on either path.
  std::vector<double> bonds(n, 0.0), scalar_bonds(n, 0.0);
  std::uint32_t bonded_apart = 0, broken = 0;
  if (law.keeps_bonds())
    for (int k = 0; k < n; k += 3) {
      bonds[k] = scalar_bonds[k] = 1.0;
      const double gap = (sa[k] - sb[k]).norm() - d;
      bonded_apart += gap >= 0 && gap < c.law.break_depth, broken += gap >= c.law.break_depth;
    }
  KernelScratch scratch;
  scratch.reserve(n);
  const OffsetArrays offset_arrays(offsets);
  const PairKernelSums s = pair_kernel(law, GetParam().kernel)(c, offset_arrays, keys.data(), n, hx.data(), hy.data(), hz.data(),
                                            law.keeps_bonds() ? bonds.data() : nullptr,
                                            two_pass ? &scratch : nullptr);
  // The stored energy, from what the evaluation left (its histories and bonds), by the same instruction set.
  const double stored = pair_energy_kernel(law, GetParam().kernel)(c, offset_arrays, keys.data(), n, hx.data(),
                                                                   hy.data(), hz.data(),
                                                                   law.keeps_bonds() ? bonds.data() : nullptr);
  for (int k = 0; k < n; ++k) kernel_hist[k] = Vec3(hx[k], hy[k], hz[k]);

  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  double force_scale = 0, moment_scale = 0;  // sums of the magnitudes: the sums' rounding is relative to these
  std::uint32_t contacts = 0, sliding = 0;
  double damping = 0, friction = 0, energy = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 r = sa[k] - sb[k];
    const bool bonded = scalar_bonds[k] > 0;
    if (r.norm() >= d && !bonded) {
      scalar_hist[k].setZero();
      continue;
    }
    const double delta = d - r.norm();
    const Vec3 nrm = r.normalized();
    const Vec3 point = sa[k] - (d / 2 - delta / 2) * nrm;
    const Vec3 v_rel = (va + wa.cross(point - c.xa)) - (vb + wb.cross(point - xb));
    const Vec3 v_damping = (ua + oa.cross(point - c.xa)) - (ub + ob.cross(point - xb));
    const ContactForce cf = contact_force(law, c.law, nrm, delta, v_rel, v_damping, scalar_hist[k], scalar_bonds[k]);
    force += cf.force;
    moment += (point - c.xa).cross(cf.force);
    force_scale += cf.force.norm(), moment_scale += (point - c.xa).cross(cf.force).norm();
    contacts += r.norm() < d || scalar_bonds[k] > 0;  // touching, or a bond that held
    sliding += cf.sliding;
    damping += cf.damping, friction += cf.friction, energy += cf.energy;
  }
  if (law.keeps_bonds()) {
    ASSERT_GT(bonded_apart, 0u) << "no bond holds apart: the case misses that branch";
    ASSERT_GT(broken, 0u) << "no bond breaks: the case misses that branch";
  }
  ASSERT_GT(contacts, 100u);
  ASSERT_GT(sliding, 10u);
  ASSERT_LT(contacts, std::uint32_t(n));
  EXPECT_EQ(s.contacts, contacts);
  EXPECT_EQ(s.sliding, sliding);
  // Per contact the law agrees to 1e-12 (the histories below); sums of ~300 forces, added in another order (2, 4 or
  // 8 lanes), to 1e-12 of the sum of their magnitudes.
  EXPECT_LT((s.force - force).norm(), 1e-12 * force_scale);
  EXPECT_LT((s.moment - moment).norm(), 1e-12 * moment_scale);
  // The energy balance's per-step losses and the stored energy (energy_balance.h) are the scalar law's too.
  ASSERT_GT(friction, 0);
  // (jkr's first touch at these deep overlaps counts its snap-in, -potential < 0, with the losses.)
  if (!law.keeps_bonds()) ASSERT_GT(damping, 0);
  ASSERT_NE(damping, 0);
  EXPECT_NEAR(s.friction, friction, 1e-9 * friction);
  EXPECT_NEAR(s.damping, damping, 1e-9 * std::abs(damping));
  EXPECT_NEAR(stored, energy, 1e-9 * energy);
  for (int k = 0; k < n; ++k) {
    // Relative to the lengths that enter the update (the old history and the new): a slip's reset, -(g + c_t v_t) / k_t,
    // may cancel between its terms.
    EXPECT_LT((kernel_hist[k] - scalar_hist[k]).norm(), 1e-12 * (scalar_hist[k].norm() + hist[k].norm()) + 1e-20) << k;
    if (law.keeps_bonds()) EXPECT_EQ(bonds[k], scalar_bonds[k]) << k;
  }
}

std::vector<KernelCase> kernel_cases() {
  std::vector<KernelCase> cases;
  // Every kernel of the binary, those this CPU lacks included: they skip, and say so.
  for (const PairKernelInfo& k : pair_kernels())
    for (bool two_pass : {false, true})
      for (NormalModel normal : {NormalModel::hooke, NormalModel::hertz, NormalModel::hertz_material,
                                 NormalModel::dmt, NormalModel::jkr})
        for (TangentialModel tangential : {TangentialModel::linear_history, TangentialModel::mindlin})
          cases.push_back({k.name, two_pass, normal, tangential});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Laws, PairKernel, ::testing::ValuesIn(kernel_cases()),
                         [](const ::testing::TestParamInfo<KernelCase>& p) {
                           std::string name = std::string(p.param.kernel) + "_" + to_string(p.param.normal) + "_" + to_string(p.param.tangential) +
                                              (p.param.two_pass ? "_DistancesFirst" : "_OnePass");
                           for (char& ch : name)
                             if (ch == '/') ch = '_';
                           return name;
                         });

}  // namespace
}  // namespace granulab

namespace granulab {
namespace {

// A kernel named by the environment stands in for auto, and an error names where the name came from.
TEST(PairKernelChoice, TheEnvironmentReplacesAutoAndErrorsNameTheirSource) {
  const char* saved = std::getenv("GRANULAB_KERNEL");
  const std::string restore = saved ? saved : "";
  ::setenv("GRANULAB_KERNEL", kBaselineKernel, 1);
  EXPECT_EQ(resolve_pair_kernel(""), kBaselineKernel);
  EXPECT_EQ(resolve_pair_kernel("auto"), kBaselineKernel);
  ::setenv("GRANULAB_KERNEL", "avx3", 1);
  try {
    resolve_pair_kernel("auto");
    ADD_FAILURE() << "accepted GRANULAB_KERNEL=avx3";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("GRANULAB_KERNEL"), std::string::npos) << e.what();
  }
  EXPECT_EQ(resolve_pair_kernel(kBaselineKernel), kBaselineKernel);  // a spec's own choice stands
  ::unsetenv("GRANULAB_KERNEL");
  EXPECT_EQ(resolve_pair_kernel(""), best_pair_kernel());
  try {
    resolve_pair_kernel("avx3");
    ADD_FAILURE() << "accepted run.kernel avx3";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("run.kernel"), std::string::npos) << e.what();
  }
  if (saved) ::setenv("GRANULAB_KERNEL", restore.c_str(), 1);
}

}  // namespace
}  // namespace granulab
