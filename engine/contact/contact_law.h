// The contact law, written once (docs/model.md, "Contact law" and "Interface laws"): contact_terms() below is what
// every path evaluates, the vectorised sphere-sphere loop (pair_kernel.cpp, across candidates) and the scalar
// sphere-wall one (contact_force()). Its laws and their parameters carry LAMMPS' pair_style granular names:
//   normal      hooke           F_ne = k_n delta                                        (the paper's, eq. 3)
//               hertz           F_ne = k_N sqrt(R* delta) delta                         (k_N in Pa)
//               hertz/material  the same with k_N = 4/3 E*, E* = E / (2 (1 - nu^2))
//               dmt             hertz/material - 4 pi gamma R*          (attracts while delta > 0)
//               jkr             F_ne = 4 E* a^3 / (3 R*) - 4 sqrt(pi gamma E* a^3),  delta = a^2 / R* - 2 sqrt(pi gamma a / E*)
//                               made at delta >= 0, kept until delta < -delta_c (pull-off, hysteresis)
//   tangential  linear_history  xi <- rotate(xi into the current tangent plane) + v_t dt,  F_t = -k_t xi - c_t v_t
//               mindlin         the same with the spring k_t a (k_t = 8 G*, Pa; a the contact radius)
//   Coulomb     |F_t| <= f F_n0, F_n0 = |F_n| (damping included), cohesive laws |F_ne + 2 F_pulloff|; on slip xi is reset
//               to match the cap
// Damping is a ratio zeta of the critical value for the pair's tangent stiffness: c_n = 2 zeta sqrt(k m_eff) with
// k = k_n (hooke) or dF_ne/d delta of the Hertz part, 2 E* a (hertz family: k_N 3 a / 2), so c_n grows as sqrt(a);
// c_t = c_n / 2. With hooke the normal restitution coefficient of one pair is e = exp(-pi zeta / sqrt(1 - zeta^2)).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

enum class NormalModel : std::uint8_t { hooke, hertz, hertz_material, dmt, jkr };
enum class TangentialModel : std::uint8_t { linear_history, mindlin };

std::string to_string(NormalModel m);
std::string to_string(TangentialModel m);
/// Every model's LAMMPS name, in declaration order.
std::vector<std::string> normal_model_names();
std::vector<std::string> tangential_model_names();
/// Whether the law attracts (dmt, jkr).
constexpr bool is_cohesive(NormalModel m) { return m == NormalModel::dmt || m == NormalModel::jkr; }
/// LAMMPS' name ("hooke", "hertz/material", ...) to the model; false when unknown.
bool normal_model_from_string(const std::string& name, NormalModel& out);
bool tangential_model_from_string(const std::string& name, TangentialModel& out);

struct ContactLaw {
  double normal_stiffness = 0;      ///< hooke: k_n (N/m); hertz family: k_N (Pa) of F_ne = k_N sqrt(R* delta) delta
  double tangential_stiffness = 0;  ///< linear_history: k_t (N/m); mindlin: k_t (Pa) of the spring k_t a
  double damping_ratio = 0;         ///< zeta, fraction of critical damping of one pair (-)
  double friction = 0;              ///< Coulomb coefficient f (-)
  double surface_energy = 0;        ///< gamma (J/m^2), dmt and jkr: pull-off 4 pi gamma R* (dmt), 3 pi gamma R* (jkr)
  double effective_modulus = 0;     ///< E* (Pa): jkr's contact radius (hertz/material, dmt: k_N = 4/3 E*)
  NormalModel normal = NormalModel::hooke;
  TangentialModel tangential = TangentialModel::linear_history;

