#include "engine/model/model.h"

#include <cmath>

namespace granulab {

double normal_stiffness(const GrainTemplate& grain, double youngs_modulus) {
  const double areal_density = grain.spheres_per_face() / grain.solid().face_area();
  return youngs_modulus / (areal_density * grain.geometry().size);
}

ContactLaw contact_law(const GrainTemplate& grain, const Material& material) {
  ContactLaw law;
  law.normal_stiffness = normal_stiffness(grain, material.youngs_modulus);
  law.tangential_stiffness = material.tangential_stiffness_ratio * law.normal_stiffness;
  law.damping_ratio = material.damping;
  law.friction = material.friction;
  return law;
}

double contact_time_scale(const GrainTemplate& grain, double youngs_modulus, double density) {
  const double face_stiffness = youngs_modulus * grain.solid().face_area() / grain.geometry().size;
  return std::sqrt(density * grain.volume() / face_stiffness);
}

}  // namespace granulab
