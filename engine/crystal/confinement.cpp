#include "engine/crystal/confinement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace granulab {

void write_confinement(SummaryWriter& w, const ConfinementReport& r) {
  w.begin_group("confinement");
  w.count("steps", r.steps);
  w.flag("converged", r.converged);
  w.number("stress_top", r.stress_top, "Pa");
  w.number("stress_bottom", r.stress_bottom, "Pa");
  w.number("lateral_stress_x", r.lateral_stress_x, "Pa");
  w.number("lateral_stress_y", r.lateral_stress_y, "Pa");
  w.number("kinetic_elastic_ratio", r.kinetic_elastic_ratio, "-");
  w.end_group();
}

void write_confinement_warning(SummaryWriter& w, const ConfinementReport& r) {
  if (r.converged) return;
  w.text(nullptr, "confinement stopped after " + std::to_string(r.steps) +
                      " steps without reaching equilibrium (platen stresses " + std::to_string(r.stress_top) + " and " +
                      std::to_string(r.stress_bottom) + " Pa, kinetic/elastic energy " +
                      std::to_string(r.kinetic_elastic_ratio) +
                      "), near it (within 5 and 10 times the criterion): what follows started from a sample close to, "
                      "not at, rest");
}

namespace {
std::string confinement_failure(const ConfinementReport& r, const CrystalSampleParams& p) {
  char text[800];
  std::snprintf(text, sizeof text,
                "confinement failed: after %llu steps (the cap, max_confinement_steps) the platens carry %.4g and "
                "%.4g kPa against p0 = %.4g kPa, the packing %.4g and %.4g kPa laterally, and the kinetic energy is "
                "%.2g of the elastic energy (equilibrium: platens within %.3g %% of p0 and kinetic/elastic below %.2g "
                "at %d checks in a row; loaded anyway, with a warning, within 5 and 10 times those and the packing within "
                "10 %% of p0); a sample this far "
                "from rest is not loaded, so this job reports no result "
                "(docs/model.md, \"Confinement\")",
                static_cast<unsigned long long>(r.steps), r.stress_top / 1e3, r.stress_bottom / 1e3,
                p.confining_pressure / 1e3, r.lateral_stress_x / 1e3, r.lateral_stress_y / 1e3,
                r.kinetic_elastic_ratio, 100 * p.equilibrium_tolerance, p.kinetic_tolerance, p.equilibrium_checks);
  return text;
}

// How the dynamic grains' motion now and one step before line up: sum m v.u / sqrt(sum m v^2 sum m u^2) over their
// velocities, the same over their angular velocities weighted by their mean principal inertia, and the smaller of the
// two (-). About 1 for motion the step resolves, about -1 for a vibration at the step's own period 2 h. (At a step too
// long for the damping it was the spins that reversed, a rocking of the grains at -0.9 to -0.98, while the
// translations, 95 % of the kinetic energy, stayed smooth at +1.)
double step_to_step_correlation(const Bodies& bodies, const std::vector<Vec3>& velocity_before,
                                const std::vector<Vec3>& spin_before) {
  double vu = 0, vv = 0, uu = 0, ws = 0, ww = 0, ss = 0;
  for (std::size_t b = 0; b < bodies.size() && b < velocity_before.size() && b < spin_before.size(); ++b) {
    if (bodies.motion[b] != Motion::dynamic) continue;
    const Vec3 &v = bodies.velocity[b], &w = bodies.angular_velocity[b];
    const double m = bodies.mass[b], i = bodies.inertia[b].sum() / 3;
    vu += m * v.dot(velocity_before[b]), vv += m * v.squaredNorm(), uu += m * velocity_before[b].squaredNorm();
    ws += i * w.dot(spin_before[b]), ww += i * w.squaredNorm(), ss += i * spin_before[b].squaredNorm();
  }
  const double moving = vv > 0 && uu > 0 ? vu / std::sqrt(vv * uu) : 1.0;
  const double turning = ww > 0 && ss > 0 ? ws / std::sqrt(ww * ss) : 1.0;
  return std::min(moving, turning);
}

std::string unstable_step_message(double correlation, double kinetic_elastic, const CrystalSampleParams& p) {
  char text[700];
  std::snprintf(text, sizeof text,
                "the time step is unstable for this damping: at %d checks in a row the grains' motion reversed "
                "from one step to the next (correlation %.2f between consecutive steps; kinetic energy %.2g of the "
                "elastic energy), a vibration the step cannot resolve and the dashpots cannot settle, so the "
                "confinement would never come to rest. Lower run.time_step_factor (now %.3g) or material.damping (now "
                "%.3g): the stable step falls as the damping rises (docs/model.md, \"Damping velocity\")",
                p.equilibrium_checks, correlation, kinetic_elastic, p.time_step_factor, p.material.damping);
  return text;
}
}  // namespace