  bool cohesive() const { return is_cohesive(normal); }
  /// Whether a pair's contact outlives delta = 0 (jkr): candidates then carry a bond flag.
  bool keeps_bonds() const { return normal == NormalModel::jkr; }
  /// The force of one pair of effective radius r_eff (m) at pull-off (N): 0 without cohesion.
  double pulloff_force(double r_eff) const;
  /// How far past delta = 0 a bonded jkr pair holds (m, positive): delta_c at the contact radius of largest tension.
  double pulloff_distance(double r_eff) const;
  /// The normal stiffness dF/d delta (N/m) of a pair of effective radius r_eff (m) pushing with `force` (N): k_n for
  /// hooke; for the others that of their Hertz part, 3/2 k_N^(2/3) R*^(1/3) F^(1/3).
  double pair_stiffness(double r_eff, double force) const;
};

/// The law's constants for one pair of bodies (effective radius and mass), hoisted out of loops over its contacts.
struct PairLaw {
  double kn = 0, kt = 0;  ///< as ContactLaw's normal_stiffness and tangential_stiffness
  double cn = 0, ct = 0;  ///< hooke: c_n, c_t (N s/m); otherwise their value per sqrt(a) (N s / m^1.5)
  double mu = 0, dt = 0;  ///< Coulomb f (-), time step (s)
  // Loop invariants of the common laws, divided once here: the kernel's loop divided them per contact (GCC does not
  // hoist them, as the loop's stores might alias the constants), two of its eight divisions and square roots.
  double inv_kt = 0;     ///< linear_history: 1 / k_t (m/N), 0 without a spring
  double dt_per_ct = 0;  ///< hooke: dt / c_t (m/N), 0 without a dashpot
  double r_eff = 0;       ///< R* (m)
  double pulloff = 0;     ///< F_pulloff (N), cohesive laws
  double jkr_p = 0;       ///< jkr: 2 R* sqrt(pi gamma / E*) (m^1.5), so that delta R* = x^4 - jkr_p x with x = sqrt(a)
  double jkr_w = 0;       ///< jkr: 4 sqrt(pi gamma E*) (N / m^1.5)
  double jkr_e = 0;       ///< jkr: 4 E* / (3 R*) (N / m^3)
  double jkr_x0 = 0;      ///< jkr: p^(1/3), sqrt(a) at delta = 0 (m^0.5)
  double break_depth = 0;   ///< jkr: delta_c (m), a bond breaks below -delta_c
  double break_energy = 0;  ///< jkr: the pair's stored energy at pull-off (J, negative: still bound there)
};

/// Normal damping coefficient c_n = 2 zeta sqrt(k_n m_eff) (N s/m) of a Hooke pair with effective mass m_eff.
inline double damping_coefficient(const ContactLaw& law, double m_eff) {
  return 2 * law.damping_ratio * std::sqrt(law.normal_stiffness * m_eff);
}

/// The normal damping coefficient of a pair of effective mass m_eff (kg): c_n (N s/m) for hooke, otherwise c_n's
/// value per sqrt(a), 2 zeta sqrt(3/2 k_N m_eff) (critical damping of the tangent stiffness dF/d delta = 3/2 k_N a).
inline double pair_damping(const ContactLaw& law, double m_eff) {
  return law.normal == NormalModel::hooke ? damping_coefficient(law, m_eff)
                                          : 2 * law.damping_ratio * std::sqrt(1.5 * law.normal_stiffness * m_eff);
}

/// `law`'s constants for a pair of effective radius r_eff (m) and mass m_eff (kg), time step dt (s). Only the
/// dashpots depend on the mass: loops over pairs of one radius set them per pair with set_pair_damping().
PairLaw pair_law(const ContactLaw& law, double r_eff, double m_eff, double dt);
/// Sets c's dashpots (cn, ct and dt_per_ct) for a pair of effective mass m_eff (kg) under `law`.
void set_pair_damping(PairLaw& c, const ContactLaw& law, double m_eff);

