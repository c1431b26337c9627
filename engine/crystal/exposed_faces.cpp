#include "engine/crystal/exposed_faces.h"

#include <cmath>

namespace granulab {

std::vector<ExposedArea> exposed_face_areas(const CrystalLattice& lattice, const Polyhedron& solid, double cell) {
  std::vector<ExposedArea> out(lattice.sites.size());
  std::vector<Mat3> rotations;  // per basis site (HCP's B grains are turned)
  for (const Quat& q : lattice.basis_orientation) rotations.push_back(q.toRotationMatrix());
  const double stretch = cell / solid.size();  // the neighbour across a face is 2 h (1 - eps0) away
  // Only sites inside the lattice box exist, so a neighbour beyond it is missing; one inside it is a grain or a
  // knock-out, and neither exposes the face. No lattice point lies on the box (it starts a quarter period, or
  // half a layer, below a site).
  const Vec3 lo = lattice.box_lo, hi = lattice.box_hi;
  for (std::size_t i = 0; i < lattice.sites.size(); ++i)
    for (const Face& face : solid.faces()) {
      const Vec3 normal = rotations[lattice.sites[i].basis] * face.normal;
      const Vec3 there = lattice.sites[i].position + 2 * face.distance * stretch * normal;
      const bool beyond_z = there.z() < lo.z() || there.z() > hi.z();
      const bool beyond_xy = there.x() < lo.x() || there.x() > hi.x() || there.y() < lo.y() || there.y() > hi.y();
      if (!(beyond_z || beyond_xy)) continue;
      (beyond_z ? out[i].end : out[i].lateral) += face.area() * normal;
    }
  return out;
}

}  // namespace granulab