ConfinementFailed::ConfinementFailed(const ConfinementReport& r, const CrystalSampleParams& p)
    : std::runtime_error(confinement_failure(r, p)) {}

void require_confined(const ConfinementReport& r, const CrystalSampleParams& p) {
  if (r.converged || !p.require_equilibrium) return;
  // Near equilibrium at the cap (the criterion missed only by its three checks in a row, a platen ringing within a few
  // tolerances): loaded, with the summary's warning. Far from it (platens at 19 of 30 kPa, kinetic/elastic 0.68): no
  // result. The bands are 5 times the platens' tolerance and 10 times the kinetic one.
  const double sigma = cohesive_stress_scale(p) > p.confining_pressure ? cohesive_stress_scale(p) : p.confining_pressure;
  const double platen_error =
      std::max(std::abs(r.stress_top - p.confining_pressure), std::abs(r.stress_bottom - p.confining_pressure)) / sigma;
  // The packing must carry the bag's p0 too (its virial lateral stresses, within 10 tolerances: other lattices' sit a
  // few % off it): two grains that never touch each other have platens at p0 and no elastic energy to measure the
  // kinetic one against, but no lateral stress at all.
  const double lateral_error = std::max(std::abs(r.lateral_stress_x - p.confining_pressure),
                                        std::abs(r.lateral_stress_y - p.confining_pressure)) / sigma;
  const bool near = platen_error <= 5 * p.equilibrium_tolerance && lateral_error <= 10 * p.equilibrium_tolerance &&
                    r.kinetic_elastic_ratio <= 10 * p.kinetic_tolerance;
  if (!near) throw ConfinementFailed(r, p);
}

double confinement_progress_steps(const CrystalSample& sample) {
  return 20 * 50 * sample.contact_time() / sample.world().settings().time_step;
}