/// One contact's outcome: force on the first body along the normal and tangent, and the step's energy terms.
struct ContactTerms {
  double fx, fy, fz;  ///< force on the first body (N); 0 when not in contact
  double normal;      ///< signed normal force, compressive positive (N)
  double overlap;     ///< delta while in contact, else 0 (m)
  double energy;      ///< stored after the step (J): the normal law's potential plus the spring's k |xi|^2 / 2
  double damping;     ///< the dashpots' work in the step (J), the tangential one only while sticking; jkr: plus the
                      ///< stored energy a bond gives up when it is made or broken (the adhesion hysteresis)
  double friction;    ///< sliding's loss in the step (J): the Coulomb force times the slip
  bool contact, slip;
};

/// The contact radius a (m) at overlap delta (m), and for jkr x = sqrt(a) (m^0.5); 0 where the law has no use for it
/// (hooke with linear_history).
template <NormalModel N, TangentialModel T>
inline __attribute__((always_inline)) void contact_radius(const PairLaw& c, double delta, double& a, double& x) {
  // Contact radius a: sqrt(R* delta) for the Hertz family and mindlin; jkr's is the largest root of the quartic in
  // x = sqrt(a), f(x) = x^4 - p x - R* delta = 0, by Newton from x0 = max((R* delta)^(1/4), p^(1/3)): f is convex and
  // increasing beyond the displacement-controlled instability, and x0 lies within 19 % of the root for delta >= 0
  // (below it: one step overshoots, then the iterates fall monotonically) and above it by at most 10 % down to the
  // pull-off distance. Six steps reach rounding; divisions and square roots only, so the loop stays vectorised
  // (a cube root is a scalar call).
  if constexpr (N == NormalModel::jkr) {
    const double rd = c.r_eff * delta;
    x = std::max(std::sqrt(std::sqrt(std::max(rd, 0.0))), c.jkr_x0);
    // Written out: a loop here, even of fixed count, kept GCC from vectorising the candidates' loop.
    const auto newton = [&](double y) { return y - (y * y * y * y - c.jkr_p * y - rd) / (4 * y * y * y - c.jkr_p); };
    x = newton(newton(newton(newton(newton(newton(x))))));
    a = x * x;
  } else if constexpr (N != NormalModel::hooke || T == TangentialModel::mindlin) {
    a = std::sqrt(c.r_eff * std::max(delta, 0.0));
  }
}

/// The normal law's potential at overlap delta (J), zero at first touch, with the contact radius a (m) and, for jkr,
/// x = sqrt(a) as contact_terms() computes them: hooke k_n delta^2 / 2; Hertz 2/5 F delta; dmt minus the attraction's
/// F_pulloff delta; jkr the integral of F along its curve from a = 0, 8 E* a^5 / (15 R*^2) - 2/3 jkr_w a^3 x / R* +
/// 2 pi gamma a^2 (2 pi gamma = jkr_w^2 / (8 E*) = jkr_w^2 / (6 jkr_e R*)).
template <NormalModel N>
inline __attribute__((always_inline)) double normal_potential(const PairLaw& c, double delta, double a, double x) {
  if constexpr (N == NormalModel::hooke) {
    return 0.5 * c.kn * delta * delta;
  } else if constexpr (N == NormalModel::jkr) {
    const double a2 = a * a;
    return a2 * (0.4 * c.jkr_e * a2 * a / c.r_eff - (2.0 / 3) * c.jkr_w * a * x / c.r_eff +
                 c.jkr_w * c.jkr_w / (6 * c.jkr_e * c.r_eff));
  } else {
    return 0.4 * c.kn * a * delta * delta - (is_cohesive(N) ? c.pulloff * delta : 0.0);
  }
}

