#include "engine/geometry/grain_template.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace granulab {

double sphere_diameter(const GrainGeometry& g) {
  const double n = g.edge_spheres - 1, c = 1 - g.overlap;
  if (g.shape == Shape::cube) return g.size / (n * c + 1);
  return g.size / ((4 / std::sqrt(3.0)) * n * c + std::sqrt(2.0));
}

namespace {

// Removes points that coincide (shared edges and vertices of adjacent faces), keeping first-seen order.
// Sort-and-sweep along x, so O(n log n) for any clump size.
std::vector<Vec3> unique_points(const std::vector<Vec3>& pts, double tol) {
  std::vector<std::size_t> order(pts.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return pts[a].x() < pts[b].x(); });
  std::vector<bool> dropped(pts.size(), false);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t a = order[k];
    if (dropped[a]) continue;
    for (std::size_t m = k + 1; m < order.size() && pts[order[m]].x() - pts[a].x() <= tol; ++m) {
      const std::size_t b = order[m];
      if (!dropped[b] && (pts[b] - pts[a]).norm() <= tol) dropped[std::max(a, b)] = true;
    }
  }
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!dropped[i]) out.push_back(pts[i]);
  return out;
}

}  // namespace

long sphere_count(const GrainGeometry& g) {
  const long m = g.edge_spheres - 2;
  return g.shape == Shape::cube ? 6 * m * m + 12 * m + 8 : 12 * m * m + 24 * m + 14;
}

GrainTemplate::GrainTemplate(const GrainGeometry& g) : geometry_(g), solid_(Polyhedron::make(g.shape, g.size)) {
  if (g.edge_spheres < 2) throw std::invalid_argument("edge_spheres must be >= 2");
  if (!(g.overlap >= 0 && g.overlap < 1)) throw std::invalid_argument("overlap must be in [0, 1)");
  if (granulab::sphere_count(g) > 65535)  // checked before allocating
    throw std::invalid_argument("edge_spheres too large: a clump holds at most 65535 spheres");
  diameter_ = sphere_diameter(g);
  spacing_ = diameter_ * (1 - g.overlap);

  // Inner polyhedron = outer scaled about the centre so that each face moves in by d/2.
  const double scale = (solid_.inradius() - diameter_ / 2) / solid_.inradius();
  const int n = g.edge_spheres;
  std::vector<Vec3> pts;
  pts.reserve(solid_.faces().size() * n * n);
  for (const Face& f : solid_.faces()) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double ti = double(i) / (n - 1), tj = double(j) / (n - 1);
        pts.push_back(scale * (f.corner + ti * f.edge_a + tj * f.edge_b));
      }
    }
  }
  offsets_ = unique_points(pts, 1e-6 * spacing_);

  const MassProperties mp = solid_.mass_properties();
  volume_ = mp.volume;
  // Cube and RD are centred and have isotropic inertia, so the given frame is already principal;
  // a general shape would be rotated into its principal frame here.
  const Mat3& in = mp.inertia_per_density;
  const double off = std::abs(in(0, 1)) + std::abs(in(0, 2)) + std::abs(in(1, 2));
  if (off > 1e-9 * in.trace() || mp.centroid.norm() > 1e-9 * g.size)
    throw std::logic_error("grain solid is not centred in its principal frame");
  principal_inertia_ = in.diagonal();

  double r = 0;
  for (const Vec3& o : offsets_) r = std::max(r, o.norm());
  bounding_radius_ = r + diameter_ / 2;
}

}  // namespace granulab
