// How large a time step the crystal takes: for each factor dt / t0, a crystal is confined, then held at
// rest (platens fixed, the bag re-detected every membrane interval as in a run) for --rest-steps steps,
// and the energy is followed: kinetic (grains), elastic (sphere contacts), and their sum. A stable step
// lets damping drain the kinetic energy and keeps the total from growing; an unstable one makes both
// grow (exponentially, and the run stops with non-finite numbers).
// Usage: bench_time_step [--factors 0.2,0.3,...] [--edge-spheres N] [--grains X,Z,Y] [--pressure Pa]
//                        [--damping zeta] [--damping-velocity half_step|quarter_step] [--rest-steps S] [--threads T]
// The evidence for the default run.time_step_factor (docs/model.md, "Time step"; bench/README.md).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bench/machine.h"
#include "engine/crystal/confinement.h"
#include "engine/crystal/crystal_sample.h"

using namespace granulab;

namespace {

std::vector<double> numbers(const std::string& list) {
  std::vector<double> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::atof(item.c_str()));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  granulab::print_machine();
  std::vector<double> factors{0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5};
  CrystalSampleParams p;
  p.grain.edge_spheres = 4;
  p.grains_x = 4, p.rows_z = 8, p.layers_y = 3;
  p.confining_pressure = 30e3;
  long rest_steps = 20000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--factors") factors = numbers(v);
    else if (a == "--edge-spheres") p.grain.edge_spheres = std::atoi(v.c_str());
    else if (a == "--grains") {
      const auto g = numbers(v);
      if (g.size() == 3) p.grains_x = int(g[0]), p.rows_z = int(g[1]), p.layers_y = int(g[2]);
    } else if (a == "--pressure") p.confining_pressure = std::atof(v.c_str());
    else if (a == "--damping") p.material.damping = std::atof(v.c_str());
    else if (a == "--damping-velocity")
      p.damping_velocity = v == "quarter_step" ? DampingVelocity::quarter_step : DampingVelocity::half_step;
    else if (a == "--rest-steps") rest_steps = std::atol(v.c_str());
    else if (a == "--threads") omp_set_num_threads(std::atoi(v.c_str()));
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  std::printf("crystal %d x %d x %d, N_e = %d, p0 = %g Pa, damping %g (dashpots at %s), %ld steps at rest after "
              "confinement\n",
              p.grains_x, p.rows_z, p.layers_y, p.grain.edge_spheres, p.confining_pressure, p.material.damping,
              p.damping_velocity == DampingVelocity::quarter_step ? "a quarter step" : "the half step", rest_steps);
  std::printf("%6s %11s %9s %16s %12s %12s %12s %14s %10s\n", "dt/t0", "confinement", "converged", "walls / p0",
              "KE/EE start", "KE/EE max", "KE/EE end", "total drift", "result");
  for (double f : factors) {
    p.time_step_factor = f;
    CrystalSample sample(p);
    World& world = sample.world();
    ConfinementReport c;
    try {
      c = confine(sample);
    } catch (const std::exception&) {
      std::printf("%6.3f %11s\n", f, "BLEW UP while confining");
      continue;
    }
    auto total = [&] { return world.kinetic_energy() + world.elastic_energy(); };
    const double ke0 = sample.kinetic_elastic_ratio(), e0 = total();
    double ke_max = ke0;
    std::string result = "stable";
    try {
      for (long s = 1; s <= rest_steps; ++s) {
        world.step();
        if (s % p.membrane_interval == 0) {
          sample.check_finite();
          sample.update_membrane();
          ke_max = std::max(ke_max, sample.kinetic_elastic_ratio());
        }
      }
    } catch (const std::exception&) {
      result = "BLEW UP";
    }
    const double drift = (total() - e0) / e0;
    if (result == "stable" && (drift > 1e-3 || ke_max > 10 * std::max(ke0, 1e-4))) result = "growing";
    std::printf("%6.3f %11llu %9s %7.4f %7.4f %12.3g %12.3g %12.3g %14.3g %10s\n", f, (unsigned long long)c.steps,
                c.converged ? "yes" : "no", c.stress_top / p.confining_pressure, c.stress_bottom / p.confining_pressure,
                ke0, ke_max, sample.kinetic_elastic_ratio(), drift, result.c_str());
    std::fflush(stdout);
  }
  return 0;
}
