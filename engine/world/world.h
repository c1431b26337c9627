// The simulation world: rigid grains of one shared template (each possibly scaled), plane walls, and the time step
// as a short list of named, timed stages (docs/architecture.md):
//   kick/drift -> move walls -> search the candidates of the grain pairs whose relative pose drifted by
//   a skin (NeighborList::update) -> sphere contact forces -> wall forces -> kick.
// Contact forces are computed per grain pair into per-pair slots (in parallel) and then reduced into
// the bodies in pair order, so the answer does not depend on the number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/boundary/wall.h"
#include "engine/contact/contact_law.h"
#include "engine/contact/neighbor_list.h"
#include "engine/contact/pair_kernel.h"
#include "engine/dynamics/bodies.h"
#include "engine/dynamics/integrator.h"
#include "engine/geometry/grain_template.h"
#include "engine/world/energy_balance.h"
#include "engine/world/open_pairs.h"
#include "engine/world/run_stats.h"

namespace granulab {

/// The velocity the contacts' dashpots see at a step's force evaluation (docs/model.md, "Damping velocity").
enum class DampingVelocity {
  half_step,     ///< velocity Verlet's v(t + h/2), as LAMMPS: stable for omega h < 2 (sqrt(1 + zeta^2) - zeta)
  quarter_step,  ///< v(t) + a(t) h/4: the same bound with zeta / 2, so heavily damped stiff modes take a larger h
};

struct WorldSettings {
  double time_step = 0;         ///< s
  double skin = 0;              ///< neighbour-list skin (m)
  Vec3 gravity = Vec3::Zero();  ///< m/s^2
  double min_scale = 1;         ///< the smallest body scale (Bodies::scale) add_grain will be given (-)
  LocalDamping local_damping{};  ///< none by default (integrator.h)
  DampingVelocity damping_velocity = DampingVelocity::half_step;
  /// The contact kernel's instruction set (pair_kernels()): "" for the widest this CPU runs.
  std::string kernel;
};

struct ContactStats {
  std::size_t candidates = 0;  ///< sphere pairs in the neighbour list
  std::size_t skipped = 0;     ///< of which in grain pairs skipped as apart (OpenPairs) at the last evaluation
  std::size_t contacts = 0;    ///< sphere-sphere pairs with overlap > 0
  std::size_t sliding = 0;     ///< of which at the Coulomb limit
  std::size_t wall_contacts = 0;
  double wall_elastic_energy = 0;  ///< energy stored in the sphere-wall contacts (J); the spheres': elastic_energy()
  double damping_loss = 0;         ///< the dashpots' work in the last evaluation, all contacts (J)
  double friction_loss = 0;        ///< sliding's loss in the last evaluation, all contacts (J)
};

class World {
 public:
  World(const GrainTemplate& grain, const ContactLaw& law, const WorldSettings& settings);

  /// Adds a grain of the shared template at pose (x, q); mass and inertia from density (kg/m^3). `scale`
  /// (in [settings().min_scale, 1]) sizes its clump: offsets and sphere radii times scale.
  BodyId add_grain(const Vec3& x, const Quat& q, double density, Motion motion = Motion::dynamic, double scale = 1);
  std::size_t add_wall(const Wall& wall);

  const GrainTemplate& grain() const { return grain_; }
  const ContactLaw& law() const { return law_; }
  const WorldSettings& settings() const { return settings_; }
  Bodies& bodies() { return bodies_; }
  const Bodies& bodies() const { return bodies_; }
  std::vector<Wall>& walls() { return walls_; }
  const std::vector<Wall>& walls() const { return walls_; }
  const NeighborList& neighbors() const { return neighbors_; }
  /// World positions of all spheres, body-major (body * spheres per grain + local), computed from the
  /// poses when asked: the contact loops work from poses and template offsets instead.
  const std::vector<Vec3>& sphere_positions() const;
  std::size_t sphere_count() const { return sphere_pos_.size(); }

  /// Forces and torques for the current state (sphere positions, candidates, contacts, walls).
  /// Call once after setting up or after changing poses by hand; step() calls it itself.
  void compute_forces();
  /// One velocity-Verlet step of length settings().time_step.
  void step();

