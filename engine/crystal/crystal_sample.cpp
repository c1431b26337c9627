#include "engine/crystal/crystal_sample.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/crystal/exposed_faces.h"
#include "engine/crystal/face_springs.h"

namespace granulab {

namespace {

WorldSettings crystal_settings(const CrystalSampleParams& p, const GrainTemplate& grain,
                               const std::vector<GrainImperfection>& imperfections = {}) {
  WorldSettings s;
  for (const GrainImperfection& g : imperfections) s.min_scale = std::min(s.min_scale, g.scale);
  s.time_step =
      p.time_step_factor * contact_time_scale(grain, p.material.youngs_modulus, p.material.density * p.mass_scaling);
  // A smaller grain has the same contact stiffness and less mass: its contact time goes as scale^1.5.
  if (s.min_scale < 1) s.time_step *= std::pow(s.min_scale, 1.5);
  s.skin = p.skin_factor * grain.diameter();
  s.kernel = p.kernel;
  s.local_damping.translational = p.local_damping;
  s.local_damping.rotational = p.local_damping_rotational < 0 ? p.local_damping : p.local_damping_rotational;
  s.damping_velocity = p.damping_velocity;
  return s;
}

CrystalGeometry lattice_geometry(const CrystalSampleParams& p) {
  CrystalGeometry g;
  g.lattice = p.lattice, g.axis = p.axis, g.lateral = p.lateral;
  g.size = p.grain.size;
  g.prestrain = hydrostatic_prestrain(p);
  g.grains_x = p.grains_x, g.rows_z = p.rows_z, g.layers_y = p.layers_y;
  g.knockout_ids = p.knockout_ids;
  g.knockout_regions = p.knockout_regions;
  return g;
}

}  // namespace

// Measured (bench/README.md, "Cost estimates"): confinement took 440-3,880 contact times on 30 crystals
// (3 x 7 x 4 to 8 x 18 x 6 grains, N_e = 4 and 6, 10 to 60 kPa), longer the more slender the crystal: rows
// over {111} layers of 1 gave 440-520, of 4 gave 2,440-3,880. 700 contact times per unit of that aspect
// ratio is within 0.74-1.39 of 26 of them; the other 4 (8 x 18 x 6 and 6 x 6 x 6 at N_e = 6, 4 x 8 x 3
// at N_e = 6 and 60 kPa) converged sooner, down to 0.27 of it.
double expected_confinement_steps(const CrystalSampleParams& p) {
  const double contact_times = 700 * std::max(1.0, double(p.rows_z) / p.layers_y);
  return std::min(double(p.max_confinement_steps), contact_times / p.time_step_factor);
}

double crystal_length_estimate(const CrystalSampleParams& p) {
  const GrainTemplate grain(p.grain);
  const CrystalLattice lattice = build_crystal(lattice_geometry(p));
  double reach = 0;  // how far a grain's spheres reach along z beyond its centre (m), in either orientation (HCP)
  for (const Quat& q : lattice.basis_orientation)
    for (const Vec3& o : grain.offsets()) reach = std::max(reach, std::abs((q * o).z()));
  double lo = 1e300, hi = -1e300;
  for (const LatticeSite& s : lattice.sites) lo = std::min(lo, s.position.z()), hi = std::max(hi, s.position.z());
  return hi - lo + 2 * (reach + grain.radius());
}

Workload confinement_workload(const CrystalSampleParams& p) {
  Workload w;
  w.grains = double(p.grains_x) * p.rows_z * p.layers_y;
  w.spheres = w.grains * double(sphere_count(p.grain));
  w.steps = double(p.max_confinement_steps);
  w.phases.push_back({"confinement", expected_confinement_steps(p)});
  return w;
}

double quasi_static_rate_number(double confining_pressure, double youngs_modulus) {
  return std::clamp(confining_pressure / youngs_modulus, 1e-8, 0.1);  // the field's allowed range
}

double cohesive_stress_scale(const CrystalSampleParams& p) {
  const GrainTemplate grain(p.grain);
  const double s = grain.spacing();
  return contact_law(grain, p.material).pulloff_force(grain.diameter() / 4) / (s * s);
}

CrystalLattice sample_lattice(const CrystalSampleParams& p) { return build_crystal(lattice_geometry(p)); }

double crystal_time_step(const CrystalSampleParams& p) {
  const GrainTemplate grain(p.grain);
  // Imperfect grains: the time step of the smallest grain there may be (an estimate's upper bound of steps).
  return crystal_settings(p, grain, {GrainImperfection{min_scale_bound(p.imperfections, grain), Quat::Identity()}})
      .time_step;
}

double hydrostatic_prestrain(double confining_pressure, double youngs_modulus) {
  return std::sqrt(2.0) * confining_pressure / youngs_modulus;
}

double hydrostatic_prestrain(const CrystalSampleParams& p) {
  const double p0 = p.confining_pressure, e = p.material.youngs_modulus;
  const bool hooke = p.material.contact.normal == NormalModel::hooke;
  if (p.lattice == LatticeType::fcc && hooke) return hydrostatic_prestrain(p0, e);  // the paper's, bit for bit
  // Love-Weber: a uniform strain eps0 overlaps face f by eps0 l_f, which carries N_f F(eps0 l_f) along l_f;
  // the mean stress is sum_f N_f F(eps0 l_f) l_f / (6 V). Hooke's F = k_n delta gives eps0 in closed form.
  GrainGeometry g = p.grain;
  g.shape = grain_shape(p.lattice);
  const GrainTemplate grain(g);
  const std::vector<FaceSpring> faces = face_springs(grain);
  const double k_n = normal_stiffness(grain, e);
  double sum = 0;
  for (const FaceSpring& f : faces) sum += k_n * double(f.pairs) * f.branch * f.branch;
  const double linear = 6 * grain.volume() * p0 / sum;
  if (hooke) return linear;
  // Any other law: the face overlaps whose forces (at rest, bonded) carry p0, by bisection on eps0, which every law's
  // F(delta) raises once it pushes.
  const ContactLaw law = contact_law(grain, p.material);
  const PairLaw c = pair_law(law, grain.radius() / 2, 1.0, 1.0);
  const auto stress = [&](double eps) {
    double total = 0;
    for (const FaceSpring& f : faces) {
      Vec3 xi = Vec3::Zero();
      double bond = 1;
      total += double(f.pairs) * contact_force(law, c, Vec3::UnitZ(), eps * f.branch, Vec3::Zero(), xi, bond).normal *
               f.branch;
    }
    return total / (6 * grain.volume());
  };
  double lo = 0, hi = linear;
  for (int k = 0; k < 200 && stress(hi) < p0; ++k) lo = hi, hi *= 2;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (stress(mid) < p0 ? lo : hi) = mid;
  }
  return hi;
}

