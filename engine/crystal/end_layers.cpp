#include "engine/crystal/end_layers.h"

#include <algorithm>
#include <stdexcept>

namespace granulab {

std::vector<double> site_heights(const std::vector<LatticeSite>& sites, double size) {
  std::vector<double> heights;
  for (const LatticeSite& s : sites) heights.push_back(s.position.z());
  std::sort(heights.begin(), heights.end());
  const double same = 1e-9 * size;
  heights.erase(std::unique(heights.begin(), heights.end(), [&](double a, double b) { return b - a < same; }),
                heights.end());
  return heights;
}

EndLayers grip_end_layers(CrystalSample& sample, double depth) {
  EndLayers out;
  World& world = sample.world();
  Bodies& bodies = world.bodies();
  // The grips: the sites within depth of the lowest and the highest of their distinct heights (exact, as built).
  const std::vector<LatticeSite>& sites = sample.lattice().sites;
  const std::vector<double> heights = site_heights(sites, sample.params().grain.size);
  const double same = 1e-9 * sample.params().grain.size, reach = depth + same;
  for (double h : heights) {
    out.layers[0] += h < heights.front() + reach;
    out.layers[1] += h > heights.back() - reach;
  }
  if (heights.size() < 3 || out.layers[0] + out.layers[1] >= int(heights.size()))  // the specs refuse it
    throw std::invalid_argument("the crystal has no layer along z between its two grips");
  out.spacing = heights.back() - heights.front();
  for (std::size_t k = 1; k < heights.size(); ++k) out.spacing = std::min(out.spacing, heights[k] - heights[k - 1]);
  for (std::size_t k = 0; k < sites.size(); ++k) {
    const double z = sites[k].position.z();
    const int layer = z < heights.front() + reach ? 0 : z > heights.back() - reach ? 1 : -1;
    if (layer < 0) continue;
    out.layer[layer].push_back(BodyId(k));
    bodies.motion[k] = Motion::prescribed;
    bodies.velocity[k].setZero();
    bodies.angular_velocity[k].setZero();
    bodies.angular_momentum[k].setZero();
  }
  // The platens step back two grain sizes: the end layers carry the load from now on.
  std::vector<Wall>& walls = world.walls();
  walls[sample.top_wall()].point += 2 * sample.params().grain.size * Vec3::UnitZ();
  walls[sample.bottom_wall()].point -= 2 * sample.params().grain.size * Vec3::UnitZ();
  for (Wall& w : walls) w.velocity.setZero();
  world.compute_forces();
  return out;
}

double mean_coordinate(const std::vector<BodyId>& bodies, const std::vector<Vec3>& x, int axis) {
  double s = 0;
  for (BodyId b : bodies) s += x[b][axis];
  return bodies.empty() ? 0 : s / double(bodies.size());
}

std::vector<double> layer_heights(const std::vector<Vec3>& x, double spacing) {
  std::vector<double> z, out;
  for (const Vec3& p : x) z.push_back(p.z());
  std::sort(z.begin(), z.end());
  for (std::size_t k = 0, first = 0; k < z.size(); ++k)
    if (k + 1 == z.size() || z[k + 1] - z[k] > spacing / 4) {
      double sum = 0;
      for (std::size_t j = first; j <= k; ++j) sum += z[j];
      out.push_back(sum / double(k + 1 - first));
      first = k + 1;
    }
  return out;
}

}  // namespace granulab
