#include "engine/model/model.h"

#include <cmath>

namespace granulab {

double normal_stiffness(const GrainTemplate& grain, double youngs_modulus) {
  const double areal_density = grain.spheres_per_face() / grain.solid().face_area();
  return youngs_modulus / (areal_density * grain.geometry().size);
}

double effective_modulus(double youngs_modulus, double poisson_ratio) {
  return youngs_modulus / (2 * (1 - poisson_ratio * poisson_ratio));
}

// hooke keeps the paper's calibration (k_n from the face, eqs. 5, 6, 8); the Hertz family takes the grains' material
// as LAMMPS' hertz/material does (k_N = 4/3 E*), or k_N itself (hertz; 4/3 E* when not set). linear_history's k_t stays the ratio of the
// calibrated k_n (N/m) whatever the normal law; mindlin's is 8 G*, 1/G* = 2 (2 - nu) / G = 4 (2 - nu) (1 + nu) / E
// for two spheres of one material (Mindlin 1949; LAMMPS' default for mindlin with k_t NULL).
ContactLaw contact_law(const GrainTemplate& grain, const Material& material) {
  const InterfaceLaw& i = material.contact;
  const double e = material.youngs_modulus, nu = i.poisson_ratio;
  const double hooke_kn = normal_stiffness(grain, e);
  ContactLaw law;
  law.normal = i.normal;
  law.tangential = i.tangential;
  law.effective_modulus = effective_modulus(e, nu);
  law.surface_energy = law.cohesive() ? i.surface_energy : 0.0;
  law.normal_stiffness = i.normal == NormalModel::hooke   ? hooke_kn
                         : i.normal == NormalModel::hertz && i.hertz_stiffness > 0 ? i.hertz_stiffness
                                                          : 4.0 / 3 * law.effective_modulus;
  law.tangential_stiffness = i.tangential == TangentialModel::mindlin ? 2 * e / ((2 - nu) * (1 + nu))
                                                                      : material.tangential_stiffness_ratio * hooke_kn;
  law.damping_ratio = material.damping;
  law.friction = material.friction;
  return law;
}

double contact_time_scale(const GrainTemplate& grain, double youngs_modulus, double density) {
  const double face_stiffness = youngs_modulus * grain.solid().face_area() / grain.geometry().size;
  return std::sqrt(density * grain.volume() / face_stiffness);
}

}  // namespace granulab
