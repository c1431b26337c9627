// The contact law shared by sphere-sphere and sphere-wall contacts (docs/model.md, "Contact law"):
//   normal      F_n = k_n delta n - c_n v_n                         (paper eq. 3, plus viscous damping)
//   tangential  xi <- rotate(xi into the current tangent plane) + v_t dt
//               F_t = -k_t xi - c_t v_t,  |F_t| <= f |F_n|  (on slip xi is reset to match the cap)
// the "Hooke with shear history" model (Cundall & Strack 1979; Silbert et al. 2001, Phys. Rev. E 64,
// 051302; Zhang & Makse 2005), which the paper ran in LAMMPS' granular package.
// Damping is a ratio zeta of the critical value for the pair: c_n = 2 zeta sqrt(k_n m_eff), so the
// normal coefficient of restitution is e = exp(-pi zeta / sqrt(1 - zeta^2)); c_t = c_n / 2.
#pragma once

#include <cmath>

#include "engine/core/types.h"

namespace granulab {

struct ContactLaw {
  double normal_stiffness = 0;      ///< k_n (N/m)
  double tangential_stiffness = 0;  ///< k_t (N/m)
  double damping_ratio = 0;         ///< zeta, fraction of critical damping of one pair (-)
  double friction = 0;              ///< Coulomb coefficient f (-)
};

struct ContactForce {
  Vec3 force;     ///< force on the first body (N)
  double normal;  ///< signed normal force magnitude, compressive positive (N)
  bool sliding;   ///< true when the Coulomb cap was active
  double energy;    ///< elastic energy stored after the step, k_n delta^2 / 2 + k_t |xi|^2 / 2 (J)
  double damping;   ///< energy the dashpots took in the step (J): dt (c_n v_n^2 + c_t |v_t|^2), the tangential
                    ///< one only while sticking (sliding, the capped force is all friction's)
  double friction;  ///< energy lost to sliding in the step (J): the Coulomb force times the slip, i.e. the part
                    ///< of v_t dt the spring did not take (0 while sticking; 0 for f = 0)
};

/// Normal damping coefficient c_n = 2 zeta sqrt(k_n m_eff) (N s/m) of a pair with effective mass m_eff.
inline double damping_coefficient(const ContactLaw& law, double m_eff) {
  return 2 * law.damping_ratio * std::sqrt(law.normal_stiffness * m_eff);
}

/// Force on body i from a contact with unit normal `n` (pointing from j to i), overlap `delta` > 0 (m),
/// relative velocity of i with respect to j at the contact point `v_rel` (m/s), normal damping
/// coefficient `c_n` (damping_coefficient(), hoisted out of loops over one grain pair), time step `dt`
/// (s). Updates the shear history `xi` (m) in place.
inline ContactForce contact_force(const ContactLaw& law, double c_n, const Vec3& n, double delta, const Vec3& v_rel,
                                  double dt, Vec3& xi) {
  const double c_t = c_n / 2;
  const double vn = v_rel.dot(n);
  const Vec3 v_t = v_rel - vn * n;
  const double fn = law.normal_stiffness * delta - c_n * vn;

  // Keep the history in the current tangent plane with its length unchanged (the plane rotates
  // with the contact; the spring must neither grow nor shrink from that rotation).
  const double xi_len2 = xi.squaredNorm();
  xi -= xi.dot(n) * n;
  const double proj2 = xi.squaredNorm();
  if (proj2 > 0) xi *= std::sqrt(xi_len2 / proj2);
  xi += v_t * dt;

  Vec3 ft = -law.tangential_stiffness * xi - c_t * v_t;
  const double cap = law.friction * std::abs(fn);
  const double ft2 = ft.squaredNorm();
  bool sliding = false;
  double friction = 0;
  if (ft2 > cap * cap) {
    sliding = true;
    const double scale = cap / std::sqrt(ft2);  // ft2 > cap^2 >= 0
    ft *= scale;
    if (law.tangential_stiffness > 0) {
      xi = -(ft + c_t * v_t) / law.tangential_stiffness;
      friction = scale * (1 - scale) * ft2 / law.tangential_stiffness;  // cap x |xi_trial - xi|
    } else {
      xi = Vec3::Zero();
      friction = cap * v_t.norm() * dt;  // no spring: all of v_t dt slips
    }
  }
  const double energy = 0.5 * law.normal_stiffness * delta * delta + 0.5 * law.tangential_stiffness * xi.squaredNorm();
  const double damping = dt * (c_n * vn * vn + (sliding ? 0.0 : c_t * v_t.squaredNorm()));
  return {fn * n + ft, fn, sliding, energy, damping, friction};
}

/// The same with the effective mass m_eff (kg) instead of the damping coefficient.
inline ContactForce contact_force(const ContactLaw& law, const Vec3& n, double delta, const Vec3& v_rel, double m_eff,
                                  double dt, Vec3& xi) {
  return contact_force(law, damping_coefficient(law, m_eff), n, delta, v_rel, dt, xi);
}

}  // namespace granulab
