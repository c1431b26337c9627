// The granulab side of the speed comparison with LAMMPS (bench/lammps_compare.py runs both).
// Problem: a dense off-axis FCC block of rhombic dodecahedra (N_e = 10, kappa = 0.75, a = 0.01 m,
// E = 3 GPa, rho = 1200, f = 0.35, zeta = 0.05, k_t/k_n = 2/7; default 6 x 6 x 6 = 216 grains, 210,384
// spheres) built from build_crystal() with a small pre-strain eps0 so that neighbouring faces touch;
// confined by two fixed plane walls normal to +-x and compressed by two walls normal to +-z, all four
// placed touching the outermost sphere surfaces (but for a gap of v dt / 2, see main()); the bottom wall
// is fixed, the top one moves down
// at the constant speed v = R sqrt(E/rho) from step 0. dt = 0.2 t0 (model.h). The lateral y faces are free.
//
// It runs S steps, records the normal force received by each wall every M steps, times the stepping
// (wall clock, after setup) and prints spheres, steps, sphere-steps/s, threads and peak RSS, last line
// machine-readable ("RESULT key=value ...").
//
// --write-lammps DIR writes the same problem for LAMMPS (the input script itself is written by
// lammps_compare.py from these files):
//   DIR/data.grains   read_data file, atom_style sphere: "id type diameter density x y z" for every sphere,
//                     plus a "Molecules" section (molecule id = grain id + 1) for fix property/atom mol;
//   DIR/bodies.rigid  per-body file for fix rigid/small's infile keyword: our grain mass (density x polyhedron
//                     volume), centre of mass and the inertia tensor of the solid polyhedron in lab axes
//                     (isotropic for an RD), zero velocity and angular momentum, zero image flags;
//   DIR/params.txt    "key value" lines: contact constants (k_n, k_t, LAMMPS' gamma_n for a grain pair and for a
//                     wall), dt, steps, record interval, wall positions and the top wall's speed, box bounds.
//
// Usage: bench_compare [--threads N] [--grains K] [--steps S] [--record-every M] [--rate R] [--prestrain E0]
//                      [--skin-factor F] [--write-lammps DIR] [--forces FILE]
// LAMMPS is a comparison tool only: nothing here links to or needs it.
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/machine.h"
#include "bench/lammps_files.h"
#include "engine/crystal/crystal_lattice.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

using namespace granulab;

namespace {

struct Options {
  int threads = 0;  // 0: OpenMP default
  int grains = 6;   // per side: grains_x = rows_z = layers_y
  int steps = 2000;
  int record_every = 20;
  double rate = 1e-4;         // R = v / sqrt(E/rho)
  double prestrain = 1e-4;    // eps0
  double skin_factor = 0.03;  // skin / d, the crystal default
  std::string lammps_dir, forces_file;
};

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // KiB on Linux
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
    const char* v = argv[++i];
    if (a == "--threads") o.threads = std::atoi(v);
    else if (a == "--grains") o.grains = std::atoi(v);
    else if (a == "--steps") o.steps = std::atoi(v);
    else if (a == "--record-every") o.record_every = std::atoi(v);
    else if (a == "--rate") o.rate = std::atof(v);
    else if (a == "--prestrain") o.prestrain = std::atof(v);
    else if (a == "--skin-factor") o.skin_factor = std::atof(v);
    else if (a == "--write-lammps") o.lammps_dir = v;
    else if (a == "--forces") o.forces_file = v;
    else throw std::invalid_argument("unknown option " + a);
  }
  if (o.grains < 2 || o.steps < 1 || o.record_every < 1)
    throw std::invalid_argument("need --grains >= 2, --steps >= 1, --record-every >= 1");
  return o;
}

enum WallIndex { x_lo, x_hi, z_lo, z_hi };
const char* const wall_names[] = {"xlo", "xhi", "zlo", "zhi"};

// Writes the LAMMPS inputs for the world as built (before any step).
void write_lammps(const std::string& dir, const World& world, const Material& mat, double eps0, double speed,
                  const Options& o) {
  // Box: the sample plus a margin of one grain size on every side (walls only move inwards; the free
  // y faces bulge by far less than that in a benchmark run).
  const std::vector<Vec3>& spheres = world.sphere_positions();
  Vec3 lo = spheres.front(), hi = lo;
  for (const Vec3& x : spheres) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double margin = world.grain().geometry().size;
  lo.array() -= margin, hi.array() += margin;
  bench::write_grains(dir, world, mat.density, lo, hi,
                      "granulab bench_compare: " + std::to_string(world.bodies().size()) + " rhombic dodecahedra, " +
                          std::to_string(world.grain().sphere_count()) + " spheres each");
  std::ofstream f(dir + "/params.txt");
  f.precision(17);
  bench::write_contact_params(f, world, mat.density);
  auto put = [&](const char* k, double v) { f << k << ' ' << v << "\n"; };
  put("youngs_modulus", mat.youngs_modulus);
  put("prestrain", eps0);
  put("steps", o.steps);
  put("record_every", o.record_every);
  for (int w = 0; w < 4; ++w) {
    const Wall& wall = world.walls()[w];
    const int axis = w < 2 ? 0 : 2;
    f << "wall_" << wall_names[w] << ' ' << wall.point[axis] << "\n";
  }
  put("top_speed", speed);  // the zhi wall moves along -z at this speed
  f << "box " << lo.x() << ' ' << hi.x() << ' ' << lo.y() << ' ' << hi.y() << ' ' << lo.z() << ' ' << hi.z() << "\n";
}

}  // namespace

