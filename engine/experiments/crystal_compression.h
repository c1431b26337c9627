// Experiment 2 of the paper (sections 4-6, Figs. 6-12): an FCC crystal of rhombic dodecahedra in the
// off-axis orientation, confined by a vacuum bag at p0 and compressed between two frictional walls.
//  1. build: the lattice with cell (1 - eps0) a, where eps0 = sqrt2 p0 / E is the hydrostatic pre-strain
//     that carries p0 (each face pair overlaps by eps0 a/sqrt2; Love-Weber stress of the FCC packing
//     = E eps0 / sqrt2); walls just touching the end rows.
//  2. confine: membrane pressure p0 on the lateral surface, walls servo-controlled to p0, until the
//     equilibrium criterion holds (wall stresses within `equilibrium_tolerance` of p0 and kinetic
//     energy below `kinetic_tolerance` of the elastic energy, at `equilibrium_checks` checks in a row).
//  3. compress: the top wall moves down at constant speed (the bottom one is fixed), strain rate from the rate number
//     R = L eps_dot / sqrt(E / rho) (rho with mass scaling); curve rows and snapshots on the way.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "engine/boundary/membrane.h"
#include "engine/experiments/crystal_lattice.h"
#include "engine/experiments/model.h"
#include "engine/experiments/progress.h"
#include "engine/world/world.h"

namespace granulab {

struct CrystalParams {
  GrainGeometry grain{Shape::rhombic_dodecahedron, 0.01, 10, 0.75};
  Material material{};  // E = 3 GPa, rho = 1200, f = 0.35
  int grains_x = 8, rows_z = 18, layers_y = 6;
  std::vector<std::uint32_t> knockout_ids;
  std::vector<KnockoutRegion> knockout_regions;
  double confining_pressure = 60e3;  ///< p0 (Pa)
  double max_strain = 0.1;           ///< compression stops here (-)
  double rate_number = 1e-5;         ///< R (-); converged default, see README "Quasi-static rate"
  double mass_scaling = 1.0;         ///< density factor (-)
  double wall_friction = -1;         ///< platens' Coulomb coefficient; negative: material.friction
  int curve_points = 400;
  std::vector<double> snapshot_strains{0.0, 0.01, 0.02, 0.04, 0.08};
  double time_step_factor = 0.2;       ///< dt / t0
  double skin_factor = 0.01;           ///< skin / d (see api/spec.cpp)
  double bridge_span = 1.5;            ///< the bag spans holes: see Membrane; in grain sizes a
  double bridge_depth = 0.3;           ///< in grain sizes a (layers are a/sqrt3 = 0.577 a apart along y)
  int membrane_interval = 200;         ///< steps between re-detections of the bag's surface (~0.1 s each at full size)
  double equilibrium_tolerance = 0.01; ///< confinement: |wall stress - p0| / p0 (-)
  double kinetic_tolerance = 1e-4;     ///< confinement: kinetic / elastic energy (-)
  int equilibrium_checks = 3;          ///< consecutive membrane intervals meeting both
  std::uint64_t max_confinement_steps = 200000;
};

struct CrystalRow {
  double strain;                      ///< wall approach / initial length
  double stress_top, stress_bottom;   ///< wall force / initial cross-section, compressive positive (Pa)
  double deviator;                    ///< mean of the two - p0 (Pa)
  double lateral_strain_x, lateral_strain_y;  ///< change of width / thickness (extension positive)
  double lateral_stress;              ///< mean of the two lateral_stresses() (Pa)
  double kinetic_elastic_ratio;
  std::size_t contacts, sliding_contacts;
};

struct CrystalSnapshot {
  double strain = 0;
  std::uint64_t step = 0;
  std::vector<std::uint32_t> id;
  std::vector<Vec3> position, displacement;  ///< m, from the start of compression
  std::vector<Quat> orientation;
  std::vector<double> penetration, penetration_ratio;  ///< Delta (m), Delta / mean Delta
  std::vector<double> max_shear_strain, equivalent_strain;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> interfaces;  ///< grain ids
  std::vector<double> sliding;  ///< per interface (m)
};

struct ConfinementReport {
  std::uint64_t steps = 0;
  bool converged = false;
  double stress_top = 0, stress_bottom = 0, lateral_stress_x = 0, lateral_stress_y = 0;
  double kinetic_elastic_ratio = 0;
};

struct CrystalResult {
  std::vector<CrystalRow> curve;
  std::vector<CrystalSnapshot> snapshots;
  ConfinementReport confinement;
  double prestrain = 0, sphere_diameter = 0, normal_stiffness = 0, time_step = 0, strain_rate = 0;
  double initial_length = 0, cross_section = 0;
  int spheres_per_face = 0;
  std::size_t grains = 0, spheres = 0, knocked_out = 0;
  std::uint64_t steps = 0, compression_steps = 0, rebuilds = 0;
  double wall_seconds = 0;
  int threads = 1;
  StageTimes stage_times;
};

/// Optional callbacks that see results as they are made, so a long run loses nothing if it is killed.
struct CrystalObserver {
  std::function<void(const CrystalRow&)> row;            ///< each curve row as it is recorded
  std::function<void(const CrystalSnapshot&)> snapshot;  ///< each snapshot as it is taken
};

class CrystalCompression {
 public:
  explicit CrystalCompression(const CrystalParams& params);

  World& world() { return world_; }
  const CrystalLattice& lattice() const { return lattice_; }
  const MembraneStats& membrane_stats() const { return membrane_.stats(); }
  const std::vector<std::uint32_t>& grain_ids() const { return ids_; }

  /// Phase 2 alone (normally called by run()).
  ConfinementReport confine(const ProgressFn& progress = nullptr);
  /// Confines, compresses, records; `progress` may stop the run (throws Cancelled).
  CrystalResult run(const ProgressFn& progress = nullptr, const CrystalObserver& observer = {});

  /// Mean lateral stresses (sigma_xx, sigma_yy) carried by the packing: the contact forces' sum of
  /// f_x l_x (l = branch vector between grain centres) over the bag's projected area on the x faces
  /// times the distance between the load centres of the two x faces (same for y). By the virial
  /// identity this equals p0 when every grain is in equilibrium under contacts and bag alone, so it
  /// measures how well the packing carries the bag's load (inertia or wall shear show up as a gap).
  std::pair<double, double> lateral_stresses() const;

 private:
  void update_membrane();
  /// Throws std::runtime_error when energy or wall forces are no longer finite (a blown-up run).
  void check_finite() const;
  double wall_stress(std::size_t wall) const;
  CrystalRow measure(double strain) const;
  CrystalSnapshot snapshot(double strain) const;

  CrystalParams params_;
  GrainTemplate grain_;
  CrystalLattice lattice_;
  World world_;
  Membrane membrane_;
  std::vector<std::uint32_t> ids_;  // grain id of each body
  std::size_t top_ = 0, bottom_ = 1;
  double cross_section_ = 0, t0_ = 0;
  // Reference state (end of confinement).
  std::vector<Vec3> ref_position_;
  std::vector<Quat> ref_orientation_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> interfaces_;  // body indices
  double ref_length_ = 0, ref_width_ = 0, ref_thickness_ = 0;
  std::vector<std::uint32_t> side_[4];  // bodies on the -x, +x, -y, +y sides of the lattice
};

}  // namespace granulab
