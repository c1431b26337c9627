#include "engine/contact/contact_law.h"

#include <array>
#include <utility>

namespace granulab {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr std::array<std::pair<NormalModel, const char*>, 5> kNormalNames{{{NormalModel::hooke, "hooke"},
                                                                            {NormalModel::hertz, "hertz"},
                                                                            {NormalModel::hertz_material, "hertz/material"},
                                                                            {NormalModel::dmt, "dmt"},
                                                                            {NormalModel::jkr, "jkr"}}};
constexpr std::array<std::pair<TangentialModel, const char*>, 2> kTangentialNames{
    {{TangentialModel::linear_history, "linear_history"}, {TangentialModel::mindlin, "mindlin"}}};
}  // namespace

std::string to_string(NormalModel m) {
  for (const auto& [model, name] : kNormalNames)
    if (model == m) return name;
  return "?";
}

std::string to_string(TangentialModel m) {
  for (const auto& [model, name] : kTangentialNames)
    if (model == m) return name;
  return "?";
}

std::vector<std::string> normal_model_names() {
  std::vector<std::string> out;
  for (const auto& [model, name] : kNormalNames) out.push_back(name);
  return out;
}

std::vector<std::string> tangential_model_names() {
  std::vector<std::string> out;
  for (const auto& [model, name] : kTangentialNames) out.push_back(name);
  return out;
}

bool normal_model_from_string(const std::string& name, NormalModel& out) {
  for (const auto& [model, n] : kNormalNames)
    if (name == n) return out = model, true;
  return false;
}

bool tangential_model_from_string(const std::string& name, TangentialModel& out) {
  for (const auto& [model, n] : kTangentialNames)
    if (name == n) return out = model, true;
  return false;
}

double ContactLaw::pulloff_force(double r_eff) const {
  if (normal == NormalModel::dmt) return 4 * kPi * surface_energy * r_eff;
  if (normal == NormalModel::jkr) return 3 * kPi * surface_energy * r_eff;
  return 0;
}

namespace {
// jkr's force is most tensile, -3 pi gamma R*, where dF/da = 0: at the contact radius a_c, a_c^3 = 9 pi gamma R*^2 /
// (4 E*). LAMMPS ends the bond there (its pull-off distance), before the displacement-controlled instability at
// a^3 = pi gamma R*^2 / (4 E*).
double pulloff_radius(const ContactLaw& law, double r_eff) {
  return std::cbrt(9 * kPi * law.surface_energy * r_eff * r_eff / (4 * law.effective_modulus));
}
}  // namespace

double ContactLaw::pulloff_distance(double r_eff) const {
  if (normal != NormalModel::jkr || !(surface_energy > 0)) return 0;
  const double ac = pulloff_radius(*this, r_eff);
  return -(ac * ac / r_eff - 2 * std::sqrt(kPi * surface_energy * ac / effective_modulus));
}

double ContactLaw::pair_stiffness(double r_eff, double force) const {
  if (normal == NormalModel::hooke) return normal_stiffness;
  return 1.5 * std::cbrt(normal_stiffness * normal_stiffness * r_eff * std::max(force, 0.0));
}

void set_pair_damping(PairLaw& c, const ContactLaw& law, double m_eff) {
  c.cn = pair_damping(law, m_eff);
  c.ct = c.cn / 2;
  c.dt_per_ct = c.ct > 0 ? c.dt / c.ct : 0;
}

PairLaw pair_law(const ContactLaw& law, double r_eff, double m_eff, double dt) {
  PairLaw c;
  c.kn = law.normal_stiffness, c.kt = law.tangential_stiffness;
  c.mu = law.friction, c.dt = dt, c.r_eff = r_eff;
  c.inv_kt = c.kt > 0 ? 1 / c.kt : 0;
  set_pair_damping(c, law, m_eff);
  c.pulloff = law.pulloff_force(r_eff);
  if (law.normal == NormalModel::jkr) {
    const double e = law.effective_modulus, g = law.surface_energy;
    c.jkr_p = 2 * r_eff * std::sqrt(kPi * g / e);
    c.jkr_w = 4 * std::sqrt(kPi * g * e);
    c.jkr_e = 4 * e / (3 * r_eff);
    c.jkr_x0 = std::cbrt(c.jkr_p);
    c.break_depth = law.pulloff_distance(r_eff);
    const double ac = pulloff_radius(law, r_eff);
    c.break_energy = ac * ac *
                     (0.4 * c.jkr_e * ac * ac * ac / r_eff - (2.0 / 3) * c.jkr_w * ac * std::sqrt(ac) / r_eff +
                      c.jkr_w * c.jkr_w / (6 * c.jkr_e * r_eff));
  }
  return c;
}

namespace {
template <NormalModel N, TangentialModel T>
ContactForce scalar_contact(const PairLaw& c, const Vec3& n, double delta, const Vec3& v_rel, const Vec3& v_damping,
                            Vec3& xi, double& bond) {
  double hx = xi.x(), hy = xi.y(), hz = xi.z();
  const ContactTerms t = contact_terms<N, T>(c, delta, delta > 0, n.x(), n.y(), n.z(), v_rel.x(), v_rel.y(), v_rel.z(),
                                             v_damping.x(), v_damping.y(), v_damping.z(), hx, hy, hz, bond);
  xi = Vec3(hx, hy, hz);
  return {Vec3(t.fx, t.fy, t.fz), t.normal, t.slip, t.energy, t.damping, t.friction};
}

template <NormalModel N>
ContactForce scalar_contact(TangentialModel tangential, const PairLaw& c, const Vec3& n, double delta,
                            const Vec3& v_rel, const Vec3& v_damping, Vec3& xi, double& bond) {
  return tangential == TangentialModel::mindlin
             ? scalar_contact<N, TangentialModel::mindlin>(c, n, delta, v_rel, v_damping, xi, bond)
             : scalar_contact<N, TangentialModel::linear_history>(c, n, delta, v_rel, v_damping, xi, bond);
}
}  // namespace

ContactForce contact_force(const ContactLaw& law, const PairLaw& c, const Vec3& n, double delta, const Vec3& v_rel,
                           Vec3& xi, double& bond) {
  return contact_force(law, c, n, delta, v_rel, v_rel, xi, bond);
}

ContactForce contact_force(const ContactLaw& law, const PairLaw& c, const Vec3& n, double delta, const Vec3& v_rel,
                           const Vec3& v_damping, Vec3& xi, double& bond) {
  switch (law.normal) {
    case NormalModel::hooke: return scalar_contact<NormalModel::hooke>(law.tangential, c, n, delta, v_rel, v_damping, xi, bond);
    case NormalModel::hertz: return scalar_contact<NormalModel::hertz>(law.tangential, c, n, delta, v_rel, v_damping, xi, bond);
    case NormalModel::hertz_material:
      return scalar_contact<NormalModel::hertz_material>(law.tangential, c, n, delta, v_rel, v_damping, xi, bond);
    case NormalModel::dmt: return scalar_contact<NormalModel::dmt>(law.tangential, c, n, delta, v_rel, v_damping, xi, bond);
    case NormalModel::jkr: return scalar_contact<NormalModel::jkr>(law.tangential, c, n, delta, v_rel, v_damping, xi, bond);
  }
  return {};
}

ContactForce contact_force(const ContactLaw& law, const Vec3& n, double delta, const Vec3& v_rel, double r_eff,
                           double m_eff, double dt, Vec3& xi) {
  double bond = 0;
  return contact_force(law, pair_law(law, r_eff, m_eff, dt), n, delta, v_rel, xi, bond);
}

}  // namespace granulab
