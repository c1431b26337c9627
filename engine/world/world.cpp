#include "engine/world/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <omp.h>
#include <stdexcept>

#include "engine/contact/pair_kernel.h"
#include "engine/dynamics/integrator.h"

namespace granulab {

namespace {
// A grain pair whose touching share of candidates was below this at the last evaluation takes the
// kernel's two-pass path (distances first). On the Zen 3 VM's AVX2 kernel (2026-12-07, one pair of 600 candidates
// stepped over and over) the two-pass path cost about 6 + 19 s ns per candidate at touching share s, one pass 18:
// even at s = 0.62. The face-forces block (most pairs' faces touching) took 1.62-1.71 ms/step in contacts at 0.5,
// 1.53-1.66 at 0.65, 1.74-1.84 with every pair on two passes.
constexpr double kSparseShare = 0.6;
}  // namespace

World::World(const GrainTemplate& grain, const ContactLaw& law, const WorldSettings& settings)
    : grain_(grain),
      offset_arrays_(grain.offsets()),
      law_(law),
      kernel_name_(resolve_pair_kernel(settings.kernel)),
      kernel_(pair_kernel(law, kernel_name_)),
      energy_kernel_(pair_energy_kernel(law, kernel_name_)),
      settings_(settings),
      // A bonded jkr pair holds to delta_c apart: the skin is widened by it, so candidates reach that far.
      neighbors_(grain.offsets(), grain.diameter(), settings.skin + law.pulloff_distance(grain.radius() / 2),
                 settings.min_scale),
      open_pairs_(grain.bounding_radius() - grain.radius()) {
  if (law.keeps_bonds()) neighbors_.keep_bonds();
  if (!(settings.time_step > 0)) throw std::invalid_argument("time step must be > 0");
  if (!(settings.min_scale > 0 && settings.min_scale <= 1)) throw std::invalid_argument("min_scale must be in (0, 1]");
}

RunStats World::run_stats(double wall_seconds) const {
  RunStats r;
  r.grains = bodies_.size();
  r.spheres = sphere_count();
  r.steps = steps_;
  r.rebuilds = rebuilds_;
  r.pair_searches = pair_searches_;
  r.mean_candidates = steps_ > 0 ? candidate_steps_ / double(steps_) : 0.0;
  r.mean_skipped = steps_ > 0 ? skipped_steps_ / double(steps_) : 0.0;
  r.time_step = settings_.time_step;
  r.sphere_diameter = grain_.diameter();
  r.normal_stiffness = law_.normal_stiffness;
  r.normal_stiffness_unit = law_.normal == NormalModel::hooke ? "N/m" : "Pa";
  r.spheres_per_face = grain_.spheres_per_face();
  r.threads = omp_get_max_threads();
  r.wall_seconds = wall_seconds;
  r.kernel = kernel_name_;
  r.stage_times = times_;
  return r;
}

BodyId World::add_grain(const Vec3& x, const Quat& q, double density, Motion motion, double scale) {
  if (!(scale >= settings_.min_scale && scale <= 1))
    throw std::invalid_argument("a grain's scale must be in [min_scale, 1]");
  const double s3 = scale * scale * scale;  // mass ~ size^3, moments of inertia ~ size^5
  const BodyId id = bodies_.add(x, q, density * grain_.volume() * s3,
                                density * grain_.principal_inertia_per_density() * (s3 * scale * scale), motion, scale);
  sphere_pos_.resize(bodies_.size() * grain_.sphere_count());
  overlap_sum_.resize(bodies_.size(), 0.0);
  spheres_current_ = false;
  external_force_.resize(bodies_.size(), Vec3::Zero());
  external_torque_.resize(bodies_.size(), Vec3::Zero());
  applied_force_.resize(bodies_.size(), Vec3::Zero());
  applied_torque_.resize(bodies_.size(), Vec3::Zero());
  neighbors_.invalidate();
  return id;
}

std::size_t World::add_wall(const Wall& wall) {
  walls_.push_back(wall);
  walls_.back().normal.normalize();
  neighbors_.invalidate();
  return walls_.size() - 1;
}

void World::step() {
  const double dt = settings_.time_step;
  {
    StageTimer t(times_.integrate);
    lagged_damping_ = settings_.damping_velocity == DampingVelocity::quarter_step;
    if (lagged_damping_) kicked_velocities(bodies_, dt / 4, damping_velocity_, damping_angular_velocity_);
    half_kick(dt / 2);
    drift(bodies_, dt);
    for (Wall& w : walls_) w.point += w.velocity * dt;
    add_half_step_work(dt);  // with the forces of the step's start
  }
  compute_forces();
  lagged_damping_ = false;  // an evaluation outside a step sees the bodies' velocities
  {
    StageTimer t(times_.integrate);
    add_half_step_work(dt);  // with the forces of its end
    energy_.friction += stats_.friction_loss;
    energy_.damping += stats_.damping_loss;
    half_kick(dt / 2);
  }
  time_ += dt;
  ++steps_;
}

void World::half_kick(double h) {
  if (settings_.local_damping.on())
    energy_.damping += kick(bodies_, h, settings_.local_damping);
  else
    kick(bodies_, h);
}

void World::compute_forces() {
  stored_energy_current_ = false;
  update_angular_velocity(bodies_);  // in case momenta were set by hand since the last drift
  spheres_current_ = false;          // poses may have changed; positions are refreshed on demand
  update_neighbors();
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    applied_force_[b] = bodies_.mass[b] * settings_.gravity + external_force_[b];
    applied_torque_[b] = external_torque_[b];
    bodies_.force[b] = applied_force_[b];
    bodies_.torque[b] = applied_torque_[b];
  }
  sphere_contact_forces();
  wall_forces();
}