double crystal_wave_speed(const CrystalSampleParams& p) {
  return std::sqrt(p.material.youngs_modulus / (p.material.density * p.mass_scaling));
}

double face_neighbour_distance(const CrystalSampleParams& p, const GrainTemplate& grain) {
  if (p.lattice == LatticeType::fcc)  // the paper's crystal, as its interfaces were always found
    return p.grain.size / std::sqrt(2.0);
  double h = 0;
  for (const Face& f : grain.solid().faces()) h = std::max(h, f.distance);
  return 2 * h;
}

double CrystalSample::face_neighbour_distance() const { return granulab::face_neighbour_distance(params_, grain_); }

double crystal_skin_factor(double overlap) {
  const double neighbour_gap = std::sqrt(1 + (1 - overlap) * (1 - overlap)) - 1;
  return std::min(0.01, 0.9 * neighbour_gap);
}

CrystalSample::CrystalSample(const CrystalSampleParams& params)
    : params_(params),
      grain_(params.grain),
      lattice_(build_crystal(lattice_geometry(params))),
      imperfections_(draw_imperfections(params.imperfections, lattice_, grain_)),
      world_(grain_, contact_law(grain_, params.material), crystal_settings(params, grain_, imperfections_)),
      membrane_(params.confining_pressure, grain_.diameter() / 2, params.bridge_span * params.grain.size,
                params.bridge_depth * params.grain.size) {
  if (params.grain.shape != grain_shape(params.lattice))
    throw std::invalid_argument("a " + to_string(params.lattice) + " crystal needs " +
                                to_string(grain_shape(params.lattice)) + " grains");
  if (!(hydrostatic_prestrain(params) < 0.1))
    throw std::invalid_argument("confining pressure too high for the modulus");
  if (lattice_.sites.size() < 2) throw std::invalid_argument("the crystal has fewer than two grains left");
  const double density = params.material.density * params.mass_scaling;
  for (std::size_t k = 0; k < lattice_.sites.size(); ++k) {
    const LatticeSite& s = lattice_.sites[k];
    const GrainImperfection& g = imperfections_[k];
    const BodyId b =
        world_.add_grain(s.position, lattice_.basis_orientation[s.basis] * g.rotation, density, Motion::dynamic, g.scale);
    ids_.push_back(s.id);
    if (s.column == 0) side_[0].push_back(b);
    if (s.column == params.grains_x - 1) side_[1].push_back(b);
    if (s.layer == 0) side_[2].push_back(b);
    if (s.layer == params.layers_y - 1) side_[3].push_back(b);
  }
  // Walls just touching the outermost sphere surfaces of the end rows.
  world_.compute_forces();
  double lo = 1e300, hi = -1e300;
  const std::vector<Vec3>& spheres = world_.sphere_positions();
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const double r = sphere_radius(i);
    lo = std::min(lo, spheres[i].z() - r), hi = std::max(hi, spheres[i].z() + r);
  }
  Wall top{Vec3(0, 0, hi), -Vec3::UnitZ()}, bottom{Vec3(0, 0, lo), Vec3::UnitZ()};
  top.friction = bottom.friction = params.wall_friction;
  top_ = world_.add_wall(top);
  bottom_ = world_.add_wall(bottom);

  cross_section_ = lattice_.extent.x() * lattice_.extent.y();
  t0_ = contact_time_scale(grain_, params.material.youngs_modulus, density);
  update_membrane();
  world_.compute_forces();
}

