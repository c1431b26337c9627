// A crystal's elastic tensor in Voigt form (docs/model.md, "Crystal stiffness"): C (Pa) with sigma = C eps, the
// order xx, yy, zz, yz, xz, xy, the shear strains engineering ones (gamma_yz = 2 eps_yz), tension positive. Its
// rotation between frames, Young's modulus along a direction, its symmetries, and the affine prediction of the
// face springs (face_springs.h; derived in docs/derivations/affine_stiffness.md).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

using Voigt = Eigen::Matrix<double, 6, 6>;
using Voigt6 = Eigen::Matrix<double, 6, 1>;

/// The Voigt index of the tensor pair (i, j), i, j in 0..2.
int voigt_index(int i, int j);
/// A symmetric stress tensor as a Voigt vector (Pa).
Voigt6 stress_voigt(const Mat3& s);
/// The symmetric strain tensor of Voigt (engineering) strain `e` (-).
Mat3 strain_tensor(const Voigt6& e);

/// C given in frame A, expressed in frame B, where `q` takes a vector's A components to its B components.
Voigt rotate_stiffness(const Voigt& c, const Mat3& q);
/// Young's modulus along unit direction `d` (Pa): the uniaxial stress over the strain along d; 0 when C is singular.
double directional_modulus(const Voigt& c, const Vec3& d);
/// max |C_ij - C_ji| / max |C_ij| (-).
double symmetry_error(const Voigt& c);
/// The largest relative spread of the cubic triples (C11, C22, C33), (C12, C13, C23), (C44, C55, C66), each triple's
/// (max - min) over the mean of |C11|, |C22|, |C33| (-): zero for a cubic tensor in its cubic frame.
double cubic_spread(const Voigt& c);
/// The largest entry a cubic tensor has zero (C14 ... C56 and the like) over the mean of |C11|, |C22|, |C33| (-).
double cubic_off_pattern(const Voigt& c);
/// Zener's anisotropy ratio 2 C44 / (C11 - C12) of the cubic triples' means (-).
double zener_ratio(const Voigt& c);

/// One face of a grain as a spring pair between neighbour centres: unit normal (the tensor's frame), branch l (m),
/// its normal and tangential stiffness K_n, K_t (N/m).
struct FaceSpringTerm {
  Vec3 normal;
  double branch = 0, normal_stiffness = 0, tangential_stiffness = 0;
};
/// The affine (unrelaxed) tensor of a crystal whose grains of volume `volume` (m^3) each have the faces `faces`:
/// C_ijkl = 1/(2V) sum_f l_f^2 [(K_n - K_t) n_i n_j n_k n_l + K_t (d_ik n_j n_l + d_il n_j n_k + d_jk n_i n_l +
/// d_jl n_i n_k) / 4] (Pa). Several kinds of site (HCP's A and B): their faces together, `volume` times the kinds.
Voigt affine_face_spring_stiffness(const std::vector<FaceSpringTerm>& faces, double volume);

}  // namespace granulab
