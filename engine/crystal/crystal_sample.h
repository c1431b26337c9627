// The crystal sample of the paper's experiment 2 (docs/model.md, "Crystal lattice", "Confinement"),
// ready for any loading: a crystal of space-filling grains (the paper's FCC of rhombic dodecahedra by default,
// or SC, BCC, HCP along any axis) built pre-strained by eps0 (sqrt2 p0 / E for FCC),
// two platens just touching its end rows, and the vacuum bag on its four lateral faces. A crystal
// experiment builds one, confines it (confinement.h), then loads it its own way.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/boundary/membrane.h"
#include "engine/crystal/crystal_lattice.h"
#include "engine/crystal/imperfections.h"
#include "engine/framework/workload.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {

/// Fixed confining forces (CrystalSample::fix_confining_forces): per face +x, -x, +y, -y, +z, -z, the
/// projected area of its grains (m^2) and the sum of their forces along the face's inward normal (N):
/// p0 x area on the lateral faces, on each end the mean of the platens' loads when they were fixed.
struct FixedForces {
  bool on = false;
  double area[6] = {0, 0, 0, 0, 0, 0};
  double load[6] = {0, 0, 0, 0, 0, 0};
  double end_load = 0;  ///< what axial_stress() adds on each end: p0 x the cross-section, within 1 % (N)
  bool follows = false;  ///< the forces follow the grains: p0 on their exposed faces (CrystalSample::wrap_bag)
};

struct CrystalSampleParams {
  LatticeType lattice = LatticeType::fcc;  ///< the grain follows: grain.shape = grain_shape(lattice)
  Indices axis{-1, -1, 2};                 ///< compression axis (lab z), a lattice direction (lattice_type.h)
  Indices lateral{0, 0, 0};                ///< lab x; all zero: default_lateral()
  GrainGeometry grain{Shape::rhombic_dodecahedron, 0.01, 10, 0.75};
  Material material{};                          // E = 3 GPa, rho = 1200, f = 0.35
  int grains_x = 8, rows_z = 18, layers_y = 6;  ///< grains per row, rows, {111} layers (-)
  std::vector<GrainId> knockout_ids;
  std::vector<KnockoutRegion> knockout_regions;
  double confining_pressure = 60e3;  ///< p0 (Pa)
  double mass_scaling = 1.0;         ///< density factor (-)
  double wall_friction = -1;         ///< platens' Coulomb coefficient (-); negative: material.friction
  double time_step_factor = 0.3;     ///< dt / t0 (-); with quarter-step dashpots (docs/model.md, "Time step")
  double skin_factor = 0.01;         ///< skin / d (-); see crystal_skin_factor()
  std::string kernel = "auto";       ///< the contact kernel's instruction set (pair_kernels()); auto: the widest here
  double local_damping = 0;          ///< lambda of each grain's net force (-); 0: none (integrator.h, LocalDamping)
  double local_damping_rotational = -1;  ///< lambda of its net torque (-); negative: local_damping
  DampingVelocity damping_velocity = DampingVelocity::quarter_step;  ///< what the dashpots see (world.h)
  double bridge_span = 1.5;          ///< the bag spans holes: see Membrane; in grain sizes a (-)
  double bridge_depth = 0.3;         ///< in grain sizes a (-); layers are a/sqrt3 = 0.577 a apart along y
  int membrane_interval = 200;       ///< steps between re-detections of the bag's surface (~0.1 s each at full size)
  ImperfectionParams imperfections;  ///< smaller and tilted grains (imperfections.h); none by default
  // Confinement (confinement.h).
  double equilibrium_tolerance = 0.01;  ///< |wall stress - p0| / p0 (-); cohesive laws: / max(p0, cohesive scale)
  double kinetic_tolerance = 1e-4;      ///< kinetic / elastic energy (-)
  int equilibrium_checks = 3;           ///< consecutive membrane intervals meeting both (-)
  std::uint64_t max_confinement_steps = 200000;
  /// A confinement that stops at the cap fails the experiment (ConfinementFailed, confinement.h); off only for tests
  /// that load a sample known not to settle.
  bool require_equilibrium = true;
};

/// eps0 = sqrt2 p0 / E (-): the hydrostatic pre-strain at which the face overlaps of the FCC packing
/// carry p0 (the Love-Weber stress of the packing is E eps0 / sqrt2).
double hydrostatic_prestrain(double confining_pressure, double youngs_modulus);
/// The same for the sample's lattice and interface law (-), the pre-strain whose face overlaps carry a mean stress
/// p0: with hooke eps0 = 6 V p0 / (k_n sum_f N_f l_f^2) over the grain's faces f (N_f spheres under it, l_f = 2 h_f
/// to the neighbour across it), sqrt2 p0 / E for FCC (the function above, bit for bit), p0 / E for SC, and HCP's the
/// same as FCC's up to round-off (its trapezoids hold N_e^2 spheres as its rhombi do, all 12 faces at D/2); with
/// any other law, sum_f N_f F(eps0 l_f) l_f = 6 V p0 solved for eps0 (a Hertz crystal is softer at these loads: its
/// eps0 is larger, and confining it from Hooke's would take the platens far longer).
double hydrostatic_prestrain(const CrystalSampleParams& p);