void World::update_sphere_positions() const {
  StageTimer t(times_.spheres);
  const auto& offsets = grain_.offsets();
  const long n_bodies = long(bodies_.size());
  const std::size_t per_body = offsets.size();
#pragma omp parallel for schedule(static) if (n_bodies > 8)
  for (long b = 0; b < n_bodies; ++b) {
    const Mat3 r = bodies_.orientation[b].toRotationMatrix() * bodies_.scale[b];
    const Vec3 x = bodies_.position[b];
    Vec3* out = sphere_pos_.data() + b * per_body;
    for (std::size_t i = 0; i < per_body; ++i) out[i] = x + r * offsets[i];
  }
  spheres_current_ = true;
}

const std::vector<Vec3>& World::sphere_positions() const {
  if (!spheres_current_) update_sphere_positions();
  return sphere_pos_;
}

void World::update_neighbors() {
  StageTimer t(times_.rebuild);
  const NeighborUpdate u = neighbors_.update(bodies_, walls_);
  if (!u.any()) return;
  pair_searches_ += u.pairs_searched;
  const std::size_t n_pairs = neighbors_.body_pairs().size();
  pair_force_.resize(n_pairs);
  pair_torque_a_.resize(n_pairs);
  pair_torque_b_.resize(n_pairs);
  pair_contacts_.resize(n_pairs);
  pair_sliding_.resize(n_pairs);
  pair_overlap_.resize(n_pairs);
  if (u.broad || open_pairs_.size() != n_pairs) {
    open_pairs_.reset(n_pairs);
  } else if (u.pairs_searched > 0) {
    for (std::size_t p = 0; p < n_pairs; ++p)
      if (neighbors_.searched(p)) open_pairs_.forget(p);
  }
  size_kernel_scratch();
  ++rebuilds_;
}