ConfinementReport confine(CrystalSample& sample, const ProgressFn& progress, const ConfinementCheck& on_check,
                          ConfinementState* state, const std::function<void()>& safe_point) {
  ConfinementReport r;
  const CrystalSampleParams& p = sample.params();
  World& world = sample.world();
  const double p0 = p.confining_pressure;
  const std::size_t top = sample.top_wall(), bottom = sample.bottom_wall();
  // Servo: wall speed = force error / (K tau). K = the stiffness of the wall's own contacts, an upper
  // bound of the wall-sample stiffness (springs in series), so the force error decays no faster than
  // with time constant tau, which is kept well above the sample's response time (~ L/c ~ 10 t0).
  const double servo_time = 50 * sample.contact_time();
  const ContactLaw& law = world.law();
  const double kn = law.normal_stiffness;
  // Quietness is kinetic energy against the contacts' stored energy. Cohesion's potential (negative: -F_pulloff delta,
  // JKR's curve) can bring that near zero or below, so a cohesive crystal compares with no less than the energy its
  // stresses would store in the grains' material, sigma^2 / (2 E) over the sample's volume, sigma the larger of p0 and
  // the cohesive stress scale (a lower bound: the crystal is softer than its material). Cohesion presses the contacts
  // to sigma whatever p0 is, so the platens' stress is held to p0 within the tolerance times sigma too: its ringing
  // is of that order. (With p0 in both, the paper's crystal at N_e = 10, dmt, gamma 2 J/m^2, p0 100 Pa was not
  // confined after 7 min, some 100,000 steps.)
  const double sigma = law.cohesive() ? std::max(p0, cohesive_stress_scale(p)) : p0;
  const double cohesive_floor =
      law.cohesive() ? sigma * sigma / (2 * p.material.youngs_modulus) * sample.cross_section() * crystal_length_estimate(p)
                     : 0.0;
  ConfinementState own;
  ConfinementState& s = state ? *state : own;
  if (!s.begun) s = {true, world.steps(), 0};
  int& good = s.good;
  const std::uint64_t start = s.start;
  double& control_time = world.stage_times().control;
  // A step past the bound of the damped modes does not blow up: the grains' spins reverse every step, held by the
  // contacts' sliding, and the kinetic energy stays (a 3 x 6 x 2 crystal of N_e = 4 at damping 0.3 and the
  // default step: kinetic/elastic 0.39 after 200,000 steps; fine at 0.2 t0). Each check compares the grains'
  // motion with that one step before. (Not checkpointed: a resumed confinement starts counting again.)
  std::vector<Vec3> velocity_before, spin_before;
  int reversing = 0;
  while (world.steps() - start < p.max_confinement_steps) {
    std::optional<StageTimer> control(control_time);
    for (std::size_t w : {top, bottom}) {
      Wall& wall = world.walls()[w];
      const double error = (p0 - sample.axial_stress(w)) * sample.cross_section();  // N; > 0: push in
      const double contacts = double(std::max<std::size_t>(1, wall.contacts));
      // A Hertz contact stiffens with its load: at the larger of the present and the target force per contact.
      const double stiffness =
          law.normal == NormalModel::hooke
              ? kn * contacts
              : contacts * law.pair_stiffness(sample.grain().radius(),
                                              std::max(std::abs(wall.force.dot(wall.normal)), p0 * sample.cross_section()) /
                                                  contacts);
      // At most a tenth of the skin per step, so a wall far from contact cannot jump into the spheres.
      const double max_speed = 0.1 * world.settings().skin / world.settings().time_step;
      wall.velocity = wall.normal * std::clamp(error / (stiffness * servo_time), -max_speed, max_speed);
    }
    if ((world.steps() + 1 - start) % std::uint64_t(p.membrane_interval) == 0)
      velocity_before = world.bodies().velocity, spin_before = world.bodies().angular_velocity;
    control.reset();
    if (sample.step(start)) {
      {
        StageTimer t(control_time);
        const double ke = world.kinetic_energy(),
                     ee = law.cohesive() ? std::max(world.elastic_energy(), cohesive_floor)
                                         : world.elastic_energy();
        const bool walls_ok = std::abs(sample.axial_stress(top) - p0) <= p.equilibrium_tolerance * sigma &&
                              std::abs(sample.axial_stress(bottom) - p0) <= p.equilibrium_tolerance * sigma;
        const bool quiet = ke <= p.kinetic_tolerance * ee;
        good = walls_ok && quiet ? good + 1 : 0;
        const double correlation = step_to_step_correlation(world.bodies(), velocity_before, spin_before);
        reversing = !quiet && correlation < -0.5 ? reversing + 1 : 0;
        if (reversing >= p.equilibrium_checks)
          throw UnstableTimeStep(unstable_step_message(correlation, ee > 0 ? ke / ee : 0.0, p));
      }
      if (on_check) {
        StageTimer recording(world.stage_times().record);
        on_check(world.steps() - start);
      }
      if (good >= p.equilibrium_checks) {
        r.converged = true;
        break;
      }
    }
    // Every step (milliseconds to a second on a crystal): a cancel or a shutdown is seen at once, and a
    // checkpoint may be taken; the whole state is the world and `s`.
    StageTimer recording(world.stage_times().record);
    if (progress && !progress(1 - std::exp(-double(world.steps() - start) / confinement_progress_steps(sample))))
      throw Cancelled();
    if (safe_point) safe_point();
  }
  for (Wall& w : world.walls()) w.velocity.setZero();
  r.steps = world.steps() - start;
  r.stress_top = sample.axial_stress(top);
  r.stress_bottom = sample.axial_stress(bottom);
  std::tie(r.lateral_stress_x, r.lateral_stress_y) = sample.lateral_stresses();
  r.kinetic_elastic_ratio = sample.kinetic_elastic_ratio();
  return r;
}

}  // namespace granulab
