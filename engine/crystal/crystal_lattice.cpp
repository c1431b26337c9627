#include "engine/crystal/crystal_lattice.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace granulab {

Quat off_axis_orientation() {
  Mat3 lab_axes;  // rows: lab x, y, z expressed in crystal coordinates
  lab_axes.row(0) = Vec3(1, -1, 0).normalized();
  lab_axes.row(1) = Vec3(1, 1, 1).normalized();
  lab_axes.row(2) = Vec3(-1, -1, 2).normalized();
  return Quat(lab_axes).normalized();  // v_lab = lab_axes * v_crystal
}

CrystalLattice build_crystal(const CrystalGeometry& g) {
  if (g.grains_x < 1 || g.rows_z < 1 || g.layers_y < 1) throw std::invalid_argument("crystal needs at least one grain");
  CrystalLattice c;
  c.orientation = off_axis_orientation();
  const double a = (1 - g.prestrain) * g.size;
  const Vec3 b1(a / std::sqrt(2.0), 0, 0);
  const Vec3 b2(a / (2 * std::sqrt(2.0)), 0, a * std::sqrt(6.0) / 4);
  const Vec3 b3(a / (2 * std::sqrt(2.0)), a / std::sqrt(3.0), a / (2 * std::sqrt(6.0)));
  const double px = b1.x(), py = b3.y(), pz = b2.z();  // row, layer and row-to-row periods
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
  return c;
}

}  // namespace granulab
