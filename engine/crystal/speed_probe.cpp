#include "engine/crystal/speed_probe.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include "engine/crystal/crystal_sample.h"

namespace granulab {

SpeedProbeResult crystal_speed_probe(double seconds) {
  CrystalSampleParams p;
  p.grain.edge_spheres = 4;
  p.grains_x = 6, p.rows_z = 12, p.layers_y = 3;
  p.confining_pressure = 30e3;
  CrystalSample sample(p);
  World& world = sample.world();
  const double spheres = double(world.sphere_count());
  using clock = std::chrono::steady_clock;
  // A first interval unmeasured: the neighbour list's first build and the caches' first touch are not a
  // run's steady cost.
  for (int s = 0; s < p.membrane_interval; ++s) world.step();
  sample.update_membrane();
  // The median interval: a machine shared with others (a VM's neighbours, a page cache flush) slows some
  // intervals by 2x; a job of hours averages over such spells, a fraction of a second does not.
  SpeedProbeResult out;
  std::vector<double> interval_speeds;
  const auto start = clock::now();
  do {
    const auto from = clock::now();
    for (int s = 0; s < p.membrane_interval; ++s) world.step();
    sample.update_membrane();
    interval_speeds.push_back(spheres * p.membrane_interval / std::chrono::duration<double>(clock::now() - from).count());
    out.steps += p.membrane_interval;
    out.seconds = std::chrono::duration<double>(clock::now() - start).count();
  } while (out.seconds < seconds);
  std::nth_element(interval_speeds.begin(), interval_speeds.begin() + interval_speeds.size() / 2, interval_speeds.end());
  out.sphere_steps_per_second = interval_speeds[interval_speeds.size() / 2];
  return out;
}

}  // namespace granulab
