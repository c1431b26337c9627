#include "engine/geometry/polyhedron.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace granulab {

std::string to_string(Shape shape) {
  switch (shape) {
    case Shape::cube: return "cube";
    case Shape::rhombic_dodecahedron: return "rhombic_dodecahedron";
    case Shape::truncated_octahedron: return "truncated_octahedron";
    case Shape::trapezo_rhombic_dodecahedron: return "trapezo_rhombic_dodecahedron";
  }
  return "cube";
}

bool shape_from_string(const std::string& name, Shape& shape) {
  for (Shape s : {Shape::cube, Shape::rhombic_dodecahedron, Shape::truncated_octahedron,
                  Shape::trapezo_rhombic_dodecahedron})
    if (to_string(s) == name) {
      shape = s;
      return true;
    }
  return false;
}

double Face::area() const {
  if (parallelogram) return edge_a.cross(edge_b).norm();
  Vec3 sum = Vec3::Zero();  // fan from vertex 0
  for (std::size_t k = 1; k + 1 < vertices.size(); ++k)
    sum += (vertices[k] - vertices[0]).cross(vertices[k + 1] - vertices[0]);
  return sum.dot(normal) / 2;
}

Vec3 Face::centre() const {
  Vec3 c = Vec3::Zero();
  for (const Vec3& v : vertices) c += v;
  return c / double(vertices.size());
}

Vec3 Face::centroid() const {
  Vec3 sum = Vec3::Zero();
  double total = 0;
  for (std::size_t k = 1; k + 1 < vertices.size(); ++k) {  // fan from vertex 0: triangles' centroids by area
    const double a = (vertices[k] - vertices[0]).cross(vertices[k + 1] - vertices[0]).dot(normal);
    sum += a * (vertices[0] + vertices[k] + vertices[k + 1]) / 3;
    total += a;
  }
  return sum / total;
}

namespace {

Face make_face(const Vec3& corner, const Vec3& b, const Vec3& c) {
  Face f{corner, b - corner, c - corner, Vec3::Zero()};
  f.normal = f.edge_a.cross(f.edge_b).normalized();
  if (f.normal.dot(corner) < 0) {  // keep edge_a x edge_b outward
    std::swap(f.edge_a, f.edge_b);
    f.normal = -f.normal;
  }
  f.distance = f.corner.dot(f.normal);
  f.vertices = {f.corner, Vec3(f.corner + f.edge_a), Vec3(f.corner + f.edge_a + f.edge_b), Vec3(f.corner + f.edge_b)};
  f.parallelogram = true;
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

// The Voronoi cells as half-spaces: one plane halfway to each neighbour whose bisector bounds the cell.
// BCC (cell a): 8 nearest neighbours at (+-1, +-1, +-1) a/2 (hexagons at sqrt3 a/4), 6 next ones at a e_k
// (squares at a/2).
void truncated_octahedron_planes(double a, std::vector<Vec3>& n, std::vector<double>& h) {
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) n.push_back(Vec3(sx, sy, sz).normalized()), h.push_back(std::sqrt(3.0) * a / 4);
  for (int k = 0; k < 3; ++k)
    for (double s : {-1.0, 1.0}) {
      Vec3 e = Vec3::Zero();
      e[k] = s;
      n.push_back(e), h.push_back(a / 2);
    }
}

// Ideal HCP, nearest-neighbour distance D, c = sqrt(8/3) D along z, the site on an A layer: 6 neighbours
// in its layer at D (cos 60k, sin 60k, 0) and 3 in each layer above and below, on the B sites
// (D/2, D/(2 sqrt3)), (-D/2, D/(2 sqrt3)), (0, -D/sqrt3) at z = +-c/2. All 12 at D: every face at D/2.
void trapezo_rhombic_dodecahedron_planes(double a, std::vector<Vec3>& n, std::vector<double>& h) {
  const double d = a / std::sqrt(2.0), c = std::sqrt(8.0 / 3.0) * d;
  std::vector<Vec3> neighbours;
  for (int k = 0; k < 6; ++k) neighbours.push_back(d * Vec3(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0));
  const Vec3 b_sites[3] = {Vec3(d / 2, d / (2 * std::sqrt(3.0)), 0), Vec3(-d / 2, d / (2 * std::sqrt(3.0)), 0),
                           Vec3(0, -d / std::sqrt(3.0), 0)};
  for (double z : {c / 2, -c / 2})
    for (const Vec3& b : b_sites) neighbours.push_back(b + Vec3(0, 0, z));
  for (const Vec3& t : neighbours) n.push_back(t.normalized()), h.push_back(t.norm() / 2);
}

}  // namespace

