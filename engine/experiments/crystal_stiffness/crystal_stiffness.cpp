#include "engine/experiments/crystal_stiffness/crystal_stiffness.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include "engine/crystal/face_springs.h"
#include "engine/model/model.h"

namespace granulab {

StiffnessParams::StiffnessParams() {
  // A box of about six periods each way: a third of its grains are the interior's at N_e = 4 and above.
  grains_x = 6, rows_z = 6, layers_y = 6;
}

const std::vector<CurveColumn>& StiffnessRow::columns() {
  static const std::vector<CurveColumn> c = {
      {"set", "-", "0: affine (every grain follows the imposed strain), 1: relaxed (the interior free)", 0},
      {"state", "-", "0: the set's reference; then 1..18: component (state - 1) / 3 + 1 to +delta, -delta and 0", 0},
      {"component", "-", "the Voigt strain component imposed: 1 xx, 2 yy, 3 zz, 4 yz, 5 xz, 6 xy (lab frame); 0: none", 0},
      {"imposed_strain", "-", "its value (shear components as engineering strains, 2 eps_ij)"},
      {"stress_xx", "Pa", "the interior's stress less the set's reference, lab frame, tension positive"},
      {"stress_yy", "Pa", "as stress_xx"},
      {"stress_zz", "Pa", "as stress_xx"},
      {"stress_yz", "Pa", "as stress_xx"},
      {"stress_xz", "Pa", "as stress_xx"},
      {"stress_xy", "Pa", "as stress_xx"},
      {"response", "Pa", "the imposed component's stress change: its slope against imposed_strain is C_kk"},
      {"relax_steps", "-", "steps held at the state before it was measured (0 for the affine set)", 0},
      {"converged", "-", "1 when the hold met loading.relax_tolerance, 0 when loading.max_relax_transits cut it", 0},
      {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
      {"contacts", "-", "sphere pairs in contact", 0},
      {"sliding_contacts", "-", "of which at the Coulomb limit", 0},
  };
  return c;
}

std::vector<double> StiffnessRow::values() const {
  return {double(set),   double(state), double(component), imposed_strain, stress[0],        stress[1],
          stress[2],     stress[3],     stress[4],         stress[5],      response,         relax_steps,
          converged ? 1.0 : 0.0, kinetic_elastic_ratio, double(contacts), double(sliding_contacts)};
}

namespace {

// The rows of `set` by state (nullptr where missing).
std::array<const StiffnessRow*, kStiffnessStates + 1> rows_of(const std::vector<StiffnessRow>& rows, int set) {
  std::array<const StiffnessRow*, kStiffnessStates + 1> out{};
  for (const StiffnessRow& row : rows)
    if (row.set == set && row.state >= 0 && row.state <= kStiffnessStates) out[std::size_t(row.state)] = &row;
  return out;
}

Voigt6 stress_of(const StiffnessRow* row) {
  Voigt6 s = Voigt6::Zero();
  if (row)
    for (int k = 0; k < 6; ++k) s[k] = row->stress[k];
  return s;
}

// The passes: 0 conditions affine, 1 measures affine, 2 conditions relaxed, 3 measures relaxed.
constexpr int kPasses = 4;
bool relaxed_pass(int pass) { return pass >= 2; }
bool measured_pass(int pass) { return pass % 2 == 1; }

double amplitude_of(const StiffnessParams& p) {
  return p.strain_amplitude > 0 ? p.strain_amplitude : default_strain_amplitude(p);
}

}  // namespace

double default_strain_amplitude(const CrystalSampleParams& p) { return std::min(1e-3, hydrostatic_prestrain(p) / 4); }

Voigt stiffness_of(const std::vector<StiffnessRow>& rows, int set, double amplitude) {
  const auto by_state = rows_of(rows, set);
  Voigt c = Voigt::Zero();
  for (int k = 0; k < 6; ++k)
    c.col(k) = (stress_of(by_state[std::size_t(3 * k + 1)]) - stress_of(by_state[std::size_t(3 * k + 2)])) /
               (2 * amplitude);
  return c;
}

double stiffness_nonlinearity(const std::vector<StiffnessRow>& rows, int set) {
  const auto by_state = rows_of(rows, set);
  double worst = 0;
  for (int k = 0; k < 6; ++k) {
    const Voigt6 plus = stress_of(by_state[std::size_t(3 * k + 1)]), minus = stress_of(by_state[std::size_t(3 * k + 2)]);
    const double span = (plus - minus).cwiseAbs().maxCoeff();
    if (span > 0) worst = std::max(worst, (plus + minus).cwiseAbs().maxCoeff() / span);
  }
  return worst;
}

double stiffness_hysteresis(const std::vector<StiffnessRow>& rows, int set) {
  const auto by_state = rows_of(rows, set);
  double worst = 0;
  for (int k = 0; k < 6; ++k) {
    const Voigt6 plus = stress_of(by_state[std::size_t(3 * k + 1)]), minus = stress_of(by_state[std::size_t(3 * k + 2)]);
    const double span = (plus - minus).cwiseAbs().maxCoeff();
    if (span > 0) worst = std::max(worst, stress_of(by_state[std::size_t(3 * k + 3)]).cwiseAbs().maxCoeff() / span);
  }
  return worst;
}

std::vector<std::uint8_t> interior_sites(const CrystalSampleParams& p, const CrystalLattice& lattice) {
  // From the lattice as built, so that an imperfect grain that lost a contact is still interior; through a grid of
  // cells one cut-off wide.
  GrainGeometry g = p.grain;
  g.shape = grain_shape(p.lattice);
  const GrainTemplate grain(g);
  const std::vector<LatticeSite>& sites = lattice.sites;
  const double cut = 1.02 * face_neighbour_distance(p, grain);
  const std::size_t faces = grain.solid().faces().size();
  std::map<std::array<long, 3>, std::vector<std::size_t>> cells;
  const auto cell_of = [&](const Vec3& x) {
    return std::array<long, 3>{long(std::floor(x.x() / cut)), long(std::floor(x.y() / cut)), long(std::floor(x.z() / cut))};
  };
  for (std::size_t k = 0; k < sites.size(); ++k) cells[cell_of(sites[k].position)].push_back(k);
  std::vector<std::uint8_t> interior(sites.size(), 0);
  for (std::size_t k = 0; k < sites.size(); ++k) {
    const std::array<long, 3> c = cell_of(sites[k].position);
    std::size_t neighbours = 0;
    for (long i = -1; i <= 1; ++i)
      for (long j = -1; j <= 1; ++j)
        for (long l = -1; l <= 1; ++l) {
          const auto it = cells.find({c[0] + i, c[1] + j, c[2] + l});
          if (it == cells.end()) continue;
          for (std::size_t m : it->second) neighbours += m != k && (sites[m].position - sites[k].position).norm() < cut;
        }
    interior[k] = neighbours >= faces;
  }
  return interior;
}

StiffnessSchedule stiffness_schedule(const StiffnessParams& p) {
  StiffnessSchedule s;
  s.size = sample_lattice(p).extent.maxCoeff();
  s.transit_steps = s.size / crystal_wave_speed(p) / crystal_time_step(p);
  s.ramp_steps = std::max(1.0, std::ceil(p.ramp_transits * s.transit_steps));
  s.check_steps = std::max(1.0, std::ceil(4 * s.transit_steps));
  const double affine = 2 * kStiffnessStates * double(p.affine_ramp_steps + 1);  // conditioning and affine
  // A hold ends at a check: when it has met the tolerance (relax_checks + 1 checks at least), or at the first check
  // at or past max_relax_transits.
  const double hold_max = s.check_steps * std::max(1.0, std::ceil(p.max_relax_transits * s.transit_steps / s.check_steps));
  const double hold = std::min((p.relax_checks + 1) * s.check_steps, hold_max);
  s.expected_steps = affine + 2 * (hold + kStiffnessStates * (s.ramp_steps + hold));
  s.max_steps = affine + 2 * (kStiffnessStates + 1) * hold_max + 2 * kStiffnessStates * s.ramp_steps;
  return s;
}

struct CrystalStiffness::Run {
  ResultSink& sink;
  StiffnessResult& r;
  Position& at;
  StiffnessSchedule schedule;
  double share = 0, confinement_steps = 0;
};

CrystalStiffness::CrystalStiffness(const StiffnessParams& params) : params_(params), sample_(params_) {}

Mat3 CrystalStiffness::interior_stress() const {
  const World& world = sample_.world();
  const std::vector<BodyPairSpan>& pairs = world.neighbors().body_pairs();
  const std::vector<Vec3>& force = world.pair_forces();
  const std::vector<Vec3>& x = world.bodies().position;
  Mat3 sum = Mat3::Zero();
  for (std::size_t k = 0; k < pairs.size() && k < force.size(); ++k) {
    const double weight = double(interior_[pairs[k].a]) + double(interior_[pairs[k].b]);
    if (weight == 0) continue;
    // Each interior grain of the pair adds (contact - centre) (x) f; for the two together that is -l (x) f exactly,
    // l = x_a - x_b; for one, about half of it (the contact near the middle of l).
    sum -= 0.5 * weight * (x[pairs[k].a] - x[pairs[k].b]) * force[k].transpose();
  }
  return volume_ > 0 ? Mat3(sum / volume_) : Mat3::Zero();
}

void CrystalStiffness::safe_point(Run& run) const {
  if (run.sink.checkpoint_due())
    run.sink.checkpoint([&](CheckpointWriter& out) { save(out, run.at, run.r); }, run.r.curve.size(), 0);
}

// After confinement: the platens step back, the interior is found, the reference is taken.
void CrystalStiffness::confine_and_begin(Run& run) {
  const auto progress = [&](double f) {
    const double steps = -std::log(std::max(1e-12, 1 - f)) * confinement_progress_steps(sample_);
    return run.sink.progress(run.share * std::min(1.0, steps / run.confinement_steps));
  };
  run.r.confinement = confine(sample_, progress, nullptr, &run.at.confinement, [&] { safe_point(run); });
  require_confined(run.r.confinement, sample_.params());
  World& world = sample_.world();
  std::vector<Wall>& walls = world.walls();
  walls[sample_.top_wall()].point += 2 * params_.grain.size * Vec3::UnitZ();
  walls[sample_.bottom_wall()].point -= 2 * params_.grain.size * Vec3::UnitZ();
  for (Wall& w : walls) w.velocity.setZero();
  const std::vector<LatticeSite>& sites = sample_.lattice().sites;
  interior_ = interior_sites(params_, sample_.lattice());
  const std::size_t inside = std::size_t(std::count(interior_.begin(), interior_.end(), 1));
  if (inside == 0)
    throw std::invalid_argument("the sample has no grain with a neighbour across every face: make crystal.grains_x, "
                                "crystal.rows_z and crystal.layers_y larger");
  const double shrink = 1 - hydrostatic_prestrain(params_);
  volume_ = double(inside) * lattice_cell(params_.lattice, params_.grain.size).site_volume() * shrink * shrink * shrink;
  reference_ = world.bodies().position;
  centre_.setZero();
  for (const Vec3& x : reference_) centre_ += x;
  centre_ /= double(std::max<std::size_t>(1, reference_.size()));
  StiffnessResult& r = run.r;
  r.amplitude = amplitude_of(params_);
  r.interior_grains = inside;
  r.boundary_grains = sites.size() - inside;
  r.interior_volume = volume_;
  r.sample_size = run.schedule.size;
  run.at.begun = true;
  run.at.first = world.steps();
  run.at.pass = 0;
  begin_set(run);
}

// The set's motions (affine: every grain prescribed; relaxed: the boundary only), all at rest, and its reference.
void CrystalStiffness::begin_set(Run& run) {
  Position& at = run.at;
  World& world = sample_.world();
  Bodies& bodies = world.bodies();
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    bodies.motion[k] = relaxed_pass(at.pass) && interior_[k] ? Motion::dynamic : Motion::prescribed;
    bodies.velocity[k].setZero();
    bodies.angular_velocity[k].setZero();
    bodies.angular_momentum[k].setZero();
  }
  world.compute_forces();
  at.state = 0;
  at.ramping = false;
  at.stage_first = world.steps();
  at.good = 0;
  std::fill(at.from, at.from + 6, 0.0);
  std::fill(at.to, at.to + 6, 0.0);
  std::fill(at.last, at.last + 6, 0.0);
  if (!relaxed_pass(at.pass)) record(run, true);  // nothing moves: the state as it is is the reference
}

// The next state's imposed strain: component (state - 1) / 3 to +delta, -delta, then 0.
void CrystalStiffness::target(Position& at) const {
  std::copy(at.to, at.to + 6, at.from);
  std::fill(at.to, at.to + 6, 0.0);
  const int k = (at.state - 1) / 3, which = (at.state - 1) % 3;
  const double delta = amplitude_of(params_);
  at.to[k] = which == 0 ? delta : which == 1 ? -delta : 0.0;
  at.ramping = true;
  at.stage_first = sample_.world().steps();
  at.good = 0;
}

void CrystalStiffness::record(Run& run, bool converged) {
  Position& at = run.at;
  const World& world = sample_.world();
  if (!measured_pass(at.pass)) return advance(run);  // conditioning
  const Voigt6 s = stress_voigt(interior_stress());
  const int set = at.pass / 2;
  if (at.state == 0)
    for (int k = 0; k < 6; ++k) run.r.reference_stress[set][k] = s[k];
  StiffnessRow row;
  row.set = set;
  row.state = at.state;
  row.component = at.state == 0 ? 0 : (at.state - 1) / 3 + 1;
  row.imposed_strain = row.component > 0 ? at.to[row.component - 1] : 0.0;
  for (int k = 0; k < 6; ++k) row.stress[k] = s[k] - run.r.reference_stress[set][k];
  row.response = row.component > 0 ? row.stress[row.component - 1] : 0.0;
  row.relax_steps = set == 1 ? double(world.steps() - at.stage_first) : 0.0;
  row.converged = converged;
  row.kinetic_elastic_ratio = sample_.kinetic_elastic_ratio();
  row.contacts = world.contact_stats().contacts;
  row.sliding_contacts = world.contact_stats().sliding;
  run.r.curve.push_back(row);
  run.sink.curve_row(row.values());
  if (set == 0 && at.state > 0) at.scale = std::max(at.scale, std::abs(row.response));
  advance(run);
}

// On to the next state, or the next set.
void CrystalStiffness::advance(Run& run) {
  Position& at = run.at;
  if (++at.state <= kStiffnessStates) {
    target(at);
  } else if (++at.pass < kPasses) {
    begin_set(run);
  }
}

// One step of the state being reached: its ramp (the prescribed grains to the imposed strain along a half cosine,
// so that they start and stop smoothly), then, relaxed, its hold.
void CrystalStiffness::step_state(Run& run) {
  Position& at = run.at;
  World& world = sample_.world();
  Bodies& bodies = world.bodies();
  const double dt = world.settings().time_step;
  const std::uint64_t into = world.steps() - at.stage_first;
  if (at.ramping) {
    const double steps = relaxed_pass(at.pass) ? run.schedule.ramp_steps : double(params_.affine_ramp_steps);
    if (double(into) < steps) {
      const double u = double(into + 1) / steps, h = (1 - std::cos(M_PI * u)) / 2;
      Voigt6 e;
      for (int k = 0; k < 6; ++k) e[k] = at.from[k] + (at.to[k] - at.from[k]) * h;
      const Mat3 strain = strain_tensor(e);
      for (std::size_t k = 0; k < bodies.size(); ++k)
        if (bodies.motion[k] == Motion::prescribed)
          bodies.velocity[k] = (reference_[k] + strain * (reference_[k] - centre_) - bodies.position[k]) / dt;
      world.step();
      return;
    }
    for (std::size_t k = 0; k < bodies.size(); ++k)
      if (bodies.motion[k] == Motion::prescribed) bodies.velocity[k].setZero();
    at.ramping = false;
    at.stage_first = world.steps();
    sample_.check_finite();
    if (!relaxed_pass(at.pass)) {
      // One step at rest before the measure: the ramp's last step still moved, and the contacts' damping would
      // add c v to the forces (measured: 6 % on C11 with a 10-step ramp).
      world.step();
      record(run, true);
    }
    return;
  }
  // The hold of a relaxed state (or the relaxed set's reference).
  world.step();
  const std::uint64_t held = world.steps() - at.stage_first;
  if (held % std::uint64_t(run.schedule.check_steps) != 0) return;
  sample_.check_finite();
  const Voigt6 s = stress_voigt(interior_stress());
  double change = 0;
  for (int k = 0; k < 6; ++k) change = std::max(change, std::abs(s[k] - at.last[k])), at.last[k] = s[k];
  const bool first_check = held == std::uint64_t(run.schedule.check_steps);
  at.good = !first_check && change <= params_.relax_tolerance * at.scale ? at.good + 1 : 0;
  if (at.good >= params_.relax_checks) return record(run, true);
  if (double(held) >= params_.max_relax_transits * run.schedule.transit_steps) record(run, false);
}

StiffnessResult CrystalStiffness::run(ResultSink& sink, const CheckpointSource* resume) {
  const auto start = std::chrono::steady_clock::now();
  StiffnessResult r;
  Position at;
  if (resume) restore(*resume, at, r);
  World& world = sample_.world();
  Run run{sink, r, at, stiffness_schedule(params_)};
  run.confinement_steps = expected_confinement_steps(params_);
  run.share = run.confinement_steps / (run.confinement_steps + run.schedule.expected_steps);
  if (!at.begun) confine_and_begin(run);
  while (at.pass < kPasses) {
    step_state(run);
    const double fraction = double(world.steps() - at.first) / std::max(1.0, run.schedule.expected_steps);
    if (world.steps() % 100 == 0 && !sink.progress(run.share + (1 - run.share) * std::min(0.99, fraction)))
      throw Cancelled();
    if (at.pass < kPasses) safe_point(run);
  }
  sink.progress(1.0);
  r.stiffness_steps = world.steps() - at.first;
  r.run = world.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return r;
}

template <class Archive, class Self, class At, class Result>
void CrystalStiffness::state(Archive& a, Self& self, At& at, Result& r) {
  a.section("crystal_stiffness");
  a.value(at);
  a.value(r.confinement);
  a.values(r.curve);
  a.value(r.reference_stress);
  a.value(r.amplitude), a.value(r.boundary_grains), a.value(r.interior_grains), a.value(r.interior_volume);
  a.value(r.sample_size);
  a.values(self.interior_);
  a.values(self.reference_);
  a.value(self.centre_), a.value(self.volume_);
}

void CrystalStiffness::save(CheckpointWriter& out, const Position& at, const StiffnessResult& r) const {
  sample_.save(out);
  state(out, *this, at, r);
}

void CrystalStiffness::restore(const CheckpointSource& checkpoint, Position& at, StiffnessResult& r) {
  CheckpointReader in(checkpoint);
  sample_.restore(in);
  state(in, *this, at, r);
  in.finish();
}

}  // namespace granulab