// Room for the largest grain pair's candidates per thread: sized whenever the candidates change (and on
// restore), so that a step without a search allocates nothing.
void World::size_kernel_scratch() {
  std::uint32_t largest = 0;
  for (const BodyPairSpan& gp : neighbors_.body_pairs()) largest = std::max(largest, gp.count);
  kernel_scratch_.resize(omp_get_max_threads());
  for (KernelScratch& s : kernel_scratch_) s.reserve(largest);
}

// A grain pair's constants but its velocities: where its spheres are (x_a, x_b and the rotations times scale, from
// rotation_), where they touch, and the law with the pair's damping.
PairKernelConstants World::pair_constants(const BodyPairSpan& gp, const PairLaw& full_size) const {
  const double d = grain_.diameter(), radius = grain_.radius();
  const double ma = bodies_.mass[gp.a], mb = bodies_.mass[gp.b];
  PairKernelConstants c;
  // Spheres of scaled grains touch at the sum of their radii; the stiffness stays the law's.
  const double sa = bodies_.scale[gp.a], sb = bodies_.scale[gp.b];
  c.diameter = sa == 1 && sb == 1 ? d : radius * (sa + sb), c.radius = radius * sa;
  const double m_eff = ma * mb / (ma + mb);
  if (sa == 1 && sb == 1) {
    c.law = full_size;
    set_pair_damping(c.law, law_, m_eff);
  } else {
    c.law = pair_law(law_, radius * sa * sb / (sa + sb), m_eff, settings_.time_step);
  }
  c.xa = bodies_.position[gp.a], c.xb = bodies_.position[gp.b];
  c.ra = rotation_[gp.a];
  c.rb = rotation_[gp.b];
  return c;
}

// The stored energy of the last evaluation, computed when first asked for after it: the grain pairs with a contact
// then, in pair order (the same sum whatever the threads), each by the kernel of the evaluation's instruction set.
double World::elastic_energy() const {
  if (stored_energy_current_) return stored_energy_;
  const auto& pairs = neighbors_.body_pairs();
  const auto& keys = neighbors_.keys();
  const ShearHistory& history = neighbors_.history();
  const long n_pairs = long(pairs.size()), n_bodies = long(bodies_.size());
  double total = 0;
  if (std::size_t(n_pairs) == pair_contacts_.size()) {  // else not evaluated yet
    rotation_.resize(n_bodies);
    pair_energy_.resize(n_pairs);
    const PairLaw full_size = pair_law(law_, grain_.radius() / 2, 1.0, settings_.time_step);
#pragma omp parallel if (n_pairs >= 8)
    {
#pragma omp for schedule(static)
      for (long b = 0; b < n_bodies; ++b) rotation_[b] = bodies_.orientation[b].toRotationMatrix() * bodies_.scale[b];
#pragma omp for schedule(guided)
      for (long p = 0; p < n_pairs; ++p) {
        const BodyPairSpan& gp = pairs[p];
        pair_energy_[p] = 0;
        if (pair_contacts_[p] == 0) continue;  // none in contact (nor bonded): nothing stored
        const PairKernelConstants c = pair_constants(gp, full_size);
        pair_energy_[p] = energy_kernel_(c, offset_arrays_, keys.data() + gp.first, gp.count,
                                         history.x.data() + gp.first, history.y.data() + gp.first,
                                         history.z.data() + gp.first,
                                         history.bonds ? history.bond.data() + gp.first : nullptr);
      }
    }
    for (long p = 0; p < n_pairs; ++p) total += pair_energy_[p];
  }
  stored_energy_ = total;
  stored_energy_current_ = true;
  return total;
}

