#include "engine/geometry/polyhedron.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace granulab {

std::string to_string(Shape shape) { return shape == Shape::cube ? "cube" : "rhombic_dodecahedron"; }

namespace {

Face make_face(const Vec3& corner, const Vec3& b, const Vec3& c) {
  Face f{corner, b - corner, c - corner, Vec3::Zero()};
  f.normal = f.edge_a.cross(f.edge_b).normalized();
  if (f.normal.dot(corner) < 0) {  // keep edge_a x edge_b outward
    std::swap(f.edge_a, f.edge_b);
    f.normal = -f.normal;
  }
  return f;
}

std::vector<Face> cube_faces(double l) {
  std::vector<Face> faces;
  const double h = l / 2;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    for (double sk : {-1.0, 1.0}) {
      Vec3 corner = Vec3::Zero(), b = Vec3::Zero(), c = Vec3::Zero();
      corner[k] = b[k] = c[k] = sk * h;
      corner[i] = -h, corner[j] = -h;
      b[i] = h, b[j] = -h;
      c[i] = -h, c[j] = h;
      faces.push_back(make_face(corner, b, c));
    }
  }
  return faces;
}

// Rhombic dodecahedron of cubic cell a: face normal (si e_i + sj e_j)/sqrt2, with 4-valent vertices
// si a/2 e_i, sj a/2 e_j and 3-valent vertices (si e_i + sj e_j +- e_k) a/4.
std::vector<Face> rhombic_dodecahedron_faces(double a) {
  std::vector<Face> faces;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const int k = 3 - i - j;
      for (double si : {-1.0, 1.0}) {
        for (double sj : {-1.0, 1.0}) {
          Vec3 corner = Vec3::Zero();
          corner[i] = si * a / 2;
          Vec3 mid = Vec3::Zero();
          mid[i] = si * a / 4, mid[j] = sj * a / 4;
          Vec3 b = mid, c = mid;
          b[k] = a / 4, c[k] = -a / 4;
          faces.push_back(make_face(corner, b, c));
        }
      }
    }
  }
  return faces;
}

}  // namespace

Polyhedron Polyhedron::make(Shape shape, double size) {
  if (!(size > 0)) throw std::invalid_argument("polyhedron size must be > 0");
  Polyhedron p;
  p.shape_ = shape;
  p.size_ = size;
  p.faces_ = shape == Shape::cube ? cube_faces(size) : rhombic_dodecahedron_faces(size);
  p.inradius_ = p.faces_.front().corner.dot(p.faces_.front().normal);
  return p;
}

double Polyhedron::face_area() const {
  const Face& f = faces_.front();
  return f.edge_a.cross(f.edge_b).norm();
}

double Polyhedron::circumradius() const {
  double r = 0;
  for (const Face& f : faces_) {
    for (const Vec3& v :
         {f.corner, Vec3(f.corner + f.edge_a), Vec3(f.corner + f.edge_b), Vec3(f.corner + f.edge_a + f.edge_b)}) {
      r = std::max(r, v.norm());
    }
  }
  return r;
}

bool Polyhedron::contains(const Vec3& p, double tol) const {
  return std::all_of(faces_.begin(), faces_.end(), [&](const Face& f) { return (p - f.corner).dot(f.normal) <= tol; });
}

MassProperties Polyhedron::mass_properties() const {
  // Each face is split into two triangles; each triangle and the origin form a tetrahedron whose
  // second moment is  |det|/120 * (sum v v^T + (sum v)(sum v)^T)  (vertices v1..v3, apex at origin).
  MassProperties m;
  Mat3 second_moment = Mat3::Zero();
  Vec3 first_moment = Vec3::Zero();
  for (const Face& f : faces_) {
    const Vec3 a = f.corner, b = f.corner + f.edge_a, c = f.corner + f.edge_b, d = f.corner + f.edge_a + f.edge_b;
    for (const auto& tri : {std::array<Vec3, 3>{a, b, d}, std::array<Vec3, 3>{a, d, c}}) {
      Mat3 v;
      v << tri[0], tri[1], tri[2];
      const double det = std::abs(v.determinant());
      const Vec3 sum = tri[0] + tri[1] + tri[2];
      m.volume += det / 6;
      first_moment += det / 6 * sum / 4;
      second_moment += det / 120 * (v * v.transpose() + sum * sum.transpose());
    }
  }
  m.centroid = first_moment / m.volume;
  const Mat3 inertia_origin = second_moment.trace() * Mat3::Identity() - second_moment;
  const Vec3& c = m.centroid;
  m.inertia_per_density = inertia_origin - m.volume * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  return m;
}

}  // namespace granulab
