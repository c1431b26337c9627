#include "engine/experiments/crystal_compression.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <omp.h>
#include <stdexcept>
#include <tuple>

#include "engine/analysis/grain_kinematics.h"

namespace granulab {

namespace {

double prestrain_for(const CrystalParams& p) { return std::sqrt(2.0) * p.confining_pressure / p.material.youngs_modulus; }

WorldSettings crystal_settings(const CrystalParams& p, const GrainTemplate& grain) {
  WorldSettings s;
  s.time_step = p.time_step_factor *
                contact_time_scale(grain, p.material.youngs_modulus, p.material.density * p.mass_scaling);
  s.skin = p.skin_factor * grain.diameter();
  return s;
}

CrystalGeometry lattice_geometry(const CrystalParams& p) {
  CrystalGeometry g;
  g.size = p.grain.size;
  g.prestrain = prestrain_for(p);
  g.grains_x = p.grains_x, g.rows_z = p.rows_z, g.layers_y = p.layers_y;
  g.knockout_ids = p.knockout_ids;
  g.knockout_regions = p.knockout_regions;
  return g;
}

double mean_coordinate(const std::vector<std::uint32_t>& bodies, const std::vector<Vec3>& x, int axis) {
  double s = 0;
  for (std::uint32_t b : bodies) s += x[b][axis];
  return bodies.empty() ? 0 : s / bodies.size();
}

// Strains at which curve rows are recorded: a quarter of the rows over the first 2.5 % of the run,
// where the crystal goes from elastic to its first yield at strains of order 10 p0 / E, and the rest
// evenly over the whole run.
std::vector<double> curve_strains(double max_strain, int points) {
  std::vector<double> at;
  const int early = std::max(1, points / 4), late = std::max(1, points - early);
  for (int k = 1; k <= early; ++k) at.push_back(0.025 * max_strain * k / early);
  for (int k = 1; k <= late; ++k) at.push_back(max_strain * k / late);
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

}  // namespace

CrystalCompression::CrystalCompression(const CrystalParams& params)
    : params_(params),
      grain_(params.grain),
      lattice_(build_crystal(lattice_geometry(params))),
      world_(grain_, contact_law(grain_, params.material), crystal_settings(params, grain_)),
      membrane_(params.confining_pressure, grain_.diameter() / 2, params.bridge_span * params.grain.size,
                params.bridge_depth * params.grain.size) {
  if (params.grain.shape != Shape::rhombic_dodecahedron)
    throw std::invalid_argument("crystal_compression needs rhombic_dodecahedron grains");
  if (!(prestrain_for(params) < 0.1)) throw std::invalid_argument("confining pressure too high for the modulus");
  if (lattice_.sites.size() < 2) throw std::invalid_argument("the crystal has fewer than two grains left");
  const double density = params.material.density * params.mass_scaling;
  for (const LatticeSite& s : lattice_.sites) {
    const BodyId b = world_.add_grain(s.position, lattice_.orientation, density);
    ids_.push_back(s.id);
    if (s.column == 0) side_[0].push_back(b);
    if (s.column == params.grains_x - 1) side_[1].push_back(b);
    if (s.layer == 0) side_[2].push_back(b);
    if (s.layer == params.layers_y - 1) side_[3].push_back(b);
  }
  // Walls just touching the outermost sphere surfaces of the end rows.
  world_.compute_forces();
  double lo = 1e300, hi = -1e300;
  for (const Vec3& x : world_.sphere_positions()) lo = std::min(lo, x.z()), hi = std::max(hi, x.z());
  Wall top{Vec3(0, 0, hi + grain_.radius()), -Vec3::UnitZ()}, bottom{Vec3(0, 0, lo - grain_.radius()), Vec3::UnitZ()};
  top.friction = bottom.friction = params.wall_friction;
  top_ = world_.add_wall(top);
  bottom_ = world_.add_wall(bottom);

  cross_section_ = lattice_.extent.x() * lattice_.extent.y();
  t0_ = contact_time_scale(grain_, params.material.youngs_modulus, density);
  update_membrane();
  world_.compute_forces();
}

void CrystalCompression::update_membrane() {
  membrane_.apply(world_.bodies().position, world_.sphere_positions(), grain_.sphere_count(), grain_.radius(),
                  world_.external_force(), world_.external_torque());
}

void CrystalCompression::check_finite() const {
  const double ke = world_.kinetic_energy();
  if (!std::isfinite(ke) || !std::isfinite(wall_stress(top_)) || !std::isfinite(wall_stress(bottom_)))
    throw std::runtime_error("the simulation became unstable (non-finite energy or wall force) at step " +
                             std::to_string(world_.steps()) + "; try a smaller run.time_step_factor");
}

double CrystalCompression::wall_stress(std::size_t w) const {
  const Wall& wall = world_.walls()[w];
  return -wall.force.dot(wall.normal) / cross_section_;
}

std::pair<double, double> CrystalCompression::lateral_stresses() const {
  Vec3 fl = Vec3::Zero();  // sum of f_i l_i per axis
  const auto& pairs = world_.neighbors().grain_pairs();
  const auto& forces = world_.pair_forces();
  const auto& x = world_.bodies().position;
  for (std::size_t p = 0; p < pairs.size(); ++p) fl += forces[p].cwiseProduct(x[pairs[p].a] - x[pairs[p].b]);
  const MembraneStats& m = membrane_.stats();
  const double width = m.load_centre[0] - m.load_centre[1], thickness = m.load_centre[2] - m.load_centre[3];
  const double area_x = (m.area[0] + m.area[1]) / 2, area_y = (m.area[2] + m.area[3]) / 2;
  return {area_x > 0 && width > 0 ? fl.x() / (area_x * width) : 0.0,
          area_y > 0 && thickness > 0 ? fl.y() / (area_y * thickness) : 0.0};
}

ConfinementReport CrystalCompression::confine(const ProgressFn& progress) {
  ConfinementReport r;
  const double p0 = params_.confining_pressure;
  // Servo: wall speed = force error / (K tau). K = the stiffness of the wall's own contacts, an upper
  // bound of the wall-sample stiffness (springs in series), so the force error decays no faster than
  // with time constant tau, which is kept well above the sample's response time (~ L/c ~ 10 t0).
  const double servo_time = 50 * t0_;
  const double kn = world_.law().normal_stiffness;
  int good = 0;
  const std::uint64_t start = world_.steps();
  while (world_.steps() - start < params_.max_confinement_steps) {
    for (std::size_t w : {top_, bottom_}) {
      Wall& wall = world_.walls()[w];
      const double error = (p0 - wall_stress(w)) * cross_section_;  // N; > 0: push in
      const double stiffness = kn * double(std::max<std::size_t>(1, wall.contacts));
      // At most a tenth of the skin per step, so a wall far from contact cannot jump into the spheres.
      const double max_speed = 0.1 * world_.settings().skin / world_.settings().time_step;
      wall.velocity = wall.normal * std::clamp(error / (stiffness * servo_time), -max_speed, max_speed);
    }
    world_.step();
    if ((world_.steps() - start) % params_.membrane_interval != 0) continue;
    check_finite();
    update_membrane();
    const double ke = world_.kinetic_energy(), ee = world_.contact_stats().elastic_energy;
    const bool walls_ok = std::abs(wall_stress(top_) - p0) <= params_.equilibrium_tolerance * p0 &&
                          std::abs(wall_stress(bottom_) - p0) <= params_.equilibrium_tolerance * p0;
    const bool quiet = ke <= params_.kinetic_tolerance * ee;
    good = walls_ok && quiet ? good + 1 : 0;
    // Its length is unknown: report a fraction that approaches 1 on the servo's time scale.
    const double servo_steps = 20 * servo_time / world_.settings().time_step;
    if (progress && !progress(1 - std::exp(-double(world_.steps() - start) / servo_steps))) throw Cancelled();
    if (good >= params_.equilibrium_checks) {
      r.converged = true;
      break;
    }
  }
  for (Wall& w : world_.walls()) w.velocity.setZero();
  r.steps = world_.steps() - start;
  r.stress_top = wall_stress(top_);
  r.stress_bottom = wall_stress(bottom_);
  std::tie(r.lateral_stress_x, r.lateral_stress_y) = lateral_stresses();
  const double ee = world_.contact_stats().elastic_energy;
  r.kinetic_elastic_ratio = ee > 0 ? world_.kinetic_energy() / ee : 0;
  return r;
}

CrystalRow CrystalCompression::measure(double strain) const {
  CrystalRow row;
  const auto& x = world_.bodies().position;
  row.strain = strain;
  row.stress_top = wall_stress(top_);
  row.stress_bottom = wall_stress(bottom_);
  row.deviator = (row.stress_top + row.stress_bottom) / 2 - params_.confining_pressure;
  const double width = mean_coordinate(side_[1], x, 0) - mean_coordinate(side_[0], x, 0);
  const double thickness = mean_coordinate(side_[3], x, 1) - mean_coordinate(side_[2], x, 1);
  row.lateral_strain_x = ref_width_ > 0 ? width / ref_width_ - 1 : 0;
  row.lateral_strain_y = ref_thickness_ > 0 ? thickness / ref_thickness_ - 1 : 0;
  const auto [sx, sy] = lateral_stresses();
  row.lateral_stress = (sx + sy) / 2;
  const double ee = world_.contact_stats().elastic_energy;
  row.kinetic_elastic_ratio = ee > 0 ? world_.kinetic_energy() / ee : 0;
  row.contacts = world_.contact_stats().contacts;
  row.sliding_contacts = world_.contact_stats().sliding;
  return row;
}

CrystalSnapshot CrystalCompression::snapshot(double strain) const {
  const Bodies& b = world_.bodies();
  CrystalSnapshot s;
  s.strain = strain;
  s.step = world_.steps();
  s.id = ids_;
  s.position = b.position;
  s.orientation = b.orientation;
  s.displacement.resize(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) s.displacement[i] = b.position[i] - ref_position_[i];
  s.penetration = world_.overlap_sums();
  double mean = 0;
  for (double d : s.penetration) mean += d;
  mean /= s.penetration.size();
  for (double d : s.penetration) s.penetration_ratio.push_back(mean > 0 ? d / mean : 0);
  for (const LocalStrain& e : local_strains(ref_position_, b.position, interfaces_)) {
    s.max_shear_strain.push_back(e.max_shear);
    s.equivalent_strain.push_back(e.equivalent);
  }
  for (const auto& [p, q] : interfaces_) s.interfaces.emplace_back(ids_[p], ids_[q]);
  s.sliding = interface_sliding(ref_position_, ref_orientation_, b.position, b.orientation, interfaces_);
  return s;
}

CrystalResult CrystalCompression::run(const ProgressFn& progress, const CrystalObserver& observer) {
  const auto start = std::chrono::steady_clock::now();
  CrystalResult r;
  // Confinement counts as the first 10 % of the progress bar (its length is not known in advance).
  r.confinement = confine([&](double f) { return !progress || progress(0.1 * f); });

  // Reference state for strains, displacements and lateral strains.
  const Bodies& b = world_.bodies();
  ref_position_ = b.position;
  ref_orientation_ = b.orientation;
  interfaces_ = neighbour_pairs(ref_position_, 1.1 * params_.grain.size / std::sqrt(2.0));
  ref_width_ = mean_coordinate(side_[1], ref_position_, 0) - mean_coordinate(side_[0], ref_position_, 0);
  ref_thickness_ = mean_coordinate(side_[3], ref_position_, 1) - mean_coordinate(side_[2], ref_position_, 1);
  Wall& top = world_.walls()[top_];
  Wall& bottom = world_.walls()[bottom_];
  ref_length_ = top.point.z() - bottom.point.z();

  const double wave_speed = std::sqrt(params_.material.youngs_modulus / (params_.material.density * params_.mass_scaling));
  const double speed = params_.rate_number * wave_speed;  // wall approach speed, R = L eps_dot / c
  const double dt = world_.settings().time_step;
  // The platen accelerates smoothly over ten wave transits of the sample: a sudden start would send a
  // stress wave of amplitude E R (= p0 at R = 1e-5, E = 3 GPa) through it.
  const double ramp_time = 10 * ref_length_ / wave_speed;
  const std::vector<double> record_at = curve_strains(params_.max_strain, params_.curve_points);

  std::vector<double> targets = params_.snapshot_strains;
  std::sort(targets.begin(), targets.end());
  std::size_t next_snapshot = 0, next_row = 0;
  auto strain_now = [&] { return 1 - (top.point.z() - bottom.point.z()) / ref_length_; };
  auto take_due_snapshots = [&] {
    while (next_snapshot < targets.size() && strain_now() >= targets[next_snapshot] - 1e-12) {
      r.snapshots.push_back(snapshot(targets[next_snapshot++]));
      if (observer.snapshot) observer.snapshot(r.snapshots.back());
    }
  };
  auto record = [&](double strain) {
    r.curve.push_back(measure(strain));
    if (observer.row) observer.row(r.curve.back());
  };
  record(0);
  take_due_snapshots();
  const std::uint64_t first = world_.steps();
  while (next_row < record_at.size()) {
    // The top platen moves, the bottom one is fixed, as in a test machine: the stress wave then
    // crosses the sample, so top and bottom forces agree only when the loading is quasi-static.
    const double t = (world_.steps() - first) * dt;
    top.velocity = top.normal * (speed * std::min(1.0, t / ramp_time));
    world_.step();
    if ((world_.steps() - first) % params_.membrane_interval == 0) {
      check_finite();
      update_membrane();
    }
    take_due_snapshots();
    const double strain = strain_now();
    // Every 100 steps (< 1 s even at full size): a cancelled run stops promptly.
    if ((world_.steps() - first) % 100 == 0 && progress &&
        !progress(0.1 + 0.9 * std::min(1.0, std::max(0.0, strain) / params_.max_strain)))
      throw Cancelled();
    if (!(strain >= record_at[next_row] - 1e-12 * params_.max_strain)) continue;
    while (next_row < record_at.size() && strain >= record_at[next_row] - 1e-12 * params_.max_strain) ++next_row;
    record(strain);
  }
  if (progress) progress(1.0);
  top.velocity.setZero();

  r.prestrain = prestrain_for(params_);
  r.sphere_diameter = grain_.diameter();
  r.normal_stiffness = world_.law().normal_stiffness;
  r.time_step = dt;
  r.strain_rate = speed / ref_length_;
  r.initial_length = ref_length_;
  r.cross_section = cross_section_;
  r.spheres_per_face = grain_.spheres_per_face();
  r.grains = b.size();
  r.spheres = world_.sphere_count();
  r.knocked_out = lattice_.knocked_out;
  r.steps = world_.steps();
  r.compression_steps = world_.steps() - first;
  r.rebuilds = world_.rebuilds();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.threads = omp_get_max_threads();
  r.stage_times = world_.stage_times();
  return r;
}

}  // namespace granulab
