// Material parameters and the model numbers derived from them without fitting (docs/model.md, "Contact law", "Time integration"):
//   k_n = E / (rho_s * size), rho_s = N_f / A_face          (paper eqs. 5, 6, 8; cube: k_n = E l / N_f)
//   t0  = sqrt(m_grain / K_face), K_face = E A_face / size,  dt = factor * t0
// The time step does not depend on N_e: k_n ~ 1/N_e^2 while the contacts per face grow as N_e^2.
#pragma once

#include "engine/contact/contact_law.h"
#include "engine/geometry/grain_template.h"

namespace granulab {

struct Material {
  double youngs_modulus = 3.0e9;                ///< E of the grain material (Pa)
  double density = 1200;                        ///< kg/m^3
  double friction = 0.35;                       ///< Coulomb coefficient between spheres and on walls
  double tangential_stiffness_ratio = 2.0 / 7;  ///< k_t / k_n
  double damping = 0.05;                        ///< damping ratio zeta of one sphere pair
};

/// k_n (N/m) for the given grain and modulus.
double normal_stiffness(const GrainTemplate& grain, double youngs_modulus);
/// The contact law of `material` on `grain`.
ContactLaw contact_law(const GrainTemplate& grain, const Material& material);
/// t0 = sqrt(m / K_face) with m = density * volume (s).
double contact_time_scale(const GrainTemplate& grain, double youngs_modulus, double density);

}  // namespace granulab
