#include "engine/crystal/lattice_type.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granulab {

std::string to_string(LatticeType lattice) {
  switch (lattice) {
    case LatticeType::fcc: return "fcc";
    case LatticeType::sc: return "sc";
    case LatticeType::bcc: return "bcc";
    case LatticeType::hcp: return "hcp";
  }
  return "fcc";
}

bool lattice_from_string(const std::string& name, LatticeType& lattice) {
  for (LatticeType l : {LatticeType::fcc, LatticeType::sc, LatticeType::bcc, LatticeType::hcp})
    if (to_string(l) == name) {
      lattice = l;
      return true;
    }
  return false;
}

Shape grain_shape(LatticeType lattice) {
  switch (lattice) {
    case LatticeType::fcc: return Shape::rhombic_dodecahedron;
    case LatticeType::sc: return Shape::cube;
    case LatticeType::bcc: return Shape::truncated_octahedron;
    case LatticeType::hcp: return Shape::trapezo_rhombic_dodecahedron;
  }
  return Shape::rhombic_dodecahedron;
}

namespace {

// HCP's hexagonal axes for cubic cell a: a1 = D x, a2 = D (-1/2, sqrt3/2, 0), c = sqrt(8/3) D z, D = a / sqrt2.
Mat3 hexagonal_axes(double a) {
  const double d = a / std::sqrt(2.0);
  Mat3 m;
  m.col(0) = Vec3(d, 0, 0);
  m.col(1) = Vec3(-d / 2, d * std::sqrt(3.0) / 2, 0);
  m.col(2) = Vec3(0, 0, std::sqrt(8.0 / 3.0) * d);
  return m;
}

}  // namespace

LatticeCell lattice_cell(LatticeType lattice, double a) {
  LatticeCell c;
  switch (lattice) {
    case LatticeType::sc: c.primitive = a * Mat3::Identity(); break;
    case LatticeType::fcc: c.primitive << 0, a / 2, a / 2, a / 2, 0, a / 2, a / 2, a / 2, 0; break;
    case LatticeType::bcc: c.primitive << -a / 2, a / 2, a / 2, a / 2, -a / 2, a / 2, a / 2, a / 2, -a / 2; break;
    case LatticeType::hcp: c.primitive = hexagonal_axes(a); break;
  }
  c.basis = {Vec3::Zero()};
  c.basis_turn = {Quat::Identity()};
  if (lattice == LatticeType::hcp) {
    // The B site at (2/3, 1/3, 1/2) of the hexagonal cell; its cell is the A cell turned half a turn about c.
    c.basis.push_back(c.primitive * Vec3(2.0 / 3, 1.0 / 3, 0.5));
    c.basis_turn.push_back(Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitZ())));
  }
  return c;
}

Vec3 direction_vector(LatticeType lattice, const Indices& uvw, double a) {
  const Vec3 n(uvw[0], uvw[1], uvw[2]);
  return lattice == LatticeType::hcp ? Vec3(hexagonal_axes(a) * n) : Vec3(a * n);
}

Indices default_axis(LatticeType lattice) { return lattice == LatticeType::fcc ? Indices{-1, -1, 2} : Indices{0, 0, 1}; }

std::string close_packed_planes(LatticeType lattice) {
  switch (lattice) {
    case LatticeType::fcc: return "{111}";
    case LatticeType::sc: return "{100}";
    case LatticeType::bcc: return "{110}";
    case LatticeType::hcp: return "(0001)";
  }
  return "{111}";
}

Vec3 plane_normal(LatticeType lattice, const Indices& plane) {
  const Vec3 h(plane[0], plane[1], plane[2]);
  // The reciprocal lattice of the cubic cell is cubic; HCP's planes are of a1, a2, c.
  if (lattice != LatticeType::hcp) return h.normalized();
  const Mat3 axes = lattice_cell(LatticeType::hcp, 1).primitive;
  return (axes.inverse().transpose() * h).normalized();
}

bool direction_indices(LatticeType lattice, const Vec3& v, int max_index, Indices& out) {
  const Vec3 c = lattice == LatticeType::hcp ? Vec3(lattice_cell(LatticeType::hcp, 1).primitive.inverse() * v) : v;
  double smallest = 1e300;
  for (int k = 0; k < 3; ++k)
    if (std::abs(c[k]) > 1e-9 * c.norm()) smallest = std::min(smallest, std::abs(c[k]));
  if (smallest > 1e299) return false;
  for (int scale = 1; scale <= max_index; ++scale) {
    const Vec3 h = c * (scale / smallest);
    bool whole = h.cwiseAbs().maxCoeff() <= max_index + 1e-6;
    for (int k = 0; k < 3 && whole; ++k) whole = std::abs(h[k] - std::round(h[k])) < 1e-6;
    if (!whole) continue;
    out = {int(std::lround(h[0])), int(std::lround(h[1])), int(std::lround(h[2]))};
    return true;
  }
  return false;
}

Indices normal_direction(LatticeType lattice, const Indices& plane) {
  Indices d;
  if (!direction_indices(lattice, plane_normal(lattice, plane), 12, d))
    throw std::invalid_argument("the plane's normal is no lattice direction with indices up to 12");
  return d;
}

}  // namespace granulab
