#include "engine/analysis/slip_bands.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <unordered_map>

namespace granulab {

namespace {

constexpr double kDegrees = 180 / M_PI;

struct Family {
  Indices indices;
  Vec3 lab;  // unit normal, lab frame
};

int gcd3(const Indices& h) { return std::gcd(std::gcd(std::abs(h[0]), std::abs(h[1])), std::abs(h[2])); }

// The plane families with indices up to `max_index`: one sign each (the first nonzero index positive), reduced.
std::vector<Family> families(LatticeType lattice, const Quat& to_lab, int max_index) {
  std::vector<Family> out;
  for (int h = -max_index; h <= max_index; ++h)
    for (int k = -max_index; k <= max_index; ++k)
      for (int l = -max_index; l <= max_index; ++l) {
        const Indices i{h, k, l};
        if (i == Indices{0, 0, 0} || gcd3(i) != 1) continue;
        const int first = h != 0 ? h : k != 0 ? k : l;
        if (first < 0) continue;
        out.push_back({i, to_lab * plane_normal(lattice, i)});
      }
  return out;
}

// The lattice direction with indices up to `max_index` nearest to unit `v` (crystal frame), either sense.
std::pair<Indices, double> nearest_direction(LatticeType lattice, const Vec3& v, int max_index) {
  Indices best{0, 0, 0};
  double cos_best = -1;
  for (int u = -max_index; u <= max_index; ++u)
    for (int w = -max_index; w <= max_index; ++w)
      for (int t = -max_index; t <= max_index; ++t) {
        const Indices i{u, w, t};
        if (i == Indices{0, 0, 0} || gcd3(i) != 1) continue;
        const double c = direction_vector(lattice, i, 1).normalized().dot(v);
        if (c > cos_best + 1e-12) cos_best = c, best = i;
      }
  return {best, std::acos(std::clamp(cos_best, -1.0, 1.0)) * kDegrees};
}

}  // namespace

LatticeType snapshot_lattice(const GrainSnapshot& s) {
  switch (s.grain_shape) {
    case Shape::cube: return LatticeType::sc;
    case Shape::truncated_octahedron: return LatticeType::bcc;
    case Shape::trapezo_rhombic_dodecahedron: return LatticeType::hcp;
    default: return LatticeType::fcc;
  }
}

std::string band_plane_text(const SlipBand& b, LatticeType lattice) {
  const auto n = [](int x) { return std::to_string(x); };
  if (lattice == LatticeType::hcp)
    return "(" + n(b.plane[0]) + " " + n(b.plane[1]) + " " + n(-(b.plane[0] + b.plane[1])) + " " + n(b.plane[2]) + ")";
  return "(" + n(b.plane[0]) + " " + n(b.plane[1]) + " " + n(b.plane[2]) + ")";
}

void write_slip_bands(SummaryWriter& w, const std::vector<SlipBand>& bands, LatticeType lattice) {
  const auto triple = [&](const char* key, const auto& v, const char* unit) {
    w.begin_list(key);
    for (int k = 0; k < 3; ++k) w.number(nullptr, double(v[k]), unit);
    w.end_list();
  };
  w.begin_list("slip_bands");
  for (const SlipBand& b : bands) {
    w.begin_group(nullptr);
    w.text("plane", band_plane_text(b, lattice));
    triple("plane_indices", b.plane, "-");
    w.number("angle_to_plane", b.angle_to_plane, "deg");
    triple("normal", b.normal, "-");
    w.number("offset", b.offset, "m");
    w.number("slip", b.slip, "m");
    w.text("direction", "[" + std::to_string(b.direction[0]) + " " + std::to_string(b.direction[1]) + " " +
                            std::to_string(b.direction[2]) + "]");
    triple("direction_indices", b.direction, "-");
    w.number("direction_angle", b.direction_angle, "deg");
    w.number("dilation_angle", b.dilation_angle, "deg");
    w.number("extent", b.extent, "m");
    w.count("interfaces", b.interfaces);
    w.end_group();
  }
  w.end_list();
}

std::vector<SlipBand> find_slip_bands(const GrainSnapshot& s, LatticeType lattice, const SlipBandOptions& o) {
  const std::size_t m = s.interfaces.size();
  if (m == 0 || s.sliding.size() != m || s.position.size() != s.id.size() || s.displacement.size() != s.id.size())
    return {};
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.id.size(); ++i) index[value(s.id[i])] = i;
  struct Interface {
    std::size_t a, b;
    Vec3 mid, unit;
    double weight;
  };
  std::vector<Interface> sliding;
  double mean = 0, neighbour = 0;
  for (double d : s.sliding) mean += d;
  mean /= double(m);
  std::vector<Interface> all;
  for (std::size_t k = 0; k < m; ++k) {
    const auto ia = index.find(value(s.interfaces[k].a)), ib = index.find(value(s.interfaces[k].b));
    if (ia == index.end() || ib == index.end()) continue;
    const Vec3 ra = s.position[ia->second] - s.displacement[ia->second];
    const Vec3 rb = s.position[ib->second] - s.displacement[ib->second];
    neighbour += (rb - ra).norm();
    all.push_back({ia->second, ib->second, (ra + rb) / 2, (rb - ra).normalized(), s.sliding[k]});
  }
  if (all.empty()) return {};
  neighbour /= double(all.size());
  for (const Interface& f : all)
    if (f.weight > o.threshold * mean && f.weight > o.noise * neighbour) sliding.push_back(f);
  double total = 0;
  for (const Interface& f : sliding) total += f.weight;
  const std::vector<Family> fam = families(lattice, s.crystal_orientation, o.max_index);
  const double crossing = std::sin(15 / kDegrees), half = neighbour / 2;
  std::vector<bool> taken(sliding.size(), false);
  std::vector<SlipBand> bands;
  while (bands.size() < o.max_bands) {
    // The family and window (half a neighbour distance wide along its normal) holding the most slip.
    double best = 0, centre = 0;
    const Family* seed = nullptr;
    std::vector<std::pair<double, double>> along;  // (position along the normal, weight)
    for (const Family& f : fam) {
      along.clear();
      for (std::size_t k = 0; k < sliding.size(); ++k)
        if (!taken[k] && std::abs(f.lab.dot(sliding[k].unit)) > crossing)
          along.push_back({f.lab.dot(sliding[k].mid), sliding[k].weight});
      std::sort(along.begin(), along.end());
      double sum = 0;
      for (std::size_t i = 0, j = 0; j < along.size(); ++j) {
        sum += along[j].second;
        while (along[j].first - along[i].first > half) sum -= along[i++].second;
        if (sum > best + 1e-15 * total) best = sum, centre = (along[i].first + along[j].first) / 2, seed = &f;
      }
    }
    if (!seed || !(best > 0) || (!bands.empty() && best < o.min_share * total)) break;
    std::vector<std::size_t> members;
    for (std::size_t k = 0; k < sliding.size(); ++k)
      if (!taken[k] && std::abs(seed->lab.dot(sliding[k].unit)) > crossing &&
          std::abs(seed->lab.dot(sliding[k].mid) - centre) <= half)
        members.push_back(k);
    if (members.size() < o.min_interfaces) break;
    for (std::size_t k : members) taken[k] = true;
    // The plane through the midpoints (least squares); a band too narrow to span a plane keeps its family's.
    Vec3 c = Vec3::Zero();
    for (std::size_t k : members) c += sliding[k].mid;
    c /= double(members.size());
    Mat3 cov = Mat3::Zero();
    for (std::size_t k : members) cov += (sliding[k].mid - c) * (sliding[k].mid - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);  // ascending
    Vec3 normal = seed->lab;
    if (eig.eigenvalues()[1] > 4 * eig.eigenvalues()[0] + 1e-30) normal = eig.eigenvectors().col(0);
    if (normal.dot(seed->lab) < 0) normal = -normal;
    SlipBand band;
    double cos_best = -1;
    for (const Family& f : fam) {
      const double cos_f = std::abs(f.lab.dot(normal));
      if (cos_f > cos_best + 1e-12) {
        cos_best = cos_f;
        for (int i = 0; i < 3; ++i) band.plane[i] = f.indices[i];
      }
    }
    band.angle_to_plane = std::acos(std::clamp(cos_best, -1.0, 1.0)) * kDegrees;
    for (int i = 0; i < 3; ++i) band.normal[i] = normal[i];
    band.offset = normal.dot(c);
    // The side the normal points to against the other.
    Vec3 relative = Vec3::Zero();
    for (std::size_t k : members) {
      const Interface& f = sliding[k];
      const double side = normal.dot(f.unit) >= 0 ? 1 : -1;
      relative += side * (s.displacement[f.b] - s.displacement[f.a]);
    }
    relative /= double(members.size());
    const Vec3 in_plane = relative - relative.dot(normal) * normal;
    band.slip = in_plane.norm();
    band.dilation_angle = std::atan2(relative.dot(normal), band.slip) * kDegrees;
    if (band.slip > 0) {
      const auto [d, angle] =
          nearest_direction(lattice, s.crystal_orientation.conjugate() * (in_plane / band.slip), o.max_index);
      for (int i = 0; i < 3; ++i) band.direction[i] = d[i];
      band.direction_angle = angle;
    }
    double extent = 0;
    for (std::size_t i = 0; i < members.size(); ++i)
      for (std::size_t j = i + 1; j < members.size(); ++j)
        extent = std::max(extent, (sliding[members[i]].mid - sliding[members[j]].mid).norm());
    band.extent = extent;
    band.interfaces = std::uint32_t(members.size());
    bands.push_back(band);
  }
  return bands;
}

}  // namespace granulab