void CrystalSample::update_membrane() {
  if (fixed_.on) return;
  const std::vector<Vec3>& spheres = world_.sphere_positions();  // timed as the world's own stage
  StageTimer t(world_.stage_times().membrane);
  membrane_.apply(world_.bodies().position, spheres, grain_.sphere_count(), grain_.radius(), world_.external_force(),
                  world_.external_torque(), scales());
}

bool CrystalSample::step(std::uint64_t since) {
  if (fixed_.follows) press_faces();
  world_.step();
  if ((world_.steps() - since) % params_.membrane_interval != 0) return false;
  {
    StageTimer t(world_.stage_times().control);
    check_finite();
  }
  update_membrane();
  return true;
}

void CrystalSample::fix_confining_forces(double end_load) {
  update_membrane();  // the lateral faces' forces, from the sample as it is now
  std::vector<Vec3>& force = world_.external_force();
  std::fill(world_.external_torque().begin(), world_.external_torque().end(), Vec3::Zero());
  const std::vector<Vec3>& spheres = world_.sphere_positions();
  std::vector<Vec3> ends(force.size(), Vec3::Zero());
  const auto [top_area, bottom_area] =
      membrane_.end_forces(world_.bodies().position, spheres, grain_.sphere_count(), grain_.radius(), ends, scales());
  const MembraneStats& m = membrane_.stats();
  for (int k = 0; k < 4; ++k) fixed_.area[k] = m.area[k], fixed_.load[k] = membrane_.pressure() * m.area[k];
  fixed_.area[4] = top_area, fixed_.area[5] = bottom_area;
  // The ends take over the platens' load as it is (p0 x cross-section, within the confinement's
  // tolerance), shared among the end grains by projected area: the axial stress is the same before and
  // after. (A jagged end's projected area is larger than the cross-section stresses are divided by, by
  // the grains' overhang at its rim: 24 % on a 4 x 3 end.)
  // The mean of the two platens' loads on both ends (they differ by the servo's tolerance): fixed forces
  // with a net axial force would push the sample along once a platen lets go.
  fixed_.load[4] = fixed_.load[5] = fixed_.end_load =
      end_load >= 0 ? end_load
                    : -(world_.walls()[top_].force.dot(world_.walls()[top_].normal) +
                        world_.walls()[bottom_].force.dot(world_.walls()[bottom_].normal)) /
                          2;
  const double top_scale = top_area > 0 ? fixed_.load[4] / (membrane_.pressure() * top_area) : 0;
  const double bottom_scale = bottom_area > 0 ? fixed_.load[5] / (membrane_.pressure() * bottom_area) : 0;
  for (std::size_t b = 0; b < force.size(); ++b) {
    double& fz = ends[b][2];
    fz *= fz < 0 ? top_scale : bottom_scale;  // the top end is pushed down
    force[b] += ends[b];
  }
  // The platens step back by their deepest sphere's overlap: bare contact, carrying nothing, while the
  // grains feel the same axial load as before. They take up the deviator as soon as they move in.
  // (They must not be servoed to bare contact instead: a body under fixed compressive forces is unstable
  // in rotation, since a tilt turns the end forces into a couple that tilts it further, and platens that
  // carry nothing cannot hold it; a 4 x 8 x 3 crystal flew apart so in 10,000 steps.)
  retract_platens();
  fixed_.on = true;
  // The forces of this state, as the loading's first step and row must see them (at rest, the one more
  // evaluation adds nothing to the contacts' shear histories that matters: v_t dt with v_t ~ 0).
  world_.compute_forces();
}