/// The sample's size, the confinement's step cap (knock-outs and an early equilibrium only lower them) and
/// its expected steps.
Workload confinement_workload(const CrystalSampleParams& p);
/// The time steps confinement is expected to take (-), from the crystal's aspect ratio (calibrated).
double expected_confinement_steps(const CrystalSampleParams& p);
/// The platens' gap before confinement (m): the end rows' outermost sphere surfaces, as the sample places
/// its walls, from the lattice and the grain's spheres alone (a few microseconds, no world built).
double crystal_length_estimate(const CrystalSampleParams& p);
/// The quasi-static rate scale R = p0 / E (-), within [1e-8, 0.1]: the shear's default rate number (tension calls it
/// with sigma / 10 in place of p0), and the unit a compression's rate is measured in (default_compression_rate_number(),
/// QuasiStaticQuality). It scales with p0 / E because a slip event loads the crystal by about E R (c / L) times
/// its duration, against a strength of order p0 (docs/results.md, "Quasi-static rate").
double quasi_static_rate_number(double confining_pressure, double youngs_modulus);

/// The order of the stress a cohesive law holds a crystal together with (Pa): one sphere pair's pull-off force
/// F_pulloff(d / 4) over the area a pair holds on a face, s^2 (s the sphere spacing); 0 without cohesion.
double cohesive_stress_scale(const CrystalSampleParams& p);

/// c = sqrt(E / (rho x mass scaling)) (m/s): the grain material's bar wave speed, what the crystal loadings' rate
/// numbers R = v / c and their ramps (in transits L / c) are measured in.
double crystal_wave_speed(const CrystalSampleParams& p);
/// The distance between neighbouring grains' centres across their farthest faces, as built (m):
/// CrystalSample::face_neighbour_distance() without a sample.
double face_neighbour_distance(const CrystalSampleParams& p, const GrainTemplate& grain);
/// The lattice the sample is built on (its sites, knock-outs done), without the world: cheap.
CrystalLattice sample_lattice(const CrystalSampleParams& p);
/// dt (s) of the sample's world; with imperfect grains, of the smallest one they may draw (min_scale_bound).
double crystal_time_step(const CrystalSampleParams& p);

/// The default neighbour skin / d of a dense crystal (docs/model.md, "Time integration"). Only the
/// touching, in-line sphere pairs should be candidates: the next sphere across a face sits at
/// d sqrt(1 + (1 - kappa)^2) (1.031 d at kappa = 0.75), and a skin beyond that makes every contact drag
/// its neighbours along (5x slower, measured). Once faces slide their sphere grids no longer line up and
/// a sphere has ~ 2 pi d skin / s^2 candidates across a face (3 at 0.03 d, 1 at 0.01 d), while a
/// smaller skin searches grain pairs more often: 0.01 d balances the two (reference crystal to 0.5 %,
/// per-grain-pair searches: 5.52 ms/step at 0.01 d, 5.53 at 0.005 d, 5.86 at 0.02 d; bench/README.md).
double crystal_skin_factor(double overlap);

class CrystalSample {
 public:
  /// Builds the lattice, the grains, the platens and the bag (not yet confined). Throws
  /// std::invalid_argument on parameters the physics cannot run.
  explicit CrystalSample(const CrystalSampleParams& params);

  const CrystalSampleParams& params() const { return params_; }
  World& world() { return world_; }
  const World& world() const { return world_; }
  const GrainTemplate& grain() const { return grain_; }
  const CrystalLattice& lattice() const { return lattice_; }
  /// Each grain's size factor and tilt, in body order (all perfect without imperfections).
  const std::vector<GrainImperfection>& imperfections() const { return imperfections_; }
  /// The stable grain id of each body.
  const std::vector<GrainId>& grain_ids() const { return ids_; }
  const MembraneStats& membrane_stats() const { return membrane_.stats(); }
  std::size_t top_wall() const { return top_; }
  std::size_t bottom_wall() const { return bottom_; }
  /// The distance between neighbouring grains' centres across their farthest faces, as built (m): what finds
  /// a grain's face neighbours (a cut-off a little beyond it).
  double face_neighbour_distance() const;
  /// Bodies on the -x, +x, -y, +y sides of the lattice (k = 0..3).
  const std::vector<BodyId>& side(int k) const { return side_[k]; }
  /// Lattice cross-section normal to z (m^2): what wall forces are divided by.
  double cross_section() const { return cross_section_; }
  /// t0 of the grain with mass scaling (s).
  double contact_time() const { return t0_; }