Polyhedron Polyhedron::make(Shape shape, double size) {
  if (!(size > 0)) throw std::invalid_argument("polyhedron size must be > 0");
  if (shape == Shape::cube || shape == Shape::rhombic_dodecahedron) {
    Polyhedron p;
    p.shape_ = shape;
    p.size_ = size;
    p.faces_ = shape == Shape::cube ? cube_faces(size) : rhombic_dodecahedron_faces(size);
    p.finish();
    p.inradius_ = p.faces_.front().corner.dot(p.faces_.front().normal);  // every face's, as the clump uses it
    return p;
  }
  std::vector<Vec3> n;
  std::vector<double> h;
  if (shape == Shape::truncated_octahedron)
    truncated_octahedron_planes(size, n, h);
  else
    trapezo_rhombic_dodecahedron_planes(size, n, h);
  return from_planes(shape, size, n, h);
}

Polyhedron Polyhedron::from_planes(Shape shape, double size, const std::vector<Vec3>& normals,
                                   const std::vector<double>& distances) {
  if (normals.size() != distances.size() || normals.size() < 4)
    throw std::invalid_argument("a polyhedron needs at least four planes");
  double scale = 0;
  for (double h : distances) {
    if (!(h > 0)) throw std::invalid_argument("every face plane must lie beyond the centre");
    scale = std::max(scale, h);
  }
  const double tol = 1e-11 * scale;
  // Vertices: every point where three planes meet that no plane cuts off. O(planes^4) once per grain shape
  // (14 planes: 364 triples).
  std::vector<Vec3> vertices;
  const std::size_t m = normals.size();
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      for (std::size_t k = j + 1; k < m; ++k) {
        const Vec3 jk = normals[j].cross(normals[k]), ki = normals[k].cross(normals[i]), ij = normals[i].cross(normals[j]);
        const double det = normals[i].dot(jk);
        if (std::abs(det) < 1e-9) continue;
        const Vec3 v = (distances[i] * jk + distances[j] * ki + distances[k] * ij) / det;
        bool inside = true;
        for (std::size_t q = 0; q < m && inside; ++q) inside = normals[q].dot(v) <= distances[q] + tol;
        if (!inside) continue;
        if (std::none_of(vertices.begin(), vertices.end(), [&](const Vec3& w) { return (w - v).norm() <= tol; }))
          vertices.push_back(v);
      }
  Polyhedron p;
  p.shape_ = shape;
  p.size_ = size;
  for (std::size_t q = 0; q < m; ++q) {
    std::vector<Vec3> on;
    for (const Vec3& v : vertices)
      if (std::abs(normals[q].dot(v) - distances[q]) <= tol) on.push_back(v);
    if (on.size() < 3) continue;
    Face f;
    f.normal = normals[q].normalized();
    f.distance = distances[q];
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : on) c += v;
    c /= double(on.size());
    const Vec3 u = (on.front() - c).normalized(), w = f.normal.cross(u);
    std::sort(on.begin(), on.end(), [&](const Vec3& x, const Vec3& y) {
      return std::atan2((x - c).dot(w), (x - c).dot(u)) < std::atan2((y - c).dot(w), (y - c).dot(u));
    });
    f.vertices = on;
    f.corner = on.front();
    f.edge_a = on[1] - on[0];
    f.edge_b = on.back() - on[0];
    f.parallelogram = on.size() == 4 && (on[0] + on[2] - on[1] - on[3]).norm() <= tol;
    p.faces_.push_back(f);
  }
  if (p.faces_.size() < 4) throw std::invalid_argument("the planes do not bound a solid");
  p.finish();
  return p;
}