void CrystalSample::release_confinement() {
  fixed_ = FixedForces{};
  pressed_.clear();
  fixed_.on = true;
  std::fill(world_.external_force().begin(), world_.external_force().end(), Vec3::Zero());
  std::fill(world_.external_torque().begin(), world_.external_torque().end(), Vec3::Zero());
  world_.compute_forces();
}

void CrystalSample::fix_face_forces() {
  const double cell = (1 - hydrostatic_prestrain(params_)) * params_.grain.size;
  const std::vector<ExposedArea> exposed = exposed_face_areas(lattice_, grain_.solid(), cell);
  std::vector<Vec3>& force = world_.external_force();
  std::fill(force.begin(), force.end(), Vec3::Zero());
  std::fill(world_.external_torque().begin(), world_.external_torque().end(), Vec3::Zero());
  fixed_ = FixedForces{};
  pressed_.clear();
  const double p0 = params_.confining_pressure;
  for (std::size_t b = 0; b < exposed.size(); ++b) {  // bodies are the sites, in order
    const double s = world_.bodies().scale[b];        // a smaller grain's faces are smaller
    const Vec3 lateral = s * s * exposed[b].lateral, end = s * s * exposed[b].end;
    force[b] = -p0 * (lateral + end);
    const double parts[6] = {lateral.x(), -lateral.x(), lateral.y(), -lateral.y(), end.z(), -end.z()};
    for (int k = 0; k < 6; ++k) fixed_.area[k] += std::max(0.0, parts[k]);
  }
  for (int k = 0; k < 6; ++k) fixed_.load[k] = p0 * fixed_.area[k];
  fixed_.end_load = p0 * cross_section_;
  fixed_.on = true;
  world_.compute_forces();
}

void CrystalSample::retract_platens() {
  const std::vector<Vec3>& spheres = world_.sphere_positions();
  for (std::size_t w : {top_, bottom_}) {
    Wall& wall = world_.walls()[w];
    double deepest = 0;
    for (std::size_t i = 0; i < spheres.size(); ++i)
      deepest = std::max(deepest, sphere_radius(i) - (spheres[i] - wall.point).dot(wall.normal));
    wall.point -= deepest * wall.normal;
  }
}

void CrystalSample::wrap_bag() {
  // Platens that carry p0 (a sample the taut bag confined) step back to bare contact: the end faces' pressure takes
  // their load over. On the lattice as built they touch already, and nothing moves.
  retract_platens();
  list_pressed_faces();
  fixed_ = FixedForces{};
  // The summary's areas per face, as fix_face_forces() gives them: the positive parts of the vector areas.
  const double cell = (1 - hydrostatic_prestrain(params_)) * params_.grain.size;
  for (const ExposedArea& e : exposed_face_areas(lattice_, grain_.solid(), cell)) {
    const double parts[6] = {e.lateral.x(), -e.lateral.x(), e.lateral.y(), -e.lateral.y(), e.end.z(), -e.end.z()};
    for (int k = 0; k < 6; ++k) fixed_.area[k] += std::max(0.0, parts[k]);
  }
  for (int k = 0; k < 6; ++k) fixed_.load[k] = params_.confining_pressure * fixed_.area[k];
  fixed_.end_load = params_.confining_pressure * cross_section_;
  fixed_.on = fixed_.follows = true;
  press_faces();
  world_.compute_forces();
}

void CrystalSample::list_pressed_faces() {
  const double cell = (1 - hydrostatic_prestrain(params_)) * params_.grain.size;
  const std::vector<Face>& faces = grain_.solid().faces();
  pressed_.clear();
  for (const ExposedFace& e : exposed_faces(lattice_, grain_.solid(), cell)) {
    const double s = world_.bodies().scale[e.site];  // bodies are the sites, in order; a smaller grain's faces are smaller
    const Face& face = faces[e.face];
    // The body frame is the template's: the site's orientation (and an imperfect grain's tilt) is the body's.
    pressed_.push_back({BodyId(e.site), face.normal, s * face.centroid(), params_.confining_pressure * s * s * face.area()});
  }
}

void CrystalSample::press_faces() {
  StageTimer t(world_.stage_times().membrane);
  std::vector<Vec3>& force = world_.external_force();
  std::vector<Vec3>& torque = world_.external_torque();
  std::fill(force.begin(), force.end(), Vec3::Zero());
  std::fill(torque.begin(), torque.end(), Vec3::Zero());
  const std::vector<Quat>& orientation = world_.bodies().orientation;
  for (const PressedFace& f : pressed_) {
    const Mat3 r = orientation[f.body].toRotationMatrix();
    const Vec3 push = -f.force * (r * f.normal);
    force[f.body] += push;
    torque[f.body] += (r * f.centroid).cross(push);
  }
}

