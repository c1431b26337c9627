// What a crystal snapshot's analyses cost (engine/crystal/crystal_snapshot.h): the reference crystal at full size
// (864 grains, 841,536 spheres), half of it shifted along a {111} plane so that a band slides, then crystal_snapshot
// (displacements, local strains and D^2_min, misorientations, interface sliding, slip bands) timed as the best of
// `repeats` calls, against one time step of the same sample on this machine's threads. With a contact law named
// (contact.normal, contact.tangential; cohesive laws at gamma = 0.1 J/m^2), the step is that law's: each law's cost
// per step on the dense crystal, every candidate touching (docs/model.md, "Interface laws").
//
//   build/bench/bench_snapshot [repeats] [edge_spheres] [normal] [tangential]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "bench/machine.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/crystal/crystal_snapshot.h"

using namespace granulab;

int main(int argc, char** argv) {
  granulab::print_machine();
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  CrystalSampleParams p;  // the paper's crystal: 8 x 18 x 6, N_e = 10
  if (argc > 2) p.grain.edge_spheres = std::atoi(argv[2]);
  if (argc > 3 && !normal_model_from_string(argv[3], p.material.contact.normal)) return std::fprintf(stderr, "bad law\n"), 2;
  if (argc > 4 && !tangential_model_from_string(argv[4], p.material.contact.tangential))
    return std::fprintf(stderr, "bad tangential law\n"), 2;
  p.material.contact.surface_energy = 0.1;  // read by dmt and jkr only
  p.confining_pressure = 60e3;
  CrystalSample sample(p);
  World& world = sample.world();
  world.compute_forces();
  CrystalReference ref;
  ref.take(sample);
  // The upper half (along the lab z, which crosses the inclined {111} planes) moves by a tenth of a grain along x.
  Bodies& b = world.bodies();
  for (std::size_t i = 0; i < b.size(); ++i)
    if (b.position[i].z() > 0) b.position[i].x() += 0.1 * p.grain.size;
  using clock = std::chrono::steady_clock;
  double best = 1e300;
  std::size_t bands = 0;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = clock::now();
    const GrainSnapshot s = crystal_snapshot(sample, ref, 0.0);
    best = std::min(best, std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    bands = s.slip_bands.size();
  }
  for (std::size_t i = 0; i < b.size(); ++i)
    if (b.position[i].z() > 0) b.position[i].x() -= 0.1 * p.grain.size;
  world.compute_forces();
  for (int s = 0; s < 20; ++s) world.step();
  const auto t0 = clock::now();
  const int steps = 100;
  for (int s = 0; s < steps; ++s) world.step();
  const double step_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count() / steps;
  std::printf("%s/%s: ", to_string(p.material.contact.normal).c_str(), to_string(p.material.contact.tangential).c_str());
  std::printf("%zu grains, %zu spheres: snapshot %.1f ms (%zu slip bands), one step %.2f ms: a snapshot costs %.2f steps\n",
              b.size(), world.sphere_count(), best, bands, step_ms, best / step_ms);
}
