// Benchmark of the time step per lattice (issue 26: "the time per step of each lattice against the FCC crystal
// of the same sphere count"): for each crystal, a sample of about the same number of spheres (N_e = 4 by
// default), built pre-strained by its p0 in its bag and platens, then stepped as the crystal loops step it
// (CrystalSample::step: the world's step and the bag's updates). The first 200 steps settle the contacts and
// are not timed. Prints the time per step, per sphere-step, and the ratio to the FCC crystal's per sphere-step.
// Usage: bench_lattices [--threads N] [--spheres S] [--steps K] [--edge-spheres E]
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/machine.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/geometry/grain_template.h"

using namespace granulab;

namespace {

struct Case {
  const char* name;
  LatticeType lattice;
  Indices axis;
};

}  // namespace

int main(int argc, char** argv) {
  granulab::print_machine();
  double target = 1e5;
  int steps = 1000, edge_spheres = 4;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--threads") omp_set_num_threads(std::atoi(argv[i + 1]));
    else if (a == "--spheres") target = std::atof(argv[i + 1]);
    else if (a == "--steps") steps = std::atoi(argv[i + 1]);
    else if (a == "--edge-spheres") edge_spheres = std::atoi(argv[i + 1]);
  }
  const Case cases[] = {{"fcc [-1 -1 2] (paper)", LatticeType::fcc, {-1, -1, 2}},
                        {"fcc [0 0 1]", LatticeType::fcc, {0, 0, 1}},
                        {"sc [0 0 1]", LatticeType::sc, {0, 0, 1}},
                        {"sc [1 1 0]", LatticeType::sc, {1, 1, 0}},
                        {"bcc [0 0 1]", LatticeType::bcc, {0, 0, 1}},
                        {"bcc [1 1 1]", LatticeType::bcc, {1, 1, 1}},
                        {"hcp [0 0 1] (c)", LatticeType::hcp, {0, 0, 1}},
                        {"hcp [1 0 0] (a1)", LatticeType::hcp, {1, 0, 0}}};
  double fcc_ns = 0;
  std::printf("threads %d, N_e %d, about %.3g spheres, %d timed steps\n", omp_get_max_threads(), edge_spheres, target,
              steps);
  for (const Case& c : cases) {
    CrystalSampleParams p;
    p.lattice = c.lattice, p.axis = c.axis;
    p.grain.shape = grain_shape(c.lattice);
    p.grain.edge_spheres = edge_spheres;
    p.confining_pressure = 30e3;
    const long per_grain = sphere_count(p.grain);
    // A box of n x n x 2n cells (AR 2), as many grains as the sphere target needs.
    const int n = std::max(2, int(std::lround(std::cbrt(target / double(per_grain) / 2))));
    p.grains_x = n, p.layers_y = n, p.rows_z = 2 * n;
    CrystalSample sample(p);
    for (int s = 0; s < 200; ++s) sample.step(0);
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) sample.step(0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::size_t spheres = sample.world().sphere_count();
    const double ns = seconds * 1e9 / (double(spheres) * steps);
    if (c.lattice == LatticeType::fcc && fcc_ns == 0) fcc_ns = ns;
    std::printf("%-22s grains %6zu  spheres/grain %4ld  spheres %8zu  %7.3f ms/step  %6.2f ns/sphere-step  x%.2f of fcc  "
                "contacts %zu\n",
                c.name, sample.world().bodies().size(), per_grain, spheres, 1e3 * seconds / steps, ns, ns / fcc_ns,
                sample.world().contact_stats().contacts);
    std::fflush(stdout);
  }
  return 0;
}