void World::sphere_contact_forces() {
  StageTimer t(times_.contacts);
  const auto& pairs = neighbors_.body_pairs();
  const auto& keys = neighbors_.keys();
  ShearHistory& history = neighbors_.history();
  const double radius = grain_.radius(), dt = settings_.time_step;
  const long n_pairs = long(pairs.size()), n_bodies = long(bodies_.size());
  rotation_.resize(n_bodies);
  pair_damping_.resize(n_pairs);  // not checkpointed (one evaluation's losses): sized here after a restore too
  pair_friction_.resize(n_pairs);
  // The law's constants of two full-size grains; a pair sets its damping (its masses) and, with a scaled grain, all.
  const PairLaw full_size = pair_law(law_, radius / 2, 1.0, dt);
  // A jkr bond holds beyond contact: its pairs are never skipped as open.
  const bool sleep = !law_.keeps_bonds();
  if (open_pairs_.size() != std::size_t(n_pairs)) open_pairs_.reset(n_pairs);

  std::size_t skipped = 0;
#pragma omp parallel if (n_pairs >= 8)
  {
    // Each body's rotation matrix once, rather than twice per grain pair (~9 pairs per grain in a crystal),
    // times its scale: the kernel then places a scaled grain's spheres at no cost per candidate.
#pragma omp for schedule(static)
    for (long b = 0; b < n_bodies; ++b) rotation_[b] = bodies_.orientation[b].toRotationMatrix() * bodies_.scale[b];
    // Guided: large chunks first, small ones at the end to balance. Chunks of 4 pairs cost the contact stage 27 %
    // more on the reference crystal (3.12 against 2.43-2.46 ms/step to 1 % strain, 2 threads; dynamic 32: 2.58-2.69,
    // 64: 2.49, static: 2.54): a shared counter taken 2,000 times a step, and neighbouring pairs' result slots,
    // written by both threads, sharing cache lines.
#pragma omp for schedule(guided) reduction(+ : skipped)
    for (long p = 0; p < n_pairs; ++p) {
      const BodyPairSpan& gp = pairs[p];
      // Watched for drift with no sphere pair within reach, or apart by more than the grains have moved since.
      if (gp.count == 0 || (sleep && open_pairs_.closed_off(std::size_t(p), bodies_, gp.a, gp.b))) {
        skipped += gp.count;
        pair_force_[p] = pair_torque_a_[p] = pair_torque_b_[p] = Vec3::Zero();
        pair_contacts_[p] = pair_sliding_[p] = 0;
        pair_overlap_[p] = pair_damping_[p] = pair_friction_[p] = 0;
        continue;
      }
      const Vec3 xa = bodies_.position[gp.a], xb = bodies_.position[gp.b];
      const Vec3 wa = bodies_.angular_velocity[gp.a], wb = bodies_.angular_velocity[gp.b];
      PairKernelConstants c = pair_constants(gp, full_size);
      // Contact points are taken relative to x_a. Then the relative velocity at c is v0 + dw x (c - x_a),
      // and the torques follow from the sums of F and (c - x_a) x F.
      c.v0 = bodies_.velocity[gp.a] - bodies_.velocity[gp.b] - wb.cross(xa - xb);
      c.dw = wa - wb;
      if (lagged_damping_) {
        const Vec3 ua = damping_angular_velocity_[gp.a], ub = damping_angular_velocity_[gp.b];
        c.v0_damping = damping_velocity_[gp.a] - damping_velocity_[gp.b] - ub.cross(xa - xb);
        c.dw_damping = ua - ub;
      } else {
        c.v0_damping = c.v0, c.dw_damping = c.dw;
      }
      // Where most candidates did not touch at the last evaluation, distances first (PairKernel).
      const bool sparse = double(pair_contacts_[p]) < kSparseShare * double(gp.count);
      const PairKernelSums s =
          kernel_(c, offset_arrays_, keys.data() + gp.first, gp.count, history.x.data() + gp.first,
                  history.y.data() + gp.first, history.z.data() + gp.first,
                  history.bonds ? history.bond.data() + gp.first : nullptr,
                  sparse ? &kernel_scratch_[omp_get_thread_num()] : nullptr);
      if (sleep) open_pairs_.evaluated(std::size_t(p), bodies_, gp.a, gp.b, s.contacts, s.nearest2, c.diameter);
      pair_force_[p] = s.force;
      pair_torque_a_[p] = s.moment;
      pair_torque_b_[p] = -s.moment - (xa - xb).cross(s.force);
      pair_contacts_[p] = s.contacts;
      pair_sliding_[p] = s.sliding;
      pair_overlap_[p] = s.overlap;
      pair_damping_[p] = s.damping;
      pair_friction_[p] = s.friction;
    }
  }

  stats_.candidates = keys.size();
  stats_.skipped = skipped;
  candidate_steps_ += double(keys.size());
  skipped_steps_ += double(skipped);
  stats_.contacts = stats_.sliding = 0;
  stats_.damping_loss = stats_.friction_loss = 0;
  std::fill(overlap_sum_.begin(), overlap_sum_.end(), 0.0);
  for (long p = 0; p < n_pairs; ++p) {
    const BodyPairSpan& gp = pairs[p];
    bodies_.force[gp.a] += pair_force_[p];
    bodies_.force[gp.b] -= pair_force_[p];
    bodies_.torque[gp.a] += pair_torque_a_[p];
    bodies_.torque[gp.b] += pair_torque_b_[p];
    stats_.contacts += pair_contacts_[p];
    stats_.sliding += pair_sliding_[p];
    stats_.damping_loss += pair_damping_[p];
    stats_.friction_loss += pair_friction_[p];
    overlap_sum_[gp.a] += pair_overlap_[p];
    overlap_sum_[gp.b] += pair_overlap_[p];
  }
}

