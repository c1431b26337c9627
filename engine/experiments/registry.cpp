// The table of experiments. To add one: a folder engine/experiments/<name>/ with its parameters, run
// loop, results and a make_<name>() factory, and one row here (docs/architecture.md).
#include "engine/experiments/registry.h"

#include "engine/experiments/crystal_compression/crystal_compression_experiment.h"
#include "engine/experiments/crystal_confinement/crystal_confinement.h"
#include "engine/experiments/crystal_shear/crystal_shear_experiment.h"
#include "engine/experiments/crystal_stiffness/crystal_stiffness_experiment.h"
#include "engine/experiments/crystal_tension/crystal_tension_experiment.h"
#include "engine/experiments/two_cube_sliding/two_cube_sliding_experiment.h"

namespace granulab {

const std::vector<ExperimentType>& experiment_types() {
  static const std::vector<ExperimentType> types = {
      {"two_cube_sliding", "two cubes sliding face to face under a pre-strain (paper section 3, Figs. 3-5)",
       make_two_cube_sliding},
      {"crystal_compression",
       "an FCC crystal of rhombic dodecahedra confined by a vacuum bag and compressed between two platens "
       "(paper sections 4-6, Figs. 6-12)",
       make_crystal_compression},
      {"crystal_confinement",
       "the crystal sample of crystal_compression confined by the vacuum bag and the servo-controlled platens "
       "alone, its approach to equilibrium recorded at every check (paper section 4)",
       make_crystal_confinement},
      {"crystal_shear",
       "a slab of any crystal sheared on a lattice plane along a direction in it, between rigid layers of its own "
       "grains, under a constant normal stress, in the bag (beyond the paper: the slip law of one slip system)",
       make_crystal_shear},
      {"crystal_stiffness",
       "the elastic tensor of any confined crystal: small strains imposed on its boundary grains, the interior "
       "relaxed and not, the stress from the contact forces (beyond the paper: its \"too stiff\" in numbers)",
       make_crystal_stiffness},
      {"crystal_tension",
       "any crystal pulled apart along its axis between grips of its own end grains, in the bag or bare (beyond the "
       "paper: the cohesive crystals of contact.normal dmt and jkr carry tension, the paper's do not)",
       make_crystal_tension},
  };
  return types;
}

const ExperimentType* find_experiment_type(const std::string& name) {
  for (const ExperimentType& t : experiment_types())
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace granulab
