#include "engine/geometry/grain_template.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace granulab {

double sphere_diameter(const GrainGeometry& g) {
  const double n = g.edge_spheres - 1, c = 1 - g.overlap;
  switch (g.shape) {
    case Shape::cube: return g.size / (n * c + 1);
    // The trapezo-rhombic dodecahedron's rhombi are the rhombic dodecahedron's (same a, same inner scale).
    case Shape::rhombic_dodecahedron:
    case Shape::trapezo_rhombic_dodecahedron: return g.size / ((4 / std::sqrt(3.0)) * n * c + std::sqrt(2.0));
    // Hexagon-hexagon edges of the inner truncated octahedron: sqrt2 (a/4 - (1 - sqrt3/2) d) = n s.
    case Shape::truncated_octahedron:
      return std::sqrt(2.0) * g.size / 4 / (n * c + std::sqrt(2.0) * (1 - std::sqrt(3.0) / 2));
  }
  return 0;
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

// The cube and the RD keep the clump they always had (N_e x N_e grids of every parallelogram face, bit for bit).
bool legacy_clump(Shape shape) { return shape == Shape::cube || shape == Shape::rhombic_dodecahedron; }

long segments(double length, double spacing) { return std::max(1L, std::lround(length / spacing)); }

// The clump on a polyhedron whose faces are any convex polygons (docs/model.md, "Grains"): a sphere on every
// vertex of the inner polyhedron, every inner edge of length L cut into round(L/s) equal segments, and then
//  - a quadrilateral: rows parallel to its longest edge through the division points of the two edges beside
//    it (a parallelogram's grid; a trapezoid's rows), each row cut into round(length/s) segments;
//  - any other polygon: the triangular lattice of spacing s centred on the face, rows parallel to its
//    longest edge, keeping the nodes at least half a row spacing inside every edge of the face and of the face
//    turned half a turn about its centre. The lattice is symmetric under that half turn, and the face the
//    neighbour across it has (recessed unequally: the truncated octahedron's hexagons) is this one turned, so
//    the two grains' nodes coincide one for one.
std::vector<Vec3> polygon_clump(const Polyhedron& inner, double s) {
  std::vector<Vec3> pts;
  for (const Face& f : inner.faces()) {
    const std::vector<Vec3>& v = f.vertices;
    const std::size_t n = v.size();
    std::size_t base = 0;  // the longest edge (the first of equal ones)
    for (std::size_t i = 1; i < n; ++i)
      if ((v[(i + 1) % n] - v[i]).norm() > (1 + 1e-9) * (v[(base + 1) % n] - v[base]).norm()) base = i;
    if (n == 4) {
      const Vec3 &p0 = v[base], &p1 = v[(base + 1) % 4], &p2 = v[(base + 2) % 4], &p3 = v[(base + 3) % 4];
      // Both legs cut alike (equal legs here: squares, rhombi, the TRD's isosceles trapezoids), from their mean so
      // that round-off cannot split them at a half.
      const long rows = segments(0.5 * ((p3 - p0).norm() + (p2 - p1).norm()), s);
      for (long k = 0; k <= rows; ++k) {
        const double t = double(k) / rows;
        const Vec3 left = p0 + t * (p3 - p0), right = p1 + t * (p2 - p1);
        const long m = segments((right - left).norm(), s);
        for (long j = 0; j <= m; ++j) pts.push_back(left + (double(j) / m) * (right - left));
      }
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 &a = v[i], &b = v[(i + 1) % n];
      const long m = segments((b - a).norm(), s);
      for (long j = 0; j < m; ++j) pts.push_back(a + (double(j) / m) * (b - a));
    }
    const Vec3 c = f.centre(), u = (v[(base + 1) % n] - v[base]).normalized(), w = f.normal.cross(u);
    const double row = s * std::sqrt(3.0) / 2;
    double reach = 0;
    for (const Vec3& p : v) reach = std::max(reach, (p - c).norm());
    const long kmax = long(std::ceil(reach / row)) + 1, jmax = long(std::ceil(reach / s)) + kmax + 1;
    for (long k = -kmax; k <= kmax; ++k)
      for (long j = -jmax; j <= jmax; ++j) {
        const Vec3 p = c + (double(j) + 0.5 * double(k)) * s * u + double(k) * row * w;
        // Inside the face and inside its half-turn about its centre: the face the neighbour across it sees
        // (the truncated octahedron's hexagon turned half a turn swaps its long and short edges), so that both
        // grains keep the same nodes and every node has its partner across the face.
        bool inside = true;
        for (std::size_t i = 0; i < n && inside; ++i) {
          const Vec3 inward = f.normal.cross(v[(i + 1) % n] - v[i]).normalized();
          inside = (p - v[i]).dot(inward) >= row / 2 && ((2 * c - v[i]) - p).dot(inward) >= row / 2;
        }
        if (inside) pts.push_back(p);
      }
  }
  return pts;
}

}  // namespace

