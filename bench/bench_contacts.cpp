// Benchmark of the time step: nanoseconds per sphere-step and peak memory for
//  (a) the two sliding cubes at N_e = 10 (the two_cube_sliding experiment, prescribed motion), and
//  (b) a dense FCC block of rhombic dodecahedra at N_e = 10, kappa = 0.75, face to face under a
//      0.5 % pre-strain, the outer shell of grains held, the inner grains free; skin 0.03 d, the crystals'
//      default until 2026-11-22 (now min(0.01, ...) d: crystal_skin_factor), kept so that the figures in
//      bench/README.md stay comparable. It gives 2.5 candidates per sphere, 16 % of them touching.
// Usage: bench_contacts [--threads N] [--grains-per-side K] [--steps S]
// Speed claims in the issue notes come from this program, never from the unit tests.
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/machine.h"
#include "engine/model/model.h"
#include "engine/experiments/two_cube_sliding/two_cube_sliding.h"
#include "engine/world/world.h"

using namespace granulab;

namespace {

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

void report(const char* name, std::size_t spheres, std::uint64_t steps, double seconds, const StageTimes& t) {
  const double ns = seconds * 1e9 / (double(spheres) * double(steps));
  std::printf(
      "%-34s spheres %8zu  steps %7llu  %7.2f s  %8.2f ns/sphere-step  %.3g sphere-steps/s  threads %d  peak RSS %.0f "
      "MiB\n",
      name, spheres, (unsigned long long)steps, seconds, ns, 1e9 / ns, omp_get_max_threads(), peak_rss_mib());
  std::printf("%-34s stages (s): integrate %.2f  spheres %.2f  rebuild %.2f  contacts %.2f  walls %.2f\n", "",
              t.integrate, t.spheres, t.rebuild, t.contacts, t.walls);
}

void two_cubes() {
  TwoCubeParams p;  // N_e = 10, kappa = 0.75, f = 0.3
  p.rate_number = 1e-5;
  TwoCubeSliding experiment(p);
  const TwoCubeResult r = experiment.run();
  report("(a) two cubes N_e=10", r.run.spheres, r.run.steps, r.run.wall_seconds, r.run.stage_times);
}

// K^3 grains on the FCC lattice spanned by the primitive vectors (1/2,1/2,0), (1/2,0,1/2), (0,1/2,1/2)
// of the cubic cell a' = (1 - eps0) a: the RD in its canonical orientation is the Voronoi cell of the
// FCC lattice, so every pair of neighbours shares a full face.
void dense_block(int per_side, int steps) {
  const GrainTemplate grain({Shape::rhombic_dodecahedron, 0.01, 10, 0.75});
  Material mat;
  const double eps0 = 0.005, cell = 0.01 * (1 - eps0);
  // The crystals' integration (their defaults: the dashpots see the quarter-step velocity, 0.3 t0). With the half-step
  // velocity and 0.2 t0 this block sprang apart from K = 10 (974,000 spheres: contacts 513,000 -> 151,040 in 1,000
  // steps, 837 searches), stable at 0.15 t0: the step's bound falls with the damping of a face's ~100 contacts in
  // parallel (docs/model.md, "Damping velocity"), and only a large free interior has the modes that reach it.
  WorldSettings settings{0.3 * contact_time_scale(grain, mat.youngs_modulus, mat.density), 0.03 * grain.diameter(),
                         Vec3::Zero()};
  settings.damping_velocity = DampingVelocity::quarter_step;
  World world(grain, contact_law(grain, mat), settings);
  const Vec3 p1(0.5, 0.5, 0), p2(0.5, 0, 0.5), p3(0, 0.5, 0.5);
  for (int i = 0; i < per_side; ++i)
    for (int j = 0; j < per_side; ++j)
      for (int k = 0; k < per_side; ++k) {
        // The outer shell is held in place (the block would otherwise spring apart in a few t0);
        // the inside is free and starts with a small random velocity so contacts shear.
        const bool shell = i == 0 || j == 0 || k == 0 || i == per_side - 1 || j == per_side - 1 || k == per_side - 1;
        const BodyId b = world.add_grain(cell * (i * p1 + j * p2 + k * p3), Quat::Identity(), mat.density,
                                         shell ? Motion::prescribed : Motion::dynamic);
        if (!shell) world.bodies().velocity[b] = 1e-3 * Vec3(std::sin(b), std::cos(3.0 * b), std::sin(7.0 * b));
      }
  world.compute_forces();
  const std::size_t contacts0 = world.contact_stats().contacts;
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) world.step();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char name[64];
  std::snprintf(name, sizeof name, "(b) %zu RD N_e=10 block", world.bodies().size());
  report(name, world.sphere_count(), world.steps(), seconds, world.stage_times());
  std::printf("%-34s sphere contacts %zu at start, %zu at end; candidates %zu; rebuilds %llu\n", "", contacts0,
              world.contact_stats().contacts, world.contact_stats().candidates, (unsigned long long)world.rebuilds());
}

}  // namespace

int main(int argc, char** argv) {
  granulab::print_machine();
  int per_side = 0, steps = 2000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--threads") omp_set_num_threads(std::atoi(argv[i + 1]));
    else if (a == "--grains-per-side") per_side = std::atoi(argv[i + 1]);
    else if (a == "--steps") steps = std::atoi(argv[i + 1]);
  }
  if (per_side == 0) {
    two_cubes();
    dense_block(4, steps);  // 64 grains
  } else {
    dense_block(per_side, steps);
  }
  return 0;
}