double CrystalSample::axial_stress(std::size_t w) const {
  return wall_stress(w) + (fixed_.on ? fixed_.end_load / cross_section_ : 0.0);
}

void CrystalSample::check_finite() const {
  const auto unstable = [&](const std::string& what) {
    return std::runtime_error("the simulation became unstable (" + what + ") at step " +
                              std::to_string(world_.steps()) +
                              "; a smaller run.time_step_factor helps if the time step is the cause (a sample of a few "
                              "grains may also just fall apart)");
  };
  const double ke = world_.kinetic_energy();
  if (!std::isfinite(ke) || !std::isfinite(wall_stress(top_)) || !std::isfinite(wall_stress(bottom_)))
    throw unstable("non-finite energy or wall force");
  // A blowing-up run flings grains away before its numbers overflow; the bag's height maps (sized by
  // the sample's bounding box) would then ask for gigabytes. No loading moves a grain further from the
  // centre than twice the sample's size.
  const double reach = 2 * (lattice_.extent.norm() + params_.grain.size);
  const std::vector<Vec3>& position = world_.bodies().position;
  for (std::size_t b = 0; b < position.size(); ++b)
    if (!(position[b].norm() < reach))
      throw unstable("grain " + std::to_string(b < ids_.size() ? value(ids_[b]) : b) +
                     " left the sample, more than twice its size from its centre");
}

double CrystalSample::wall_stress(std::size_t w) const {
  const Wall& wall = world_.walls()[w];
  return -wall.force.dot(wall.normal) / cross_section_;
}

double CrystalSample::kinetic_elastic_ratio() const {
  const double ee = world_.elastic_energy();
  return ee > 0 ? world_.kinetic_energy() / ee : 0;
}

std::pair<double, double> CrystalSample::lateral_stresses() const {
  Vec3 fl = Vec3::Zero();  // sum of f_i l_i per axis
  const auto& pairs = world_.neighbors().body_pairs();
  const auto& forces = world_.pair_forces();
  const auto& x = world_.bodies().position;
  for (std::size_t p = 0; p < pairs.size(); ++p) fl += forces[p].cwiseProduct(x[pairs[p].a] - x[pairs[p].b]);
  if (fixed_.follows) {
    // The wrapped bag's own virial: over its closed surface the integral of x_k n_k dA is the enclosed volume V, so
    // in equilibrium the packing's stress is its virial over V. The pair sum counts the centre-to-centre spans only;
    // each bag force also acts across the half grain between its face and the grain's centre, which adds
    // F (c_k n_k) per face (c: centroid from the centre). Without it a crystal n grains wide reads (n - 1)/n of p0.
    const std::vector<Quat>& orientation = world_.bodies().orientation;
    Vec3 volume = Vec3::Zero();
    for (const PressedFace& f : pressed_) {
      const Mat3 r = orientation[f.body].toRotationMatrix();
      const Vec3 c = r * f.centroid, n = r * f.normal;
      fl += f.force * c.cwiseProduct(n);
      volume += (x[f.body] + c).cwiseProduct(n) * (f.force / params_.confining_pressure);
    }
    return {volume.x() > 0 ? fl.x() / volume.x() : 0.0, volume.y() > 0 ? fl.y() / volume.y() : 0.0};
  }
  const MembraneStats& m = membrane_.stats();
  const double width = m.load_centre[0] - m.load_centre[1], thickness = m.load_centre[2] - m.load_centre[3];
  const double area_x = (m.area[0] + m.area[1]) / 2, area_y = (m.area[2] + m.area[3]) / 2;
  return {area_x > 0 && width > 0 ? fl.x() / (area_x * width) : 0.0,
          area_y > 0 && thickness > 0 ? fl.y() / (area_y * thickness) : 0.0};
}

void CrystalSample::save(CheckpointWriter& w) const {
  world_.save(w);
  membrane_.save(w);
  w.section("fixed_forces");
  w.value(fixed_);
}

void CrystalSample::restore(CheckpointReader& r) {
  world_.restore(r);
  membrane_.restore(r);
  r.section("fixed_forces");
  r.value(fixed_);
  if (fixed_.follows) list_pressed_faces();  // from the lattice; the forces follow at the next step
}

}  // namespace granulab