double World::kinetic_energy() const {
  double e = 0;
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    if (bodies_.motion[b] == Motion::dynamic)
      e += bodies_.translational_energy(BodyId(b)) + bodies_.rotational_energy(BodyId(b));
  return e;
}

// Each candidate's force in parallel (most are apart: a sphere of the outer layer near, not on, the wall),
// then the sums into bodies and walls in key order, so the result does not depend on the threads.
void World::wall_forces() {
  StageTimer t(times_.walls);
  for (Wall& w : walls_) w.force.setZero(), w.contacts = 0;
  const auto& keys = neighbors_.wall_keys();
  Vec3* history = neighbors_.wall_history().data();
  const std::size_t per_body = grain_.sphere_count();
  const Vec3* offsets = grain_.offsets().data();
  const double radius = grain_.radius(), dt = settings_.time_step;
  const long n_keys = long(keys.size());
  // Platens do not stick: with a cohesive law (dmt, jkr) a sphere meets a wall with the law's Hertz part alone
  // (docs/model.md, "Interface laws"). A wall is a sphere of infinite radius, R* = r.
  ContactLaw wall_law = law_;
  if (law_.cohesive()) wall_law.normal = NormalModel::hertz_material, wall_law.surface_energy = 0;
  // Its constants once; a candidate sets its friction (the wall's), damping (its grain's mass) and radius.
  const PairLaw wall_constants = pair_law(wall_law, radius, 1.0, dt);
  wall_force_.resize(n_keys);
  wall_torque_.resize(n_keys);
  wall_touching_.resize(n_keys);
  wall_energy_.resize(n_keys);
#pragma omp parallel for schedule(static) if (n_keys >= 2048)
  for (long k = 0; k < n_keys; ++k) {
    const Wall& w = walls_[keys[k] >> 32];
    const std::size_t s = keys[k] & 0xffffffffu;
    const BodyId b = BodyId(s / per_body);
    const Vec3 centre = bodies_.position[b] + rotation_[b] * offsets[s % per_body];
    const double dist = w.distance(centre);
    const double delta = radius * bodies_.scale[b] - dist;
    wall_touching_[k] = delta > 0;
    if (delta <= 0) {
      if (!history[k].isZero()) history[k].setZero();
      continue;
    }
    const Vec3 c = centre - dist * w.normal;  // foot of the sphere centre on the plane
    const Vec3 arm = c - bodies_.position[b];
    const Vec3 v_rel = bodies_.velocity[b] + bodies_.angular_velocity[b].cross(arm) - w.velocity;
    const Vec3 v_damping =
        lagged_damping_ ? damping_velocity_[b] + damping_angular_velocity_[b].cross(arm) - w.velocity : v_rel;
    PairLaw pair = wall_constants;
    if (w.friction >= 0) pair.mu = w.friction;
    set_pair_damping(pair, wall_law, bodies_.mass[b]);
    pair.r_eff = radius * bodies_.scale[b];
    double no_bond = 0;  // walls do not bond
    const ContactForce cf = contact_force(wall_law, pair, w.normal, delta, v_rel, v_damping, history[k], no_bond);
    wall_force_[k] = cf.force;
    wall_torque_[k] = arm.cross(cf.force);
    wall_energy_[k] = {cf.energy, cf.damping, cf.friction};
  }
  stats_.wall_contacts = 0;
  stats_.wall_elastic_energy = 0;
  for (long k = 0; k < n_keys; ++k) {
    if (!wall_touching_[k]) continue;
    Wall& w = walls_[keys[k] >> 32];
    const BodyId b = BodyId((keys[k] & 0xffffffffu) / per_body);
    bodies_.force[b] += wall_force_[k];
    bodies_.torque[b] += wall_torque_[k];
    w.force -= wall_force_[k];
    ++w.contacts;
    ++stats_.wall_contacts;
    stats_.wall_elastic_energy += wall_energy_[k][0];
    stats_.damping_loss += wall_energy_[k][1];
    stats_.friction_loss += wall_energy_[k][2];
  }
}