long sphere_count(const GrainGeometry& g) {
  const long m = g.edge_spheres - 2;
  if (g.shape == Shape::cube) return 6 * m * m + 12 * m + 8;
  if (g.shape == Shape::rhombic_dodecahedron) return 12 * m * m + 24 * m + 14;
  try {  // no closed form: the clump is built (a few milliseconds at most, N_e <= 40)
    return long(GrainTemplate(g).sphere_count());
  } catch (const std::exception&) {
    return 0;  // parameters the template refuses; its own check names them
  }
}

GrainTemplate::GrainTemplate(const GrainGeometry& g) : geometry_(g), solid_(Polyhedron::make(g.shape, g.size)) {
  if (g.edge_spheres < 2) throw std::invalid_argument("edge_spheres must be >= 2");
  if (!(g.overlap >= 0 && g.overlap < 1)) throw std::invalid_argument("overlap must be in [0, 1)");
  if (legacy_clump(g.shape) && granulab::sphere_count(g) > 65535)  // checked before allocating
    throw std::invalid_argument("edge_spheres too large: a clump holds at most 65535 spheres");
  diameter_ = sphere_diameter(g);
  spacing_ = diameter_ * (1 - g.overlap);
  if (legacy_clump(g.shape)) {
    build_parallelogram_clump();
  } else {
    Polyhedron inner;
    try {
      inner = solid_.recessed(diameter_ / 2);
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("edge_spheres " + std::to_string(g.edge_spheres) + " is too few for a " +
                                  to_string(g.shape) + " at overlap " + std::to_string(g.overlap) +
                                  ": its spheres would be larger than its smallest faces (raise edge_spheres)");
    }
    offsets_ = unique_points(polygon_clump(inner, spacing_), 1e-6 * spacing_);
    if (offsets_.size() > 65535)
      throw std::invalid_argument("edge_spheres too large: a clump holds at most 65535 spheres");
    const Face& ref = inner.reference_face();
    spheres_per_face_ = 0;
    for (const Vec3& o : offsets_)
      if (std::abs(o.dot(ref.normal) - ref.distance) <= 1e-6 * spacing_) ++spheres_per_face_;
  }
  finish();
}

void GrainTemplate::build_parallelogram_clump() {
  const GrainGeometry& g = geometry_;
  spheres_per_face_ = g.edge_spheres * g.edge_spheres;

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
}

void GrainTemplate::finish() {
  const GrainGeometry& g = geometry_;
  const MassProperties mp = solid_.mass_properties();
  volume_ = mp.volume;
  // Every grain is centred in its crystal frame, which is principal: the cube, the rhombic dodecahedron and the
  // truncated octahedron have isotropic inertia, the trapezo-rhombic dodecahedron's is symmetric about its c
  // axis (z); a general shape would be rotated into its principal frame here.
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