  /// Wall force along its inward normal over the cross-section, compressive positive (Pa).
  double wall_stress(std::size_t wall) const;
  /// Mean lateral stresses (sigma_xx, sigma_yy) carried by the packing (Pa): the contact forces' sum of
  /// f_x l_x (l = branch vector between grain centres) over the bag's projected area on the x faces
  /// times the distance between the load centres of the two x faces (same for y). By the virial
  /// identity this equals p0 when every grain is in equilibrium under contacts and bag alone, so it
  /// measures how well the packing carries the bag's load (inertia or wall shear show up as a gap). With the wrapped
  /// bag (wrap_bag()): (sum of f_k l_k + each pressed face's F c_k n_k, c its centroid from the grain's centre) over
  /// the volume its faces enclose along k (the sum of (x + c)_k n_k area over them).
  std::pair<double, double> lateral_stresses() const;
  /// Kinetic over elastic energy of the contacts (-), 0 without contacts.
  double kinetic_elastic_ratio() const;
  /// Re-detects the bag's surface and recomputes its forces; nothing once the forces are fixed.
  void update_membrane();
  /// One time step of the crystal, as every crystal loop takes it: the world's step, then, every
  /// membrane_interval steps counted from step `since`, the finiteness check (timed as control) and the
  /// bag's update. True when the bag was updated this step.
  bool step(std::uint64_t since);
  /// Replaces the bag by fixed forces, as the paper's LAMMPS scripts confined the crystal: each surface
  /// grain gets, once, p0 x its projected area along the inward normal of each lateral face it lies on,
  /// at its centre, from the sample as it is (confined); the end grains share the platens' present load
  /// (the mean of the two) in proportion to their projected areas on the ends, and the platens step back to bare contact. These
  /// forces then stay as they are, whatever the grains do; the platens carry the deviator alone, and
  /// axial_stress() counts both. Call on a sample at rest, right before it is loaded. `end_load` (N), when
  /// given, is each end's load instead of the platens' (bench/fixed_force_lammps: the bag's forces on a sample
  /// as built, whose platens carry nothing yet).
  void fix_confining_forces(double end_load = -1);
  /// The paper's LAMMPS set-up instead of the bag (docs/model.md, "Fixed forces"): on the sample as built
  /// (the lattice at eps0, at rest, platens just touching), each surface grain gets, at its centre,
  /// -p0 x the vector area of its exposed faces (exposed_faces.h), end grains included, fixed from then on.
  /// They add up to zero; the platens carry the deviator alone, and axial_stress() adds p0 back on each
  /// end. The summary's areas are the positive parts of the vector areas per face.
  void fix_face_forces();
  /// The bag wrapped over the whole sample, as a vacuum bag on centimetre grains is (loading.confinement
  /// "pressure", docs/model.md, "Confinement"): p0 on every exposed face of every surface grain (exposed_faces.h,
  /// end faces included), at the face's centroid along its inward normal, both turning and moving with the grain at
  /// every step. On the lattice as built this is the paper's LAMMPS set-up (fix_face_forces()) with a pressure's
  /// torques; as the grains turn it stays a pressure (over a rigid sample it sums to no force and no moment, where
  /// fixed forces make a couple). The platens step back to bare contact and carry the deviator alone; axial_stress()
  /// adds p0 on each end.
  void wrap_bag();
  const FixedForces& fixed_forces() const { return fixed_; }
  /// Takes the bag away: no confining force from now on (fixed forces of zero), as a crystal held by its own grips
  /// and cohesion is loaded bare. Forces are recomputed.
  void release_confinement();
  /// Radius of sphere i (body-major index) (m): the template's times its grain's scale.
  double sphere_radius(std::size_t i) const {
    return grain_.radius() * world_.bodies().scale[i / grain_.sphere_count()];
  }
  /// The axial stress on the face at a platen (Pa): wall_stress() plus, with fixed forces, their p0 (end_load).
  double axial_stress(std::size_t wall) const;
  /// Throws std::runtime_error when energy or wall forces are no longer finite (a blown-up run).
  void check_finite() const;
  /// The world, the bag and fixed forces (checkpoints); everything else follows from the parameters.
  void save(CheckpointWriter& w) const;
  void restore(CheckpointReader& r);

 private:
  /// The bodies' scales for the bag's height maps, when some grain is not the template's size.
  const std::vector<double>* scales() const { return params_.imperfections.any() ? &world_.bodies().scale : nullptr; }
  /// One face the wrapped bag presses, in its grain's frame, scaled by the grain's size.
  struct PressedFace {
    BodyId body = 0;
    Vec3 normal;        ///< outward unit normal (-)
    Vec3 centroid;      ///< from the grain's centre (m)
    double force = 0;   ///< p0 x area (N)
  };
  /// Both platens step back by their deepest sphere's overlap: bare contact.
  void retract_platens();
  /// wrap_bag()'s faces, from the lattice; the forces and torques they make now.
  void list_pressed_faces();
  void press_faces();
  CrystalSampleParams params_;
  GrainTemplate grain_;
  CrystalLattice lattice_;
  std::vector<GrainImperfection> imperfections_;  // per site
  World world_;
  Membrane membrane_;
  FixedForces fixed_;
  std::vector<PressedFace> pressed_;  // with fixed_.follows
  std::vector<GrainId> ids_;
  std::size_t top_ = 0, bottom_ = 1;
  double cross_section_ = 0, t0_ = 0;
  std::vector<BodyId> side_[4];
};

}  // namespace granulab