int main(int argc, char** argv) try {
  granulab::print_machine();
  const Options o = parse(argc, argv);
  if (o.threads > 0) omp_set_num_threads(o.threads);

  const GrainTemplate grain({Shape::rhombic_dodecahedron, 0.01, 10, 0.75});
  const Material mat;  // E = 3 GPa, rho = 1200, f = 0.35, k_t/k_n = 2/7, zeta = 0.05
  CrystalGeometry geo;
  geo.size = grain.geometry().size;
  geo.prestrain = o.prestrain;
  geo.grains_x = geo.rows_z = geo.layers_y = o.grains;
  const CrystalLattice lattice = build_crystal(geo);

  WorldSettings settings;
  settings.time_step = 0.2 * contact_time_scale(grain, mat.youngs_modulus, mat.density);
  settings.skin = o.skin_factor * grain.diameter();
  World world(grain, contact_law(grain, mat), settings);
  for (const LatticeSite& s : lattice.sites) world.add_grain(s.position, lattice.orientation, mat.density);

  // Walls touching the outermost sphere surfaces (the x ones lie on the flat faces of the end grains), but
  // for a gap of half the top wall's travel in one step: the outer spheres of a perfect lattice are coplanar,
  // and with a zero gap their overlaps with a wall start at round-off level, so which of them count as
  // touching (and feel the damping force c_n v from the moving wall) would depend on the last bit of
  // their positions, which the two codes compute differently. With the gap every outer sphere of the top
  // row touches the top wall from step 1 with overlap v dt / 2, in both codes.
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  for (const Vec3& x : world.sphere_positions()) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double speed = o.rate * std::sqrt(mat.youngs_modulus / mat.density);
  const double r = grain.radius() + 0.5 * speed * settings.time_step;
  world.add_wall(Wall{Vec3(lo.x() - r, 0, 0), Vec3::UnitX(), Vec3::Zero(), Vec3::Zero()});
  world.add_wall(Wall{Vec3(hi.x() + r, 0, 0), -Vec3::UnitX(), Vec3::Zero(), Vec3::Zero()});
  world.add_wall(Wall{Vec3(0, 0, lo.z() - r), Vec3::UnitZ(), Vec3::Zero(), Vec3::Zero()});
  world.add_wall(Wall{Vec3(0, 0, hi.z() + r), -Vec3::UnitZ(), -speed * Vec3::UnitZ(), Vec3::Zero()});
  world.compute_forces();

  if (!o.lammps_dir.empty()) write_lammps(o.lammps_dir, world, mat, o.prestrain, speed, o);

  // Force received by each wall, along the lab axis of its normal (x for the side walls, z for top and
  // bottom); compressive loads give xlo < 0, xhi > 0, zlo < 0, zhi > 0.
  struct Record {
    std::uint64_t step;
    double f[4];
  };
  std::vector<Record> records;
  records.reserve(o.steps / o.record_every + 2);
  auto record = [&] {
    Record rec{world.steps(), {}};
    for (int w = 0; w < 4; ++w) rec.f[w] = world.walls()[w].force[w < 2 ? 0 : 2];
    records.push_back(rec);
  };
  record();

  const auto start = std::chrono::steady_clock::now();
  for (int s = 1; s <= o.steps; ++s) {
    world.step();
    if (s % o.record_every == 0) record();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (!o.forces_file.empty()) {
    std::ofstream f(o.forces_file);
    f.precision(10);
    f << "step,time,f_xlo,f_xhi,f_zlo,f_zhi\n";
    for (const Record& rec : records)
      f << rec.step << ',' << rec.step * settings.time_step << ',' << rec.f[0] << ',' << rec.f[1] << ',' << rec.f[2]
        << ',' << rec.f[3] << "\n";
  }

  const double sphere_steps = double(world.sphere_count()) * o.steps;
  const StageTimes& t = world.stage_times();
  std::printf("granulab: %zu grains, %zu spheres, %d steps, dt %.4g s, top wall speed %.4g m/s\n",
              world.bodies().size(), world.sphere_count(), o.steps, settings.time_step, speed);
  std::printf(
      "  %.3f s  %.4g sphere-steps/s  threads %d  peak RSS %.0f MiB  rebuilds %llu  contacts %zu  wall contacts %zu\n",
      seconds, sphere_steps / seconds, omp_get_max_threads(), peak_rss_mib(), (unsigned long long)world.rebuilds(),
      world.contact_stats().contacts, world.contact_stats().wall_contacts);
  std::printf("  stages (s): integrate %.2f  spheres %.2f  rebuild %.2f  contacts %.2f  walls %.2f\n", t.integrate,
              t.spheres, t.rebuild, t.contacts, t.walls);
  std::printf("  final wall forces (N): xlo %.6g  xhi %.6g  zlo %.6g  zhi %.6g\n", records.back().f[0],
              records.back().f[1], records.back().f[2], records.back().f[3]);
  std::printf(
      "RESULT spheres=%zu grains=%zu steps=%d seconds=%.6f sphere_steps_per_s=%.6g threads=%d peak_rss_mib=%.1f\n",
      world.sphere_count(), world.bodies().size(), o.steps, seconds, sphere_steps / seconds, omp_get_max_threads(),
      peak_rss_mib());
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_compare: %s\n", e.what());
  return 1;
}
