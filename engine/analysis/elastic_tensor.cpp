#include "engine/analysis/elastic_tensor.h"

#include <algorithm>
#include <cmath>

namespace granulab {

namespace {

constexpr int kPair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};

// The 3x3x3x3 tensor of a Voigt stiffness and back (the stiffness's entries need no factors: with engineering
// shear strains, C_IJ = C_ijkl for I = (ij), J = (kl)).
using Tensor4 = double[3][3][3][3];

void to_tensor(const Voigt& c, Tensor4& t) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) t[i][j][k][l] = c(voigt_index(i, j), voigt_index(k, l));
}

double triple_mean_diagonal(const Voigt& c) { return (std::abs(c(0, 0)) + std::abs(c(1, 1)) + std::abs(c(2, 2))) / 3; }

}  // namespace

int voigt_index(int i, int j) {
  if (i == j) return i;
  return 6 - i - j;  // (1,2) -> 3, (0,2) -> 4, (0,1) -> 5
}

Voigt6 stress_voigt(const Mat3& s) {
  Voigt6 v;
  for (int k = 0; k < 6; ++k) v[k] = 0.5 * (s(kPair[k][0], kPair[k][1]) + s(kPair[k][1], kPair[k][0]));
  return v;
}

Mat3 strain_tensor(const Voigt6& e) {
  Mat3 m;
  m << e[0], e[5] / 2, e[4] / 2, e[5] / 2, e[1], e[3] / 2, e[4] / 2, e[3] / 2, e[2];
  return m;
}

Voigt rotate_stiffness(const Voigt& c, const Mat3& q) {
  Tensor4 t;
  to_tensor(c, t);
  // C'_abcd = q_ai q_bj q_ck q_dl C_ijkl, one index at a time.
  Tensor4 u;
  for (int pass = 0; pass < 4; ++pass) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int cc = 0; cc < 3; ++cc)
          for (int d = 0; d < 3; ++d) {
            double s = 0;
            for (int m = 0; m < 3; ++m) {
              const int idx[4] = {a, b, cc, d};
              int src[4] = {a, b, cc, d};
              src[pass] = m;
              s += q(idx[pass], m) * t[src[0]][src[1]][src[2]][src[3]];
            }
            u[a][b][cc][d] = s;
          }
    std::copy(&u[0][0][0][0], &u[0][0][0][0] + 81, &t[0][0][0][0]);
  }
  Voigt out;
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J) out(I, J) = t[kPair[I][0]][kPair[I][1]][kPair[J][0]][kPair[J][1]];
  return out;
}

double directional_modulus(const Voigt& c, const Vec3& d_in) {
  const Vec3 d = d_in.normalized();
  const Voigt6 sigma = stress_voigt(d * d.transpose());
  const Eigen::FullPivLU<Voigt> lu(c);
  if (!lu.isInvertible()) return 0;
  const Voigt6 e = lu.solve(sigma);
  const double along = d.dot(strain_tensor(e) * d);
  return along > 0 ? 1 / along : 0;
}

double symmetry_error(const Voigt& c) {
  const double largest = c.cwiseAbs().maxCoeff();
  return largest > 0 ? (c - c.transpose()).cwiseAbs().maxCoeff() / largest : 0;
}

double cubic_spread(const Voigt& c) {
  const double scale = triple_mean_diagonal(c);
  if (!(scale > 0)) return 0;
  const double triples[3][3] = {{c(0, 0), c(1, 1), c(2, 2)},
                                {(c(0, 1) + c(1, 0)) / 2, (c(0, 2) + c(2, 0)) / 2, (c(1, 2) + c(2, 1)) / 2},
                                {c(3, 3), c(4, 4), c(5, 5)}};
  double spread = 0;
  for (const auto& t : triples) spread = std::max(spread, *std::max_element(t, t + 3) - *std::min_element(t, t + 3));
  return spread / scale;
}

double cubic_off_pattern(const Voigt& c) {
  const double scale = triple_mean_diagonal(c);
  double largest = 0;
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J) {
      const bool normal_block = I < 3 && J < 3, shear_diagonal = I >= 3 && I == J;
      if (!normal_block && !shear_diagonal) largest = std::max(largest, std::abs(c(I, J)));
    }
  return scale > 0 ? largest / scale : 0;
}

double zener_ratio(const Voigt& c) {
  const double c11 = (c(0, 0) + c(1, 1) + c(2, 2)) / 3;
  const double c12 = (c(0, 1) + c(0, 2) + c(1, 2) + c(1, 0) + c(2, 0) + c(2, 1)) / 6;
  const double c44 = (c(3, 3) + c(4, 4) + c(5, 5)) / 3;
  return c11 != c12 ? 2 * c44 / (c11 - c12) : 0;
}

Voigt affine_face_spring_stiffness(const std::vector<FaceSpringTerm>& faces, double volume) {
  Tensor4 t = {};
  const auto delta = [](int i, int j) { return i == j ? 1.0 : 0.0; };
  for (const FaceSpringTerm& f : faces) {
    const Vec3& n = f.normal;
    const double w = f.branch * f.branch / (2 * volume), kn = f.normal_stiffness, kt = f.tangential_stiffness;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l)
            t[i][j][k][l] += w * ((kn - kt) * n[i] * n[j] * n[k] * n[l] +
                                  kt * (delta(i, k) * n[j] * n[l] + delta(i, l) * n[j] * n[k] + delta(j, k) * n[i] * n[l] +
                                        delta(j, l) * n[i] * n[k]) / 4);
  }
  Voigt out;
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J) out(I, J) = t[kPair[I][0]][kPair[I][1]][kPair[J][0]][kPair[J][1]];
  return out;
}

}  // namespace granulab
