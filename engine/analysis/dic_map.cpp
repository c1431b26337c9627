#include "engine/analysis/dic_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "engine/analysis/snapshot_layers.h"

namespace granulab {

namespace {

struct FaceGrain {
  double x, z;  // reference (m)
  Vec3 u;       // displacement (m)
};

}  // namespace

DicMap dic_map(const GrainSnapshot& s, double step, double subset, std::size_t max_nodes) {
  if (!(step > 0)) throw std::invalid_argument("the DIC grid step must be > 0");
  if (s.id.empty()) throw std::invalid_argument("the snapshot has no grains");
  const SnapshotLayers layers = snapshot_layers(s);
  double neighbour = neighbour_distance(s);
  std::vector<FaceGrain> face;
  DicMap m;
  for (std::size_t i = 0; i < s.id.size(); ++i) {
    if (layers.layer[i] != 0) continue;
    const Vec3 ref = s.position[i] - s.displacement[i];
    face.push_back({ref.x(), ref.z(), s.displacement[i]});
    m.y += ref.y();
  }
  m.grains = face.size();
  m.y /= double(face.size());
  double x_lo = 1e300, x_hi = -1e300, z_lo = 1e300, z_hi = -1e300;
  for (const FaceGrain& g : face)
    x_lo = std::min(x_lo, g.x), x_hi = std::max(x_hi, g.x), z_lo = std::min(z_lo, g.z), z_hi = std::max(z_hi, g.z);
  if (!(neighbour > 0)) neighbour = std::max({x_hi - x_lo, z_hi - z_lo, step});  // no interfaces: one grain or so
  m.step = step;
  m.subset = subset > 0 ? subset : std::max(step, 1.25 * neighbour);
  // Nodes over the face's grain centres, centred on them.
  const double nx_f = std::floor((x_hi - x_lo) / step) + 1, nz_f = std::floor((z_hi - z_lo) / step) + 1;
  if (nx_f * nz_f > double(max_nodes))
    throw std::invalid_argument("a DIC grid of step " + std::to_string(step) + " m has " +
                                std::to_string(std::llround(nx_f * nz_f)) + " nodes over this face, more than " +
                                std::to_string(max_nodes) + ": take a larger step");
  m.nx = int(nx_f), m.nz = int(nz_f);
  m.x0 = 0.5 * (x_lo + x_hi) - 0.5 * (m.nx - 1) * step;
  m.z0 = 0.5 * (z_lo + z_hi) - 0.5 * (m.nz - 1) * step;

  // Buckets of the subset's size over the face.
  const double cell = m.subset;
  const int cx = int(std::floor((x_hi - x_lo) / cell)) + 1, cz = int(std::floor((z_hi - z_lo) / cell)) + 1;
  std::vector<std::vector<std::size_t>> bucket(std::size_t(cx) * std::size_t(cz));
  const auto cell_of = [&](double v, double lo, int n) { return std::clamp(int(std::floor((v - lo) / cell)), 0, n - 1); };
  for (std::size_t g = 0; g < face.size(); ++g)
    bucket[std::size_t(cell_of(face[g].z, z_lo, cz)) * cx + cell_of(face[g].x, x_lo, cx)].push_back(g);

  const std::size_t nodes = std::size_t(m.nx) * std::size_t(m.nz);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto* field : {&m.ux, &m.uy, &m.uz, &m.exx, &m.ezz, &m.exz, &m.gamma_max}) field->assign(nodes, nan);
  const double r2 = m.subset * m.subset, near2 = neighbour * neighbour, min_spread2 = 0.04 * near2;
#pragma omp parallel for schedule(dynamic, 16) if (nodes > 4096)
  for (long node = 0; node < long(nodes); ++node) {
    const double X = m.x0 + double(node % m.nx) * step, Z = m.z0 + double(node / m.nx) * step;
    // Weighted normal equations of u = a + b (x - X) + c (z - Z), weight (1 - d^2/r^2)^2: smooth as grains
    // enter and leave the subset, and exact for an affine field whatever the weights.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // columns: u_x, u_y, u_z
    double nearest2 = 1e300;
    int count = 0;
    const int i0 = cell_of(X - m.subset, x_lo, cx), i1 = cell_of(X + m.subset, x_lo, cx);
    const int k0 = cell_of(Z - m.subset, z_lo, cz), k1 = cell_of(Z + m.subset, z_lo, cz);
    for (int k = k0; k <= k1; ++k)
      for (int i = i0; i <= i1; ++i)
        for (std::size_t g : bucket[std::size_t(k) * cx + i]) {
          const double dx = face[g].x - X, dz = face[g].z - Z, d2 = dx * dx + dz * dz;
          nearest2 = std::min(nearest2, d2);
          if (d2 >= r2) continue;
          const double w = (1 - d2 / r2) * (1 - d2 / r2);
          const Eigen::Vector3d basis(1, dx, dz);
          normal += w * basis * basis.transpose();
          rhs += w * basis * face[g].u.transpose();
          ++count;
        }
    if (count < 3 || nearest2 > near2) continue;  // outside the face, or in a hole
    // The subset's grains must spread in both directions, or the gradient is undetermined (collinear grains) or
    // amplifies their non-affine motion without bound (nearly collinear, at a hole's rim): the weighted spread of
    // their positions about their centroid, its smaller principal value, at least a fifth of a neighbour distance
    // (a full hexagon has about 0.6).
    const double w = normal(0, 0), mx = normal(0, 1) / w, mz = normal(0, 2) / w;
    const double cxx = normal(1, 1) / w - mx * mx, czz = normal(2, 2) / w - mz * mz, cxz = normal(1, 2) / w - mx * mz;
    const double least = 0.5 * (cxx + czz) - std::sqrt(0.25 * (cxx - czz) * (cxx - czz) + cxz * cxz);
    if (!(least >= min_spread2)) continue;
    const Eigen::LDLT<Eigen::Matrix3d> solve(normal);
    if (solve.info() != Eigen::Success) continue;
    const Eigen::Matrix3d coef = solve.solve(rhs);  // rows: value, d/dX, d/dZ; columns: u_x, u_y, u_z
    Eigen::Matrix<double, 3, 2> F;
    F << 1 + coef(1, 0), coef(2, 0), coef(1, 1), coef(2, 1), coef(1, 2), 1 + coef(2, 2);
    const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
    m.ux[node] = coef(0, 0), m.uy[node] = coef(0, 1), m.uz[node] = coef(0, 2);
    m.exx[node] = E(0, 0), m.ezz[node] = E(1, 1), m.exz[node] = E(0, 1);
    m.gamma_max[node] = std::sqrt(0.25 * (E(0, 0) - E(1, 1)) * (E(0, 0) - E(1, 1)) + E(0, 1) * E(0, 1));
  }
  return m;
}

}  // namespace granulab
