#include "engine/analysis/snapshot_layers.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace granulab {

double neighbour_distance(const GrainSnapshot& s) {
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.id.size(); ++i) index[value(s.id[i])] = i;
  std::vector<double> d;
  for (const GrainPair& p : s.interfaces) {
    const auto a = index.find(value(p.a)), b = index.find(value(p.b));
    if (a == index.end() || b == index.end()) continue;
    d.push_back(
        ((s.position[a->second] - s.displacement[a->second]) - (s.position[b->second] - s.displacement[b->second]))
            .norm());
  }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

SnapshotLayers snapshot_layers(const GrainSnapshot& s) {
  SnapshotLayers out;
  const std::size_t n = s.id.size();
  double neighbour = neighbour_distance(s);
  if (!(neighbour > 0)) neighbour = 1;
  const double spacing = s.layer_spacing > 0 ? s.layer_spacing : neighbour * std::sqrt(2.0 / 3.0);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  const auto y = [&](std::size_t i) { return s.position[i].y() - s.displacement[i].y(); };
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return y(i) < y(j); });
  out.layer.resize(n);
  int layer = -1;
  double last = -1e300;
  for (std::size_t i : order) {
    if (y(i) - last > 0.1 * spacing) ++layer;
    last = y(i);
    out.layer[i] = layer;
  }
  out.count = layer + 1;
  return out;
}

}  // namespace granulab
