#include "engine/analysis/yield_estimate.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "engine/crystal/crystal_lattice.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

namespace {

constexpr double kTol = 1e-9;
constexpr double kDegrees = 180.0 / M_PI;

// Each basis site's face neighbours: the vector to the neighbour across each face of its Voronoi cell (twice the
// face's distance along its normal), crystal frame, cubic cell 1.
std::vector<std::vector<Vec3>> neighbour_vectors(LatticeType lattice, const LatticeCell& cell) {
  const Polyhedron grain = Polyhedron::make(grain_shape(lattice), 1);
  std::vector<std::vector<Vec3>> out(cell.basis.size());
  for (std::size_t b = 0; b < cell.basis.size(); ++b)
    for (const Face& f : grain.faces()) out[b].push_back(cell.basis_turn[b] * (2 * f.distance * f.normal));
  return out;
}

void add_unique(std::vector<Vec3>& normals, const Vec3& n) {
  for (const Vec3& m : normals)
    if ((m - n).norm() < 1e-7) return;
  normals.push_back(n);
}

// The cuts of the crystal along the planes of unit normal m: one between each pair of neighbouring site planes
// within a Bravais spacing (one cut for SC, FCC and BCC; HCP's basal planes alternate A and B, two). For each, the
// unit normals of the faces crossing it upward (n . m > 0): a face between a site at height y_b and its neighbour
// d above crosses the cut at h when y_b < h < y_b + d . m, counted over the site planes k spacings apart.
std::vector<std::vector<Vec3>> cuts(const LatticeCell& cell, const std::vector<std::vector<Vec3>>& neighbours,
                                    const Vec3& m) {
  const double spacing = bravais_plane_spacing(cell, m);
  std::vector<double> heights;  // each basis site's plane, in spacings, in [0, 1)
  for (const Vec3& b : cell.basis) {
    const double y = b.dot(m) / spacing + 1e-12;
    heights.push_back(y - std::floor(y));
  }
  std::vector<double> planes = heights;
  std::sort(planes.begin(), planes.end());
  planes.erase(std::unique(planes.begin(), planes.end(), [](double a, double b) { return b - a < 1e-7; }),
               planes.end());
  std::vector<std::vector<Vec3>> out;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const double next = i + 1 < planes.size() ? planes[i + 1] : planes[0] + 1;
    const double cut = (planes[i] + next) / 2;
    std::vector<Vec3> faces;
    for (std::size_t b = 0; b < cell.basis.size(); ++b)
      for (const Vec3& d : neighbours[b]) {
        const double up = d.dot(m) / spacing;
        if (up <= kTol) continue;
        const double crossings = std::floor(cut - heights[b]) - std::floor(cut - heights[b] - up);
        if (crossings > 0.5) add_unique(faces, d.normalized());
      }
    out.push_back(faces);
  }
  return out;
}

// Whether translation t opens or slides on every face (t . n >= 0); `closed` counts those it slides on.
bool admissible(const std::vector<Vec3>& faces, const Vec3& t, int& closed) {
  closed = 0;
  for (const Vec3& n : faces) {
    const double along = t.dot(n);
    if (along < -kTol) return false;
    closed += along <= kTol;
  }
  return true;
}

struct Mechanism {
  double load = 1e300;  // lambda: (sigma1 - p0) / p0
  Vec3 t = Vec3::Zero();
  int closed = 0;
};

void keep_lower(Mechanism& best, double load, const Vec3& t, int closed) {
  if (load < best.load - 1e-12 * std::max(1.0, std::abs(load))) best = {load, t, closed};
}