/// The law for one candidate: unit normal (nx, ny, nz) from the second body to the first, overlap `delta` (m,
/// negative when apart), `touching` (the centres closer than the contact distance, as the caller measured it),
/// relative velocity of the first body at the contact point (vx, vy, vz) (m/s), which moves the shear history, and
/// the velocity the dashpots see (wx, wy, wz) (m/s; the same, or the lagged one of World's damping_velocity). Updates
/// the shear history (hx, hy, hz) (m) and, for jkr, the bond flag (1 bonded, 0 not): a pair out of contact forgets
/// both. Branch-free (selects only), so the kernel's loop vectorises across candidates; N and T are fixed per run.
/// `Stored`: whether to compute `energy` (the contact kernels leave it to pair_stored_energy(), 0 here).
template <NormalModel N, TangentialModel T, bool Stored = true>
inline __attribute__((always_inline)) ContactTerms contact_terms(const PairLaw& c, double delta, bool touching, double nx,
                                                                 double ny, double nz, double vx, double vy, double vz,
                                                                 double wx, double wy, double wz, double& hx_io,
                                                                 double& hy_io, double& hz_io, double& bond_io) {
  constexpr bool hooke = N == NormalModel::hooke, jkr = N == NormalModel::jkr;
  constexpr bool cohesive = is_cohesive(N), mindlin = T == TangentialModel::mindlin;
  const double kn = c.kn, dt = c.dt;
  // A jkr bond holds past delta = 0 down to -delta_c; every other law touches while the centres are within reach.
  // (Bitwise, not short-circuit, operators: branches would stop the kernel's loop from vectorising.)
  const bool bonded = jkr & (bond_io > 0);
  const bool contact = jkr ? (touching | (bonded & (delta > -c.break_depth))) : touching;

  double a = 0, x = 0;
  contact_radius<N, T>(c, delta, a, x);

  // Normal force: elastic part and damping.
  double fe;
  if constexpr (hooke) fe = kn * delta;
  else if constexpr (jkr) fe = c.jkr_e * a * a * a - c.jkr_w * a * x;
  else fe = kn * a * delta - (cohesive ? c.pulloff : 0.0);
  const double cn = hooke ? c.cn : c.cn * std::sqrt(a), ct = hooke ? c.ct : 0.5 * cn;
  const double kt = mindlin ? c.kt * a : c.kt;
  const double inv_kt = mindlin ? (kt > 0 ? 1 / kt : 0) : c.inv_kt;
  // The sliding loss is cap x slip: s (1 - s) |g|^2 / k_t with a spring; without one (k_t = 0, g = -c_t v_t) all of
  // v_t dt slips, cap |v_t| dt = s |g|^2 dt / c_t.
  const double spring = kt > 0 ? 1.0 : 0.0;
  const double loss = kt > 0 ? inv_kt : (hooke ? c.dt_per_ct : (ct > 0 ? dt / ct : 0.0));
  const double vn = vx * nx + vy * ny + vz * nz;
  const double tx = vx - vn * nx, ty = vy - vn * ny, tz = vz - vn * nz;
  // The dashpots' velocity, normal and tangential.
  const double wn = wx * nx + wy * ny + wz * nz;
  const double sx = wx - wn * nx, sy = wy - wn * ny, sz = wz - wn * nz;
  const double fn = fe - cn * wn;

  // Shear history: into the current tangent plane, length kept, then the tangential increment.
  double hx = hx_io, hy = hy_io, hz = hz_io;
  const double len2 = hx * hx + hy * hy + hz * hz;
  const double along = hx * nx + hy * ny + hz * nz;
  hx -= along * nx, hy -= along * ny, hz -= along * nz;
  const double proj2 = hx * hx + hy * hy + hz * hz;
  const double keep = proj2 > 0 ? std::sqrt(len2 / proj2) : 1.0;
  hx = hx * keep + tx * dt, hy = hy * keep + ty * dt, hz = hz * keep + tz * dt;

  // Tangential force with the Coulomb cap; on slip the spring is reset to match the cap.
  double gx = -kt * hx - ct * sx, gy = -kt * hy - ct * sy, gz = -kt * hz - ct * sz;
  const double cap = c.mu * std::abs(cohesive ? fe + 2 * c.pulloff : fn);
  const double g2 = gx * gx + gy * gy + gz * gz;
  const bool slip = g2 > cap * cap;
  const double scale = slip ? cap / std::sqrt(g2) : 1.0;
  gx *= scale, gy *= scale, gz *= scale;
  hx = slip ? -(gx + ct * sx) * inv_kt : hx;
  hy = slip ? -(gy + ct * sy) * inv_kt : hy;
  hz = slip ? -(gz + ct * sz) * inv_kt : hz;

  // Pairs out of contact forget their history and exert nothing.
  hx_io = contact ? hx : 0.0, hy_io = contact ? hy : 0.0, hz_io = contact ? hz : 0.0;
  ContactTerms out;
  out.fx = contact ? fn * nx + gx : 0.0, out.fy = contact ? fn * ny + gy : 0.0, out.fz = contact ? fn * nz + gz : 0.0;
  out.normal = contact ? fn : 0.0;
  out.contact = contact;
  out.slip = contact && slip;
  out.overlap = contact ? delta : 0.0;
  // jkr's hysteresis below needs the potential whether or not the stored energy is asked for.
  const double potential = Stored || jkr ? normal_potential<N>(c, delta, a, x) : 0.0;
  out.energy = Stored && contact ? potential + 0.5 * kt * (hx * hx + hy * hy + hz * hz) : 0.0;
  // This step's losses: the dashpots' work over the step's motion (their force times v dt), the tangential one only
  // while sticking, and on slip the Coulomb force times the slip, cap (1 - scale) |g| / k_t.
  out.damping = contact ? dt * (cn * wn * vn + (slip ? 0.0 : ct * (sx * tx + sy * ty + sz * tz))) : 0.0;
  if constexpr (jkr) {
    // A bond made jumps onto the curve below zero energy (the snap-in gives up -potential); one broken leaves it at
    // break_energy and returns to zero. Both are the adhesion hysteresis, counted with the losses.
    out.damping += ((contact & !bonded) ? -potential : 0.0) + ((bonded & !contact) ? c.break_energy : 0.0);
    bond_io = contact ? 1.0 : 0.0;
  }
  out.friction = contact && slip ? scale * (1 - spring * scale) * g2 * loss : 0.0;
  return out;
}