// The saved state, in one list for both directions (CheckpointWriter and CheckpointReader have the
// same value/values names): what is written is what is read, in the same order.
template <class Archive, class Self>
void World::state(Archive& a, Self& w) {
  for (auto* field : {&w.bodies_.position, &w.bodies_.velocity, &w.bodies_.angular_momentum,
                      &w.bodies_.angular_velocity, &w.bodies_.force, &w.bodies_.torque, &w.bodies_.inertia,
                      &w.pair_force_, &w.pair_torque_a_, &w.pair_torque_b_, &w.external_force_, &w.external_torque_,
                      &w.applied_force_, &w.applied_torque_})
    a.values(*field);
  a.values(w.bodies_.orientation);
  a.values(w.bodies_.mass);
  a.values(w.bodies_.motion);
  a.values(w.walls_);
  a.values(w.pair_contacts_);
  a.values(w.pair_sliding_);
  a.values(w.pair_overlap_);
  a.values(w.overlap_sum_);
  a.value(w.time_);
  a.value(w.steps_);
  a.value(w.rebuilds_);
  a.value(w.pair_searches_);
  a.value(w.candidate_steps_);
  a.value(w.skipped_steps_);
  a.value(w.stats_);
  a.value(w.energy_);
  a.value(w.times_);
  w.neighbors_.state(a);
  w.open_pairs_.state(a);
}

void World::save(CheckpointWriter& w) const {
  w.section("world");
  w.value(std::uint64_t(bodies_.size()));
  w.value(std::uint64_t(walls_.size()));
  state(w, *this);
}

void World::restore(CheckpointReader& r) {
  r.section("world");
  const auto bodies = r.value<std::uint64_t>(), walls = r.value<std::uint64_t>();
  if (bodies != bodies_.size() || walls != walls_.size())
    throw CheckpointError("checkpoint of a world with " + std::to_string(bodies) + " bodies and " +
                          std::to_string(walls) + " walls, this one has " + std::to_string(bodies_.size()) + " and " +
                          std::to_string(walls_.size()) + ": not the same spec");
  state(r, *this);
  spheres_current_ = false;  // sphere positions follow from the restored poses
  size_kernel_scratch();
  stored_energy_current_ = false;
}

}  // namespace granulab