void Polyhedron::finish() {
  inradius_ = faces_.front().distance;
  for (const Face& f : faces_) inradius_ = std::min(inradius_, f.distance);
  vertices_.clear();
  const double tol = 1e-11 * size_;
  for (const Face& f : faces_)
    for (const Vec3& v : f.vertices)
      if (std::none_of(vertices_.begin(), vertices_.end(), [&](const Vec3& w) { return (w - v).norm() <= tol; }))
        vertices_.push_back(v);
  reference_ = 0;
  for (std::size_t k = 0; k < faces_.size(); ++k) {
    const Face& f = faces_[k];
    const bool wanted = shape_ == Shape::truncated_octahedron           ? f.vertices.size() == 6
                        : shape_ == Shape::trapezo_rhombic_dodecahedron ? f.parallelogram
                                                                        : true;
    if (wanted) {
      reference_ = k;
      break;
    }
  }
}

Polyhedron Polyhedron::recessed(double depth) const {
  std::vector<Vec3> n;
  std::vector<double> h;
  for (const Face& f : faces_) n.push_back(f.normal), h.push_back(f.distance - depth);
  for (double d : h)
    if (!(d > 0)) throw std::invalid_argument("the recess reaches the centre");
  Polyhedron p = from_planes(shape_, size_, n, h);
  if (p.faces_.size() != faces_.size()) throw std::invalid_argument("a face vanishes when recessed");
  for (std::size_t k = 0; k < faces_.size(); ++k)
    if (p.faces_[k].vertices.size() != faces_[k].vertices.size())
      throw std::invalid_argument("a face loses a vertex when recessed");
  return p;
}

double Polyhedron::circumradius() const {
  double r = 0;
  for (const Vec3& v : vertices_) r = std::max(r, v.norm());
  return r;
}

bool Polyhedron::contains(const Vec3& p, double tol) const {
  return std::all_of(faces_.begin(), faces_.end(), [&](const Face& f) { return (p - f.corner).dot(f.normal) <= tol; });
}

MassProperties Polyhedron::mass_properties() const {
  // Each face is split into triangles (a parallelogram into two, any other polygon into a fan from its first
  // vertex); each triangle and the origin form a tetrahedron whose second moment is
  // |det|/120 * (sum v v^T + (sum v)(sum v)^T)  (vertices v1..v3, apex at origin).
  MassProperties m;
  Mat3 second_moment = Mat3::Zero();
  Vec3 first_moment = Vec3::Zero();
  const auto add = [&](const std::array<Vec3, 3>& tri) {
    Mat3 v;
    v << tri[0], tri[1], tri[2];
    const double det = std::abs(v.determinant());
    const Vec3 sum = tri[0] + tri[1] + tri[2];
    m.volume += det / 6;
    first_moment += det / 6 * sum / 4;
    second_moment += det / 120 * (v * v.transpose() + sum * sum.transpose());
  };
  for (const Face& f : faces_) {
    if (f.parallelogram) {
      const Vec3 a = f.corner, b = f.corner + f.edge_a, c = f.corner + f.edge_b, d = f.corner + f.edge_a + f.edge_b;
      add({a, b, d});
      add({a, d, c});
      continue;
    }
    for (std::size_t k = 1; k + 1 < f.vertices.size(); ++k) add({f.vertices[0], f.vertices[k], f.vertices[k + 1]});
  }
  m.centroid = first_moment / m.volume;
  const Mat3 inertia_origin = second_moment.trace() * Mat3::Identity() - second_moment;
  const Vec3& c = m.centroid;
  m.inertia_per_density = inertia_origin - m.volume * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  return m;
}

}  // namespace granulab