/// The scalar form for one contact, as the sphere-wall loop and the tests use it.
struct ContactForce {
  Vec3 force;       ///< force on the first body (N)
  double normal;    ///< signed normal force magnitude, compressive positive (N)
  bool sliding;     ///< true when the Coulomb cap was active
  double energy;    ///< stored after the step (J), as ContactTerms
  double damping;   ///< the dashpots' work in the step (J), as ContactTerms
  double friction;  ///< sliding's loss in the step (J), as ContactTerms
};

/// Force on body i from a contact with unit normal `n` (pointing from j to i), overlap `delta` (m; in contact while
/// positive, or for a bonded jkr pair down to -delta_c), relative velocity of i with respect to j at the contact
/// point `v_rel` (m/s), under the pair's constants `c` (pair_law()). Updates the shear history `xi` (m) and `bond`
/// in place; the law is chosen at run time (once per call: loops over many contacts use contact_terms directly).
ContactForce contact_force(const ContactLaw& law, const PairLaw& c, const Vec3& n, double delta, const Vec3& v_rel,
                           Vec3& xi, double& bond);
/// The same with the dashpots seeing `v_damping` (m/s) rather than v_rel (WorldSettings::damping_velocity).
ContactForce contact_force(const ContactLaw& law, const PairLaw& c, const Vec3& n, double delta, const Vec3& v_rel,
                           const Vec3& v_damping, Vec3& xi, double& bond);

/// The same for a non-bonding pair of effective radius r_eff (m) and mass m_eff (kg).
ContactForce contact_force(const ContactLaw& law, const Vec3& n, double delta, const Vec3& v_rel, double r_eff,
                           double m_eff, double dt, Vec3& xi);

}  // namespace granulab