// The first compression load lambda >= 0 (R = m + lambda q z, q = z . m, in p0) at which a mechanism of one cut
// becomes possible.
Mechanism first_mechanism(const std::vector<Vec3>& faces, const Vec3& m, const Vec3& z, double f) {
  Mechanism best;
  const double q = z.dot(m);
  if (std::abs(q) < kTol) return best;  // the axis lies in the plane: no shear traction on it
  // One face closed: R at the friction angle of n, t against R's part along the face.
  for (const Vec3& n : faces) {
    const double a = m.dot(n), b = q * z.dot(n);
    const Vec3 A = m - a * n, B = q * (z - z.dot(n) * n);
    const double c2 = B.dot(B) - f * f * b * b, c1 = 2 * (A.dot(B) - f * f * a * b), c0 = A.dot(A) - f * f * a * a;
    std::vector<double> roots;
    if (std::abs(c2) < 1e-14) {
      if (std::abs(c1) > 1e-14) roots.push_back(-c0 / c1);
    } else {
      const double disc = c1 * c1 - 4 * c2 * c0;
      if (disc >= 0) {
        const double s = std::sqrt(disc);
        roots.push_back((-c1 - s) / (2 * c2));
        roots.push_back((-c1 + s) / (2 * c2));
      }
    }
    for (double load : roots) {
      if (load < -1e-12 || a + load * b <= 0) continue;
      const Vec3 tangential = A + load * B;
      if (tangential.norm() < 1e-12) continue;
      const Vec3 t = -tangential.normalized();
      int closed = 0;
      if (admissible(faces, t, closed)) keep_lower(best, std::max(0.0, load), t, closed);
    }
  }
  // Two faces closed, t along their common edge (either sense): R in the cone of n_j - f t and n_k - f t.
  for (std::size_t j = 0; j < faces.size(); ++j)
    for (std::size_t k = j + 1; k < faces.size(); ++k) {
      const Vec3 edge = faces[j].cross(faces[k]);
      if (edge.norm() < 1e-7) continue;
      for (double sense : {1.0, -1.0}) {
        const Vec3 t = sense * edge.normalized();
        int closed = 0;
        if (!admissible(faces, t, closed)) continue;
        const Vec3 vj = faces[j] - f * t, vk = faces[k] - f * t;
        Mat3 system;  // alpha vj + beta vk - lambda q z = m
        system.col(0) = vj, system.col(1) = vk, system.col(2) = -q * z;
        if (std::abs(system.determinant()) > 1e-12) {
          const Vec3 x = system.colPivHouseholderQr().solve(m);
          if (x[0] >= -kTol && x[1] >= -kTol && x[2] >= -1e-12) keep_lower(best, std::max(0.0, x[2]), t, closed);
          continue;
        }
        // z in the plane of vj, vk: R stays in it only if m is too; then the loads where both weights are >= 0.
        const Vec3 w = vj.cross(vk).normalized();
        if (std::abs(m.dot(w)) > 1e-9) continue;
        Eigen::Matrix<double, 3, 2> basis;
        basis.col(0) = vj, basis.col(1) = vk;
        const Eigen::Vector2d at0 = basis.colPivHouseholderQr().solve(m), per = basis.colPivHouseholderQr().solve(q * z);
        double lo = 0, hi = 1e300;
        bool feasible = true;
        for (int c = 0; c < 2; ++c) {
          if (std::abs(per[c]) < 1e-14) feasible = feasible && at0[c] >= -kTol;
          else if (per[c] > 0) lo = std::max(lo, -at0[c] / per[c]);
          else hi = std::min(hi, -at0[c] / per[c]);
        }
        if (feasible && lo <= hi) keep_lower(best, lo, t, closed);
      }
    }
  return best;
}

int gcd_all(const std::vector<int>& v) {
  int g = 0;
  for (int x : v) g = std::gcd(g, std::abs(x));
  return g;
}

std::string indices_text(const std::vector<int>& v, char open, char close) {
  std::string s(1, open);
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? " " : "") + std::to_string(v[k]);
  return s + close;
}

// Miller indices as users write them: HCP in four, (h k -(h+k) l).
std::vector<int> plane_indices(LatticeType lattice, const Indices& p) {
  if (lattice == LatticeType::hcp) return {p[0], p[1], -(p[0] + p[1]), p[2]};
  return {p[0], p[1], p[2]};
}

// Direction indices as users write them: HCP in four, [U V T W] = [2u - v, 2v - u, -(u + v), 3w] / 3, reduced.
std::vector<int> direction_list(LatticeType lattice, const Indices& d) {
  if (lattice != LatticeType::hcp) return {d[0], d[1], d[2]};
  std::vector<int> four{2 * d[0] - d[1], 2 * d[1] - d[0], -(d[0] + d[1]), 3 * d[2]};
  const int g = gcd_all(four);
  for (int& x : four) x /= g;
  return four;
}

void describe(YieldEstimate& e, LatticeType lattice, const Indices& plane, const Vec3& m, const Vec3& t, int closed) {
  e.found = true;
  e.plane = plane_indices(lattice, plane);
  e.plane_text = indices_text(e.plane, '(', ')');
  e.plane_normal = m;
  e.slip = t;
  e.closed_faces = closed;
  e.dilation_angle = std::asin(std::clamp(t.dot(m), -1.0, 1.0)) * kDegrees;
  if (std::abs(e.dilation_angle) < 1e-9) e.dilation_angle = 0;  // flat faces: no "-0"
  const Vec3 along = t - t.dot(m) * m;
  Indices d;
  if (along.norm() > 1e-9 && direction_indices(lattice, along, 12, d)) {
    e.direction = direction_list(lattice, d);
    e.direction_text = indices_text(e.direction, '[', ']');
  }
}

}  // namespace

