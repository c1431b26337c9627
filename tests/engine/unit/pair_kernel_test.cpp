// The vectorised contact loop computes the same law as the scalar contact_force(): random sphere
// pairs (touching and separated), random shear histories (some at the Coulomb limit, some rotated far
// out of the tangent plane), random rigid-body velocities. Results agree to rounding, on both paths
// (one pass over every candidate; distances first, then the law on the touching ones).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/contact/neighbor_list.h"
#include "engine/contact/pair_kernel.h"

namespace granulab {
namespace {

class PairKernel : public ::testing::TestWithParam<bool> {};

TEST_P(PairKernel, MatchesScalarContactLaw) {
  const bool two_pass = GetParam();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  const double d = 1e-3;
  const ContactLaw law{2e5, 2.0 / 7 * 2e5, 0.1, 0.35};
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
  c.diameter = d, c.radius = d / 2, c.kn = law.normal_stiffness, c.kt = law.tangential_stiffness;
  const double m_eff = 1e-3;
  c.cn = damping_coefficient(law, m_eff), c.ct = c.cn / 2;
  c.friction = law.friction, c.dt = 1e-6;
  c.xa = xa, c.xb = xb, c.ra = qa.toRotationMatrix(), c.rb = qb.toRotationMatrix();
  const Vec3 va(0.1, -0.05, 0.02), vb(-0.03, 0.04, 0.01), wa(3, -1, 2), wb(-2, 4, 1);
  c.v0 = va - vb - wb.cross(c.xa - xb);
  c.dw = wa - wb;

  std::vector<Vec3> kernel_hist = hist, scalar_hist = hist;
  std::vector<double> hx(n), hy(n), hz(n);  // the kernel's layout: one array per component
  for (int k = 0; k < n; ++k) hx[k] = hist[k].x(), hy[k] = hist[k].y(), hz[k] = hist[k].z();
  std::vector<std::uint32_t> scratch(n, 12345);
  const PairKernelSums s = pair_contacts(c, OffsetArrays(offsets), keys.data(), n, hx.data(), hy.data(), hz.data(),
                                         two_pass ? scratch.data() : nullptr);
  for (int k = 0; k < n; ++k) kernel_hist[k] = Vec3(hx[k], hy[k], hz[k]);

  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  std::uint32_t contacts = 0, sliding = 0;
  double damping = 0, friction = 0, energy = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 r = sa[k] - sb[k];
    if (r.norm() >= d) {
      scalar_hist[k].setZero();
      continue;
    }
    const double delta = d - r.norm();
    const Vec3 nrm = r.normalized();
    const Vec3 point = sa[k] - (d / 2 - delta / 2) * nrm;
    const Vec3 v_rel = (va + wa.cross(point - c.xa)) - (vb + wb.cross(point - xb));
    const ContactForce cf = contact_force(law, c.cn, nrm, delta, v_rel, c.dt, scalar_hist[k]);
    force += cf.force;
    moment += (point - c.xa).cross(cf.force);
    ++contacts;
    sliding += cf.sliding;
    damping += cf.damping, friction += cf.friction, energy += cf.energy;
  }
  ASSERT_GT(contacts, 100u);
  ASSERT_GT(sliding, 10u);
  ASSERT_LT(contacts, std::uint32_t(n));
  EXPECT_EQ(s.contacts, contacts);
  EXPECT_EQ(s.sliding, sliding);
  // Sums of ~300 forces of ~1e-1 N; positions rebuilt from poses differ from sa, sb by ~1e-18 m,
  // i.e. 1e-12 of the overlaps (~1e-5 m): agreement to ~1e-10 relative.
  EXPECT_LT((s.force - force).norm(), 1e-10 * force.norm());
  EXPECT_LT((s.moment - moment).norm(), 1e-10 * moment.norm());
  // The energy balance's per-step losses and the stored energy (energy_balance.h) are the scalar law's too.
  ASSERT_GT(friction, 0);
  ASSERT_GT(damping, 0);
  EXPECT_NEAR(s.friction, friction, 1e-9 * friction);
  EXPECT_NEAR(s.damping, damping, 1e-9 * damping);
  EXPECT_NEAR(s.energy, energy, 1e-9 * energy);
  for (int k = 0; k < n; ++k)
    EXPECT_LT((kernel_hist[k] - scalar_hist[k]).norm(), 1e-10 * scalar_hist[k].norm() + 1e-20) << k;
}

INSTANTIATE_TEST_SUITE_P(Paths, PairKernel, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& p) {
                           return p.param ? "DistancesFirst" : "OnePass";
                         });

}  // namespace
}  // namespace granulab