  double time() const { return time_; }
  std::uint64_t steps() const { return steps_; }
  /// Force evaluations at which some candidates were searched again (grain pairs or walls).
  std::uint64_t rebuilds() const { return rebuilds_; }
  const StageTimes& stage_times() const { return times_; }
  /// The instruction set of the contact kernel this world runs (settings().kernel resolved): "avx512", "avx2", "sse2".
  const std::string& kernel() const { return kernel_name_; }
  /// For the stages an experiment times around the world's (membrane, control, record).
  StageTimes& stage_times() { return times_; }
  /// The run's statistics and model numbers as of now; `wall_seconds` is the caller's measure of the run.
  RunStats run_stats(double wall_seconds) const;
  const ContactStats& contact_stats() const { return stats_; }
  /// The energy stored in the sphere-sphere contacts by the last force evaluation (J): the normal law's potential plus
  /// k_t |xi|^2 / 2 per contact (contact_law.h). Computed when first asked for after an evaluation (PairEnergyKernel),
  /// from the poses and histories it left (and a checkpoint restores): call it before moving bodies by hand. 0 before
  /// the first evaluation.
  double elastic_energy() const;
  /// Force on grain a of each grain pair of neighbors().body_pairs() from grain b, last evaluation (N).
  const std::vector<Vec3>& pair_forces() const { return pair_force_; }
  /// Per body: sum of the sphere overlaps with other grains in the last evaluation (m), the paper's Delta.
  const std::vector<double>& overlap_sums() const { return overlap_sum_; }
  /// Per-body forces and torques added at every evaluation (e.g. the confining membrane); sized with bodies.
  std::vector<Vec3>& external_force() { return external_force_; }
  std::vector<Vec3>& external_torque() { return external_torque_; }
  const std::vector<Vec3>& external_force() const { return external_force_; }
  /// Translational plus rotational kinetic energy of the dynamic bodies (J).
  double kinetic_energy() const;
  /// Starts the energy balance here: works and losses from zero, energies counted from their values now.
  void start_energy_balance();
  /// The balance since the last start_energy_balance() (or since the world was built).
  EnergyBalance energy_balance() const;

  /// Everything a step reads or a measurement reports, bit for bit (checkpoints). restore() needs a world
  /// built the same way (same template, law, settings, number of bodies and walls); throws CheckpointError.
  void save(CheckpointWriter& w) const;
  void restore(CheckpointReader& r);

 private:
  template <class Archive, class Self>
  static void state(Archive& a, Self& w);  // save() and restore()'s one list of fields
  void update_sphere_positions() const;
  void update_neighbors();
  void size_kernel_scratch();
  void sphere_contact_forces();
  PairKernelConstants pair_constants(const BodyPairSpan& gp, const PairLaw& full_size) const;
  void wall_forces();
  /// kick() with the settings' local damping, its energy counted with the dashpots'.
  void half_kick(double h);
  void add_half_step_work(double dt);  // world_energy.cpp

  GrainTemplate grain_;
  OffsetArrays offset_arrays_;  // grain_'s offsets for the contact loop
  ContactLaw law_;
  std::string kernel_name_;  // the instruction set of kernel_ (resolve_pair_kernel())
  PairKernel kernel_;        // the contact loop compiled for law_'s models
  PairEnergyKernel energy_kernel_;  // and its stored energy, for elastic_energy()
  WorldSettings settings_;
  Bodies bodies_;
  std::vector<Wall> walls_;
  NeighborList neighbors_;

  mutable std::vector<Vec3> sphere_pos_;
  mutable bool spheres_current_ = false;
  mutable StageTimes times_;

  // Per-grain-pair results of the contact stage, reduced in pair order.
  std::vector<Vec3> pair_force_, pair_torque_a_, pair_torque_b_;
  std::vector<std::uint32_t> pair_contacts_, pair_sliding_;
  std::vector<double> pair_overlap_, pair_damping_, pair_friction_;
  mutable std::vector<double> pair_energy_;  // elastic_energy()'s per pair, summed in pair order
  // elastic_energy() of the last evaluation, once computed (not saved: a restored world computes it again).
  mutable bool stored_energy_current_ = false;
  mutable double stored_energy_ = 0;
  // The dashpots' velocities in a step (DampingVelocity::quarter_step), and whether this evaluation uses them.
  std::vector<Vec3> damping_velocity_, damping_angular_velocity_;
  bool lagged_damping_ = false;
  std::vector<double> overlap_sum_;
  std::vector<KernelScratch> kernel_scratch_;  // per thread, for the kernel's two-pass path
  OpenPairs open_pairs_;                       // grain pairs apart by more than they have moved since (saved)
  mutable std::vector<Mat3> rotation_;  // body -> world rotation of each body times its scale, for the contact stage
  // Per sphere-wall candidate, the last evaluation: force on the sphere (N), its moment about the grain
  // centre (N m), and whether it touched.
  std::vector<Vec3> wall_force_, wall_torque_;
  std::vector<std::uint8_t> wall_touching_;
  std::vector<std::array<double, 3>> wall_energy_;  // stored, dashpots' and sliding's (J), as ContactForce
  std::vector<Vec3> external_force_, external_torque_;
  // The fixed forces (gravity and external) and torques of the last evaluation, as the bodies' forces hold them:
  // external_force_ may change before the next step, whose first half kick still uses these.
  std::vector<Vec3> applied_force_, applied_torque_;
  EnergyTotals energy_;

  double time_ = 0;
  std::uint64_t steps_ = 0, rebuilds_ = 0, pair_searches_ = 0;
  double candidate_steps_ = 0;  // sum over force evaluations of the candidates
  double skipped_steps_ = 0;    // the same of those skipped (ContactStats::skipped)
  ContactStats stats_;
};

}  // namespace granulab
