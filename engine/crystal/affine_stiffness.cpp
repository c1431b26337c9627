#include "engine/crystal/affine_stiffness.h"

#include <Eigen/LU>
#include <vector>

#include "engine/crystal/face_springs.h"
#include "engine/model/model.h"

namespace granulab {

Voigt affine_prediction(const CrystalSampleParams& p) {
  GrainGeometry g = p.grain;
  g.shape = grain_shape(p.lattice);
  const GrainTemplate grain(g);
  const ContactLaw law = contact_law(grain, p.material);
  const LatticeCell cell = lattice_cell(p.lattice, p.grain.size);
  std::vector<FaceSpringTerm> terms;
  const Eigen::FullPivLU<Mat3> lattice(cell.primitive);
  // Each kind of site's grain, turned in the crystal frame (HCP's B: half a turn about c); each face's springs the
  // sphere pairs that touch the neighbour across it, whichever kind of site that is.
  for (std::size_t k = 0; k < cell.basis.size(); ++k)
    for (const FaceSpring& f : face_springs(grain)) {
      const Vec3 branch = f.branch * (cell.basis_turn[k] * f.normal);
      std::size_t across = k;
      for (std::size_t m = 0; m < cell.basis.size(); ++m) {
        const Vec3 steps = lattice.solve(cell.basis[k] + branch - cell.basis[m]);
        if ((steps - steps.array().round().matrix()).cwiseAbs().maxCoeff() < 1e-6) across = m;
      }
      const double pairs = double(touching_pairs(grain, cell.basis_turn[k], cell.basis_turn[across], branch));
      terms.push_back({branch.normalized(), f.branch, pairs * law.normal_stiffness, pairs * law.tangential_stiffness});
    }
  return affine_face_spring_stiffness(terms, cell.site_volume() * double(cell.basis.size()));
}

double affine_axial_modulus(const CrystalSampleParams& p) {
  return directional_modulus(affine_prediction(p), direction_vector(p.lattice, p.axis, 1).normalized());
}

}  // namespace granulab
