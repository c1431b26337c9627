#include "engine/crystal/crystal_lattice.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace granulab {

namespace {

std::string indices_text(const Indices& n) {
  return "[" + std::to_string(n[0]) + ", " + std::to_string(n[1]) + ", " + std::to_string(n[2]) + "]";
}

Indices reduced(const Indices& n) {
  const int g = std::gcd(std::gcd(std::abs(n[0]), std::abs(n[1])), std::abs(n[2]));
  return g > 1 ? Indices{n[0] / g, n[1] / g, n[2] / g} : n;
}

bool integral(const Vec3& v) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(v[k] - std::round(v[k])) > 1e-9) return false;
  return true;
}

// The shortest translation of the Bravais lattice along [u v w] (m): [u v w] itself once reduced, or half of it
// (FCC and BCC centring).
double repeat_length(const LatticeCell& cell, LatticeType lattice, const Indices& uvw, double a) {
  const Vec3 v = direction_vector(lattice, reduced(uvw), a);
  return integral(cell.primitive.inverse() * (v / 2)) ? v.norm() / 2 : v.norm();
}

// The fraction in [0, 1) of x.
double fraction(double x) { return x - std::floor(x); }

// Where to start a box cell so that no value (in periods) sits on a boundary: `preferred` unless some value is
// within 1e-7 of it, else the middle of the widest gap between the values (mod 1). Returned in [-1, 0).
double cell_start(std::vector<double> values, double preferred) {
  for (double& v : values) v = fraction(v);
  const bool clear = std::none_of(values.begin(), values.end(), [&](double v) {
    const double d = std::abs(v - fraction(preferred));
    return d < 1e-7 || d > 1 - 1e-7;
  });
  if (clear || values.empty()) return preferred;
  std::sort(values.begin(), values.end());
  double best = 1 - values.back() + values.front(), start = values.back() + best / 2;
  for (std::size_t i = 1; i < values.size(); ++i)
    if (values[i] - values[i - 1] > best) best = values[i] - values[i - 1], start = values[i - 1] + best / 2;
  return fraction(start) - 1;
}

CrystalLattice build_off_axis_fcc(const CrystalGeometry& g);
CrystalLattice build_any(const CrystalGeometry& g);
void knock_out(CrystalLattice& c, const CrystalGeometry& g);

}  // namespace

// The smallest multiple of (t_i . n) over the primitive translations t_i that is integral is 1/|g|.
double bravais_plane_spacing(const LatticeCell& cell, const Vec3& n) {
  const Vec3 c = cell.primitive.transpose() * n;
  const double top = c.cwiseAbs().maxCoeff();
  for (int q = 1; q <= 2000; ++q)
    if (integral(c * (q / top))) return top / q;
  throw std::invalid_argument("the lattice planes normal to the direction asked for are too far from a low-index plane");
}

Indices default_lateral(LatticeType lattice, const Indices& axis) {
  const LatticeCell cell = lattice_cell(lattice, 1);
  const Vec3 z = direction_vector(lattice, axis, 1).normalized();
  Indices best{0, 0, 0};
  double shortest = 1e300;
  for (int u = 12; u >= -12; --u)
    for (int v = 12; v >= -12; --v)
      for (int w = 12; w >= -12; --w) {
        const Indices n{u, v, w};
        if (reduced(n) != n || (u == 0 && v == 0 && w == 0)) continue;
        const int first = u != 0 ? u : v != 0 ? v : w;
        if (first < 0) continue;
        const Vec3 x = direction_vector(lattice, n, 1);
        if (std::abs(x.normalized().dot(z)) > 1e-9) continue;
        const double length = repeat_length(cell, lattice, n, 1);
        if (length < shortest * (1 - 1e-9)) shortest = length, best = n;  // descending order: ties keep the largest
      }
  if (shortest > 1e299) throw std::invalid_argument("loading.axis " + indices_text(axis) +
                                " has no normal lattice direction with indices up to 12 (give the lateral direction yourself)");
  return best;
}

