#include "engine/crystal/exposed_faces.h"

#include <cmath>

namespace granulab {

std::vector<ExposedArea> exposed_face_areas(const CrystalLattice& lattice, const Polyhedron& solid, double cell) {
  std::vector<ExposedArea> out(lattice.sites.size());
  const Mat3 rotation = lattice.orientation.toRotationMatrix();
  const double spacing = cell / std::sqrt(2.0);
  // Only sites inside the lattice box exist, so a neighbour beyond it is missing; one inside it is a grain or a
  // knock-out, and neither exposes the face. No lattice point lies on the box (it starts a quarter period, or
  // half a layer, below a site).
  const Vec3 lo = lattice.box_lo, hi = lattice.box_hi;
  for (std::size_t i = 0; i < lattice.sites.size(); ++i)
    for (const Face& face : solid.faces()) {
      const Vec3 normal = rotation * face.normal, there = lattice.sites[i].position + spacing * normal;
      const bool beyond_z = there.z() < lo.z() || there.z() > hi.z();
      const bool beyond_xy = there.x() < lo.x() || there.x() > hi.x() || there.y() < lo.y() || there.y() > hi.y();
      if (!(beyond_z || beyond_xy)) continue;
      (beyond_z ? out[i].end : out[i].lateral) += face.edge_a.cross(face.edge_b).norm() * normal;
    }
  return out;
}

}  // namespace granulab
