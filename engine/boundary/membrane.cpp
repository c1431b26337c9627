#include "engine/boundary/membrane.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granulab {

Membrane::Membrane(double pressure, double cell) : pressure_(pressure), cell_(cell) {}

void Membrane::apply(const std::vector<Vec3>& body_positions, const std::vector<Vec3>& spheres, std::size_t per_body,
                     double radius, std::vector<Vec3>& force, std::vector<Vec3>& torque) {
  std::fill(force.begin(), force.end(), Vec3::Zero());
  std::fill(torque.begin(), torque.end(), Vec3::Zero());
  stats_ = MembraneStats{};
  if (spheres.empty()) return;
  Vec3 lo = spheres.front(), hi = lo;
  for (const Vec3& s : spheres) lo = lo.cwiseMin(s), hi = hi.cwiseMax(s);
  lo.array() -= radius;
  hi.array() += radius;

  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  const double cell_area = cell_ * cell_;
  std::vector<bool> touched(body_positions.size(), false);

  for (int face = 0; face < 4; ++face) {
    const int axis = face < 2 ? 0 : 1;             // x faces, then y faces
    const double sign = face % 2 == 0 ? 1.0 : -1.0;  // outward direction along axis
    const int u = axis == 0 ? 1 : 0, v = 2;         // the map's in-plane axes (z is always one)
    const int nu = int(std::ceil((hi[u] - lo[u]) / cell_)), nv = int(std::ceil((hi[v] - lo[v]) / cell_));
    height_.assign(std::size_t(nu) * nv, -std::numeric_limits<double>::infinity());
    owner_.assign(std::size_t(nu) * nv, kNone);

    // Outermost sphere surface per cell: every cell a sphere's disc covers, at the sphere's cap height.
    const int reach = int(std::ceil(radius / cell_));
    for (std::size_t s = 0; s < spheres.size(); ++s) {
      const Vec3& c = spheres[s];
      const double top = sign * c[axis];
      const int iu0 = int((c[u] - lo[u]) / cell_), iv0 = int((c[v] - lo[v]) / cell_);
      for (int iu = std::max(0, iu0 - reach); iu <= std::min(nu - 1, iu0 + reach); ++iu) {
        const double du = lo[u] + (iu + 0.5) * cell_ - c[u];
        for (int iv = std::max(0, iv0 - reach); iv <= std::min(nv - 1, iv0 + reach); ++iv) {
          const double dv = lo[v] + (iv + 0.5) * cell_ - c[v];
          const double r2 = radius * radius - du * du - dv * dv;
          if (r2 < 0) continue;
          const double h = top + std::sqrt(r2);
          const std::size_t k = std::size_t(iu) * nv + iv;
          if (h > height_[k]) height_[k] = h, owner_[k] = std::uint32_t(s);
        }
      }
    }

    double area = 0, weighted = 0;
    for (int iu = 0; iu < nu; ++iu) {
      for (int iv = 0; iv < nv; ++iv) {
        const std::size_t k = std::size_t(iu) * nv + iv;
        if (owner_[k] == kNone) continue;
        Vec3 f = Vec3::Zero();
        f[axis] = -sign * pressure_ * cell_area;
        Vec3 point;
        point[axis] = sign * height_[k];
        point[u] = lo[u] + (iu + 0.5) * cell_;
        point[v] = lo[v] + (iv + 0.5) * cell_;
        const std::size_t b = owner_[k] / per_body;
        force[b] += f;
        torque[b] += (point - body_positions[b]).cross(f);
        touched[b] = true;
        area += cell_area;
        weighted += cell_area * body_positions[b][axis];
      }
    }
    stats_.area[face] = area;
    stats_.load_centre[face] = area > 0 ? weighted / area : 0;
  }
  stats_.grains = std::size_t(std::count(touched.begin(), touched.end(), true));
}

}  // namespace granulab