std::string layer_planes(const CrystalLattice& lattice) {
  const Vec3 y = lattice.orientation.conjugate() * Vec3::UnitY();  // crystal frame
  if (lattice.type == LatticeType::fcc && (y - Vec3(1, 1, 1).normalized()).norm() < 1e-9) return "{111}";
  // Miller indices: the plane normal to y cuts the axes (cubic: the cube edges; HCP: a1, a2, c) at reciprocals
  // proportional to t . y; the smallest integers that fit, the first nonzero one positive (a plane and its
  // opposite are the same planes). HCP in four indices (h k i l), i = -(h + k).
  const Mat3 axes = lattice.type == LatticeType::hcp ? lattice_cell(LatticeType::hcp, 1).primitive : Mat3::Identity();
  Vec3 n = axes.transpose() * y;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(n[k]) <= 1e-9) continue;
    if (n[k] < 0) n = -n;
    break;
  }
  double smallest = 1e300;
  for (int k = 0; k < 3; ++k)
    if (std::abs(n[k]) > 1e-9) smallest = std::min(smallest, std::abs(n[k]));
  for (int m = 1; m <= 12; ++m) {
    const Vec3 h = n * (m / smallest);
    if (!integral(h)) continue;
    const long a = std::lround(h[0]), b = std::lround(h[1]), c = std::lround(h[2]);
    if (lattice.type == LatticeType::hcp)
      return "(" + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(-(a + b)) + " " +
             std::to_string(c) + ")";
    return "(" + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + ")";
  }
  return "layers normal to y";
}

Quat off_axis_orientation() {
  Mat3 lab_axes;  // rows: lab x, y, z expressed in crystal coordinates
  lab_axes.row(0) = Vec3(1, -1, 0).normalized();
  lab_axes.row(1) = Vec3(1, 1, 1).normalized();
  lab_axes.row(2) = Vec3(-1, -1, 2).normalized();
  return Quat(lab_axes).normalized();  // v_lab = lab_axes * v_crystal
}

bool papers_crystal(LatticeType lattice, const Indices& axis, const Indices& lateral) {
  return lattice == LatticeType::fcc && reduced(axis) == Indices{-1, -1, 2} && (lateral == Indices{0, 0, 0} || reduced(lateral) == Indices{1, -1, 0});
}

CrystalLattice build_crystal(const CrystalGeometry& g) {
  if (g.grains_x < 1 || g.rows_z < 1 || g.layers_y < 1) throw std::invalid_argument("crystal needs at least one grain");
  CrystalLattice c = papers_crystal(g.lattice, g.axis, g.lateral) ? build_off_axis_fcc(g) : build_any(g);
  knock_out(c, g);
  return c;
}

