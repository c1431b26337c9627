#include "engine/crystal/exposed_faces.h"

#include <cmath>

namespace granulab {

std::vector<ExposedFace> exposed_faces(const CrystalLattice& lattice, const Polyhedron& solid, double cell) {
  std::vector<ExposedFace> out;
  std::vector<Mat3> rotations;  // per basis site (HCP's B grains are turned)
  for (const Quat& q : lattice.basis_orientation) rotations.push_back(q.toRotationMatrix());
  const double stretch = cell / solid.size();  // the neighbour across a face is 2 h (1 - eps0) away
  // Only sites inside the lattice box exist, so a neighbour beyond it is missing; one inside it is a grain or a
  // knock-out, and neither exposes the face. No lattice point lies on the box (it starts a quarter period, or
  // half a layer, below a site).
  const Vec3 lo = lattice.box_lo, hi = lattice.box_hi;
  const std::vector<Face>& faces = solid.faces();
  for (std::size_t i = 0; i < lattice.sites.size(); ++i)
    for (std::size_t k = 0; k < faces.size(); ++k) {
      const Vec3 normal = rotations[lattice.sites[i].basis] * faces[k].normal;
      const Vec3 there = lattice.sites[i].position + 2 * faces[k].distance * stretch * normal;
      const bool beyond_z = there.z() < lo.z() || there.z() > hi.z();
      const bool beyond_xy = there.x() < lo.x() || there.x() > hi.x() || there.y() < lo.y() || there.y() > hi.y();
      if (beyond_z || beyond_xy) out.push_back({i, int(k), beyond_z});
    }
  return out;
}

std::vector<ExposedArea> exposed_face_areas(const CrystalLattice& lattice, const Polyhedron& solid, double cell) {
  std::vector<ExposedArea> out(lattice.sites.size());
  for (const ExposedFace& e : exposed_faces(lattice, solid, cell)) {
    const Face& face = solid.faces()[e.face];
    const Vec3 normal = lattice.basis_orientation[lattice.sites[e.site].basis].toRotationMatrix() * face.normal;
    (e.end ? out[e.site].end : out[e.site].lateral) += face.area() * normal;
  }
  return out;
}

}  // namespace granulab
