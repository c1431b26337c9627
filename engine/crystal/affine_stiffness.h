// The affine elastic tensor of a crystal sample from its faces as springs (face_springs.h; derived in
// docs/derivations/affine_stiffness.md): what the stiffness experiment measures against, and the upper bound a compression
// reports beside its apparent modulus (every grain following the strain, no face opening or sliding).
#pragma once

#include "engine/analysis/elastic_tensor.h"
#include "engine/crystal/crystal_sample.h"

namespace granulab {

/// The affine face-spring prediction for the sample's lattice and grain (crystal frame, Pa; face_springs.h): each face
/// N_f aligned pairs, N_f the sphere pairs that touch the neighbour across it (touching_pairs).
Voigt affine_prediction(const CrystalSampleParams& p);

/// Young's modulus of that tensor along the sample's compression axis (Pa): the stress along the axis over the
/// strain along it with the lateral stresses held, as a bag holds them.
double affine_axial_modulus(const CrystalSampleParams& p);

}  // namespace granulab
