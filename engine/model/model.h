// Material parameters and the model numbers derived from them without fitting (docs/model.md, "Contact law", "Time integration"):
//   k_n = E / (rho_s * size), rho_s = N_f / A_face          (paper eqs. 5, 6, 8; cube: k_n = E l / N_f)
//   t0  = sqrt(m_grain / K_face), K_face = E A_face / size,  dt = factor * t0
// The time step does not depend on N_e: k_n ~ 1/N_e^2 while the contacts per face grow as N_e^2.
#pragma once

#include "engine/contact/contact_law.h"
#include "engine/geometry/grain_template.h"

namespace granulab {

/// The interface law between grains (the "contact" section), with LAMMPS pair_style granular's names.
struct InterfaceLaw {
  NormalModel normal = NormalModel::hooke;
  TangentialModel tangential = TangentialModel::linear_history;
  double poisson_ratio = 0.3;    ///< nu of the grains' material (hertz/material, dmt, jkr, mindlin)
  double surface_energy = 0;     ///< gamma (J/m^2), dmt and jkr
  double hertz_stiffness = 0;    ///< k_N of `hertz` (Pa); 0: 4/3 E* of the material (the spec default)
};

/// E* = E / (2 (1 - nu^2)) of two spheres of one material (Pa).
double effective_modulus(double youngs_modulus, double poisson_ratio);

struct Material {
  double youngs_modulus = 3.0e9;                ///< E of the grain material (Pa)
  double density = 1200;                        ///< kg/m^3
  double friction = 0.35;                       ///< Coulomb coefficient between spheres and on walls
  double tangential_stiffness_ratio = 2.0 / 7;  ///< k_t / k_n
  double damping = 0.05;                        ///< damping ratio zeta of one sphere pair
  InterfaceLaw contact;                         ///< the law between spheres of different grains
};

/// k_n (N/m) for the given grain and modulus.
double normal_stiffness(const GrainTemplate& grain, double youngs_modulus);
/// The contact law of `material` on `grain`.
ContactLaw contact_law(const GrainTemplate& grain, const Material& material);
/// t0 = sqrt(m / K_face) with m = density * volume (s).
double contact_time_scale(const GrainTemplate& grain, double youngs_modulus, double density);

}  // namespace granulab
