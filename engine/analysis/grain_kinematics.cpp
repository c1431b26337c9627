#include "engine/analysis/grain_kinematics.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace granulab {

std::vector<BodyPair> neighbour_pairs(const std::vector<Vec3>& x, double cutoff) {
  // Sort by x and sweep: O(n log n + pairs) for the near-uniform packings we analyse.
  std::vector<std::uint32_t> order(x.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return x[a].x() < x[b].x(); });
  std::vector<BodyPair> pairs;
  for (std::size_t k = 0; k < order.size(); ++k)
    for (std::size_t m = k + 1; m < order.size() && x[order[m]].x() - x[order[k]].x() < cutoff; ++m)
      if ((x[order[m]] - x[order[k]]).norm() < cutoff)
        pairs.push_back({std::min(order[k], order[m]), std::max(order[k], order[m])});
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<LocalStrain> local_strains(const std::vector<Vec3>& ref, const std::vector<Vec3>& cur,
                                       const std::vector<BodyPair>& pairs) {
  const std::size_t n = ref.size();
  std::vector<Mat3> v(n, Mat3::Zero()), w(n, Mat3::Zero());  // sum d0 d0^T and sum d d0^T
  for (const auto& [a, b] : pairs) {
    const Vec3 d0 = ref[b] - ref[a], d = cur[b] - cur[a];
    v[a] += d0 * d0.transpose(), w[a] += d * d0.transpose();
    v[b] += d0 * d0.transpose(), w[b] += d * d0.transpose();  // (-d)(-d0)^T
  }
  std::vector<LocalStrain> out(n);
  std::vector<Mat3> fit(n, Mat3::Identity());
  for (std::size_t i = 0; i < n; ++i) {
    if (v[i].isZero()) continue;
    // F v = w  ->  F = w v^+ (v symmetric); the pseudo-inverse handles planar neighbourhoods.
    const Eigen::JacobiSVD<Mat3> svd(v[i], Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Vec3 s = svd.singularValues();
    Vec3 inv = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
      if (s[k] > 1e-9 * s[0]) inv[k] = 1 / s[k];
    const Mat3 v_plus = svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose();
    // Directions no neighbour spans (a planar neighbourhood) are taken as undeformed, not collapsed.
    const Mat3 f = w[i] * v_plus + (Mat3::Identity() - v[i] * v_plus);
    fit[i] = f;
    const Mat3 e = 0.5 * (f.transpose() * f - Mat3::Identity());
    out[i].green_lagrange = e;
    const Vec3 principal = Eigen::SelfAdjointEigenSolver<Mat3>(e).eigenvalues();  // ascending
    const Mat3 dev = e - e.trace() / 3 * Mat3::Identity();
    out[i].max_shear = (principal[2] - principal[0]) / 2;
    out[i].equivalent = std::sqrt(2.0 / 3.0 * dev.squaredNorm());
  }
  // The residual, pair by pair (not from the sums: for an affine motion it would be a difference of large terms).
  for (const auto& [a, b] : pairs) {
    const Vec3 d0 = ref[b] - ref[a], d = cur[b] - cur[a];
    out[a].d2min += (d - fit[a] * d0).squaredNorm();
    out[b].d2min += (d - fit[b] * d0).squaredNorm();  // |(-d) - F (-d0)|
  }
  return out;
}

Misorientation misorientation(const Quat& reference, const Quat& current) {
  Quat r = (current * reference.conjugate()).normalized();
  if (r.w() < 0) r.coeffs() = -r.coeffs();  // the shorter way round: angle in [0, 180]
  const double s = r.vec().norm();
  Misorientation m;
  m.angle = 2 * std::atan2(s, r.w()) * 180 / M_PI;
  if (s > 0) m.axis = r.vec() / s;
  return m;
}

std::vector<double> interface_sliding(const std::vector<Vec3>& ref_pos, const std::vector<Quat>& ref_q,
                                      const std::vector<Vec3>& pos, const std::vector<Quat>& q,
                                      const std::vector<BodyPair>& pairs) {
  std::vector<double> out;
  out.reserve(pairs.size());
  for (const auto& [a, b] : pairs) {
    const Vec3 mid = (ref_pos[a] + ref_pos[b]) / 2;
    // The material point of each grain at the reference midpoint, carried by its rigid motion.
    const Vec3 pa = pos[a] + q[a] * (ref_q[a].conjugate() * (mid - ref_pos[a]));
    const Vec3 pb = pos[b] + q[b] * (ref_q[b].conjugate() * (mid - ref_pos[b]));
    // The interface turns with the grains, not with the line between their centres (which tilts as
    // they slide): the reference normal carried by each grain's rotation, averaged over the two.
    const Vec3 n0 = ref_pos[b] - ref_pos[a];
    const Vec3 n = (q[a] * (ref_q[a].conjugate() * n0) + q[b] * (ref_q[b].conjugate() * n0)).normalized();
    const Vec3 gap = pb - pa;
    out.push_back((gap - gap.dot(n) * n).norm());
  }
  return out;
}

}  // namespace granulab