namespace {

// The paper's crystal, built as it always was (bit for bit: golden data and examples depend on it).
CrystalLattice build_off_axis_fcc(const CrystalGeometry& g) {
  CrystalLattice c;
  c.type = LatticeType::fcc;
  c.orientation = off_axis_orientation();
  c.basis_orientation = {c.orientation};
  const double a = (1 - g.prestrain) * g.size;
  const Vec3 b1(a / std::sqrt(2.0), 0, 0);
  const Vec3 b2(a / (2 * std::sqrt(2.0)), 0, a * std::sqrt(6.0) / 4);
  const Vec3 b3(a / (2 * std::sqrt(2.0)), a / std::sqrt(3.0), a / (2 * std::sqrt(6.0)));
  const double px = b1.x(), py = b3.y(), pz = b2.z();  // row, layer and row-to-row periods
  c.period = Vec3(px, py, pz);
  c.extent = Vec3(g.grains_x * px, g.layers_y * py, g.rows_z * pz);

  const std::uint32_t n_box = std::uint32_t(g.grains_x) * g.rows_z * g.layers_y;
  for (GrainId id : g.knockout_ids)
    if (value(id) >= n_box)
      throw std::invalid_argument("knock-out id " + std::to_string(value(id)) + " is outside the crystal (ids 0.." +
                                  std::to_string(n_box - 1) + ")");

  // The sites of the infinite lattice k b3 + j b2 + i b1 that fall inside the box, which starts a quarter
  // period below the first site so that no site sits on a boundary. (Wrapping coordinates instead would
  // break the lattice: a shift of one row period along z alone is not a lattice vector.)
  const int reach = g.grains_x + g.rows_z + g.layers_y + 2;
  for (int k = 0; k < g.layers_y; ++k) {
    for (int j = -reach; j <= reach; ++j) {
      const double z = j * pz + k * b3.z();
      const int row = int(std::floor(z / pz + 0.25));
      if (row < 0 || row >= g.rows_z) continue;
      for (int i = -2 * reach; i <= 2 * reach; ++i) {
        const double x = i * px + j * b2.x() + k * b3.x();
        const int column = int(std::floor(x / px + 0.25));
        if (column < 0 || column >= g.grains_x) continue;
        LatticeSite s;
        s.layer = k, s.row = row, s.column = column;
        s.id = GrainId((k * g.rows_z + row) * g.grains_x + column);
        s.position = Vec3(x, k * py, z);
        c.sites.push_back(s);
      }
    }
  }
  // Centre the bounding box of the grain centres on the origin (along z it sits pz/12 off the box's
  // own centre when there are three layers or more, because of the ABC stacking).
  Vec3 lo = c.sites.front().position, hi = lo;
  for (const LatticeSite& s : c.sites) lo = lo.cwiseMin(s.position), hi = hi.cwiseMax(s.position);
  const Vec3 centre = (lo + hi) / 2;
  for (LatticeSite& s : c.sites) s.position -= centre;
  // The box the rules above keep sites in: columns and rows start a quarter period below a site, layers
  // half a layer spacing below one.
  c.box_lo = Vec3(-0.25 * px, -0.5 * py, -0.25 * pz) - centre;
  c.box_hi = c.box_lo + c.extent;

  return c;
}

// Removes the knocked-out sites and sorts the rest by id.
void knock_out(CrystalLattice& c, const CrystalGeometry& g) {
  auto knocked = [&](const LatticeSite& s) {
    if (std::find(g.knockout_ids.begin(), g.knockout_ids.end(), s.id) != g.knockout_ids.end()) return true;
    for (const KnockoutRegion& r : g.knockout_regions) {
      const double dx = s.position.x() / g.size - r.x, dz = s.position.z() / g.size - r.z;
      if (dx * dx + dz * dz < r.radius * r.radius) return true;
    }
    return false;
  };
  const std::size_t before = c.sites.size();
  c.sites.erase(std::remove_if(c.sites.begin(), c.sites.end(), knocked), c.sites.end());
  c.knocked_out = before - c.sites.size();
  std::sort(c.sites.begin(), c.sites.end(), [](const LatticeSite& p, const LatticeSite& q) { return p.id < q.id; });
}

// Any lattice along any axis: the sites of the lattice whose lab position falls in the box, which starts a
// quarter period below the origin's site along x and z and half a layer below it along y, unless another
// site would then sit on a boundary (then in the widest gap between them; for HCP's unevenly spaced planes
// so that each plane has its own layer).
CrystalLattice build_any(const CrystalGeometry& g) {
  const double a = (1 - g.prestrain) * g.size;
  const LatticeCell cell = lattice_cell(g.lattice, a);
  if (g.axis == Indices{0, 0, 0}) throw std::invalid_argument("loading.axis must not be [0, 0, 0]");
  const Indices lateral = g.lateral == Indices{0, 0, 0} ? default_lateral(g.lattice, g.axis) : g.lateral;
  const Vec3 z = direction_vector(g.lattice, g.axis, a).normalized();
  const Vec3 x = direction_vector(g.lattice, lateral, a).normalized();
  if (std::abs(x.dot(z)) > 1e-9)
    throw std::invalid_argument("loading.lateral " + indices_text(lateral) + " is not normal to loading.axis " +
                                indices_text(g.axis) + " (their dot product, in lengths, is " +
                                std::to_string(x.dot(z)) + ")");
  const Vec3 y = z.cross(x);
  Mat3 lab_axes;  // rows: lab x, y, z in crystal coordinates, v_lab = lab_axes v_crystal
  lab_axes.row(0) = x, lab_axes.row(1) = y, lab_axes.row(2) = z;

  CrystalLattice c;
  c.type = g.lattice;
  c.orientation = Quat(lab_axes).normalized();
  for (const Quat& turn : cell.basis_turn) c.basis_orientation.push_back((c.orientation * turn).normalized());
  // Periods: the repeat along x; the spacing of the site planes normal to y (HCP: the B planes halve the
  // Bravais spacing on average); whatever along z makes one grain per cell on average.
  const double wx = repeat_length(cell, g.lattice, lateral, a), bravais_y = bravais_plane_spacing(cell, y);
  std::vector<double> plane_offsets;  // each basis site's plane, in Bravais spacings
  for (const Vec3& b : cell.basis) plane_offsets.push_back(fraction(b.dot(y) / bravais_y + 1e-12));
  std::sort(plane_offsets.begin(), plane_offsets.end());
  const bool split = plane_offsets.size() > 1 && std::min(plane_offsets.back(), 1 - plane_offsets.back()) > 1e-7;
  const double wy = split ? bravais_y / 2 : bravais_y, wz = cell.site_volume() / (wx * wy);
  c.period = Vec3(wx, wy, wz);
  c.extent = Vec3(g.grains_x * wx, g.layers_y * wy, g.rows_z * wz);
  // y: half a layer below the origin's plane; with two planes per Bravais spacing at 0 and delta (in
  // spacings), the start b (in layers of half a spacing) must put 0 in [b, b + 1) and 2 delta in [b + 1, b + 2).
  double start_y = -0.5;
  if (split) {
    const double delta = 2 * plane_offsets.back();
    start_y = (std::max(-1.0, delta - 2) + std::min(0.0, delta - 1)) / 2;
  }

  // Every site in the box plus a period of margin, as candidates: the box's corners in fractional coordinates.
  const Mat3 lab_to_fraction = cell.primitive.inverse() * lab_axes.transpose();
  const Vec3 margin = c.period, lo_guess = Vec3(-1.25 * wx, (start_y - 1) * wy, -1.25 * wz);
  const Vec3 hi_guess = lo_guess + c.extent + 2 * margin;
  Vec3 f_lo = Vec3::Constant(1e300), f_hi = Vec3::Constant(-1e300);
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? hi_guess.x() : lo_guess.x(), (corner & 2) ? hi_guess.y() : lo_guess.y(),
                 (corner & 4) ? hi_guess.z() : lo_guess.z());
    const Vec3 f = lab_to_fraction * p;
    f_lo = f_lo.cwiseMin(f), f_hi = f_hi.cwiseMax(f);
  }
  // The search visits every lattice point of the box's bounding box in lattice coordinates: for a high-index
  // axis and a long thin box that is far more than the grains (sc [12 11 10] at 1 x 1 x 400: 1e11). Bounded, so
  // that no spec holds a request or a worker for minutes (about 0.1 s per 1e7 points).
  double points = double(cell.basis.size());
  for (int k = 0; k < 3; ++k) points *= std::ceil(f_hi[k]) - std::floor(f_lo[k]) + 3;
  if (points > kMaxLatticeSearch)
    throw std::invalid_argument("loading.axis " + indices_text(g.axis) + " with this box needs a search of " +
                                std::to_string(long(points)) + " lattice points (at most " +
                                std::to_string(long(kMaxLatticeSearch)) +
                                "): take a lower-index axis or lateral direction, or a box less long and thin");
  struct Candidate {
    Vec3 position;
    std::uint8_t basis;
  };
  std::vector<Candidate> candidates;
  for (long i = long(std::floor(f_lo.x())) - 1; i <= long(std::ceil(f_hi.x())) + 1; ++i)
    for (long j = long(std::floor(f_lo.y())) - 1; j <= long(std::ceil(f_hi.y())) + 1; ++j)
      for (long k = long(std::floor(f_lo.z())) - 1; k <= long(std::ceil(f_hi.z())) + 1; ++k)
        for (std::size_t b = 0; b < cell.basis.size(); ++b) {
          const Vec3 p = lab_axes * (cell.primitive * Vec3(double(i), double(j), double(k)) + cell.basis[b]);
          if (((p - lo_guess).array() >= 0).all() && ((hi_guess - p).array() > 0).all())
            candidates.push_back({p, std::uint8_t(b)});
        }
  std::vector<double> fx, fz;
  for (const Candidate& q : candidates) fx.push_back(q.position.x() / wx), fz.push_back(q.position.z() / wz);
  const Vec3 lo(cell_start(fx, -0.25) * wx, start_y * wy, cell_start(fz, -0.25) * wz);

  for (const Candidate& q : candidates) {
    const Vec3 u = (q.position - lo).cwiseQuotient(c.period);
    const int column = int(std::floor(u.x())), layer = int(std::floor(u.y() + 1e-9)), row = int(std::floor(u.z()));
    if (column < 0 || column >= g.grains_x || layer < 0 || layer >= g.layers_y || row < 0 || row >= g.rows_z) continue;
    LatticeSite s;
    s.column = column, s.layer = layer, s.row = row;
    s.position = q.position;
    s.basis = q.basis;
    c.sites.push_back(s);
  }
  if (c.sites.empty()) throw std::invalid_argument("the crystal box holds no lattice site");
  // Ids: layer-major, then row, then column (then along x and z, where a cell holds more than one site).
  std::sort(c.sites.begin(), c.sites.end(), [](const LatticeSite& p, const LatticeSite& q) {
    if (p.layer != q.layer) return p.layer < q.layer;
    if (p.row != q.row) return p.row < q.row;
    if (p.column != q.column) return p.column < q.column;
    if (p.position.x() != q.position.x()) return p.position.x() < q.position.x();
    return p.position.z() < q.position.z();
  });
  for (std::size_t k = 0; k < c.sites.size(); ++k) c.sites[k].id = GrainId(std::uint32_t(k));
  for (GrainId id : g.knockout_ids)
    if (value(id) >= c.sites.size())
      throw std::invalid_argument("knock-out id " + std::to_string(value(id)) + " is outside the crystal (ids 0.." +
                                  std::to_string(c.sites.size() - 1) + ")");
  Vec3 p_lo = c.sites.front().position, p_hi = p_lo;
  for (const LatticeSite& s : c.sites) p_lo = p_lo.cwiseMin(s.position), p_hi = p_hi.cwiseMax(s.position);
  const Vec3 centre = (p_lo + p_hi) / 2;
  for (LatticeSite& s : c.sites) s.position -= centre;
  c.box_lo = lo - centre;
  c.box_hi = c.box_lo + c.extent;
  return c;
}

}  // namespace

}  // namespace granulab