std::string yield_estimate_text(const YieldEstimate& e) {
  char text[400];
  const std::string where = "sliding on " + e.plane_text + (e.direction_text.empty() ? "" : " along " + e.direction_text);
  if (!e.found)
    return e.shear ? "rigid-grain shear strength: none, the faces lock this direction"
                   : "rigid-grain first yield: none, no plane of Miller indices up to 3 slides (locked until the grains "
                     "deform or turn)";
  if (e.shear)
    std::snprintf(text, sizeof text, "rigid-grain shear strength: tau / sigma_n = %.3g, %s, uplift %.3g deg",
                  e.shear_over_normal, where.c_str(), e.dilation_angle);
  else
    std::snprintf(text, sizeof text, "rigid-grain first yield: sigma1 = %.3g p0 (deviator %.3g p0), %s, uplift %.3g deg",
                  e.axial_over_p0, e.axial_over_p0 - 1, where.c_str(), e.dilation_angle);
  return text;
}

void write_yield_estimate(SummaryWriter& w, const YieldEstimate& e) {
  w.begin_group("yield_estimate");
  w.flag("found", e.found);
  if (e.found) {
    if (e.shear) {
      w.number("shear_over_normal", e.shear_over_normal, "-");
    } else {
      w.number("axial_over_p0", e.axial_over_p0, "-");
      w.number("deviator_over_p0", e.axial_over_p0 - 1, "-");
      w.number("shear_over_normal", e.shear_over_normal, "-");
    }
    w.text("plane", e.plane_text);
    w.text("direction", e.direction_text);
    w.number("dilation_angle", e.dilation_angle, "deg");
    w.count("closed_faces", std::uint64_t(e.closed_faces));
  } else {
    w.text("note", e.shear ? "no rigid translation along this direction slides the plane: the faces lock it"
                           : "no rigid translation on any plane of Miller indices up to 3: the crystal is locked until "
                             "its grains deform or turn");
  }
  w.text("text", yield_estimate_text(e));
  w.text("method", "rigid grains, Coulomb sliding of one half-crystal over the other on a lattice plane (docs/model.md, "
                   "\"Yield estimate\")");
  w.end_group();
}

YieldEstimate compression_yield_estimate(LatticeType lattice, const Vec3& axis, double friction, int max_index) {
  const LatticeCell cell = lattice_cell(lattice, 1);
  const auto neighbours = neighbour_vectors(lattice, cell);
  const Vec3 z = axis.normalized();
  YieldEstimate best;
  Mechanism lowest;
  for (int h = 0; h <= max_index; ++h)
    for (int k = -max_index; k <= max_index; ++k)
      for (int l = -max_index; l <= max_index; ++l) {
        const Indices plane{h, k, l};
        const int first = h != 0 ? h : k != 0 ? k : l;
        if (first <= 0 || gcd_all({h, k, l}) != 1) continue;  // a plane and its opposite are one
        const Vec3 m = plane_normal(lattice, plane);
        std::vector<std::vector<Vec3>> plane_cuts;
        try {
          plane_cuts = cuts(cell, neighbours, m);
        } catch (const std::invalid_argument&) {
          continue;
        }
        for (const std::vector<Vec3>& faces : plane_cuts) {
          const Mechanism found = first_mechanism(faces, m, z, friction);
          if (found.load < lowest.load - 1e-12 * std::max(1.0, std::abs(found.load))) {
            lowest = found;
            describe(best, lattice, plane, m, found.t, found.closed);
            best.axial_over_p0 = 1 + found.load;
            const Vec3 r = m + found.load * z.dot(m) * z;  // the traction then, in p0
            best.shear_over_normal = (r - r.dot(m) * m).norm() / r.dot(m);
          }
        }
      }
  return best;
}

YieldEstimate shear_yield_estimate(LatticeType lattice, const Indices& plane, const Vec3& direction, double friction) {
  const LatticeCell cell = lattice_cell(lattice, 1);
  const Vec3 m = plane_normal(lattice, plane), s = direction.normalized();
  if (std::abs(s.dot(m)) > 1e-9) throw std::invalid_argument("the shear direction does not lie in the shear plane");
  YieldEstimate best;
  best.shear = true;
  best.shear_over_normal = 1e300;
  for (const std::vector<Vec3>& faces : cuts(cell, neighbour_vectors(lattice, cell), m)) {
    // The least uplift that opens or slides every face, and the faces it slides on.
    double theta = -M_PI / 2;
    for (const Vec3& n : faces) theta = std::max(theta, std::atan2(-s.dot(n), m.dot(n)));
    const Vec3 t = std::cos(theta) * s + std::sin(theta) * m, u = -std::sin(theta) * s + std::cos(theta) * m;
    double c = 0;
    int closed = 0;
    for (const Vec3& n : faces)
      if (std::abs(t.dot(n)) <= 1e-9) c = std::max(c, n.dot(u)), ++closed;
    if (c <= kTol) continue;
    const double angle = theta + std::atan(friction / c);
    if (angle >= M_PI / 2 - 1e-12) continue;  // locked: no shear stress slides it
    const double ratio = std::tan(angle);
    if (ratio < best.shear_over_normal - 1e-12) {
      describe(best, lattice, plane, m, t, closed);
      best.shear_over_normal = ratio;
    }
  }
  if (!best.found) best.shear_over_normal = 0;
  return best;
}

}  // namespace granulab
