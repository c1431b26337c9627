#include "engine/world/open_pairs.h"

#include <cmath>

namespace granulab {

namespace {

// Rounding in the poses and distances is ~1e-16 of the grains' coordinates; a gap below a millionth of a sphere
// diameter is not worth keeping, and the margin covers the rounding many times over.
constexpr double kMargin = 1e-6;

}  // namespace

void OpenPairs::reset(std::size_t n) {
  gap_.assign(n, 0.0);
  t0_.resize(n);
  q0_.resize(n);
}

bool OpenPairs::closed_off(std::size_t p, const Bodies& bodies, BodyId a, BodyId b) const {
  if (!(gap_[p] > 0)) return false;
  const Quat qa_inv = bodies.orientation[a].conjugate();
  const Vec3 t = qa_inv * (bodies.position[b] - bodies.position[a]);
  const Quat dq = q0_[p].conjugate() * (qa_inv * bodies.orientation[b]);
  return (t - t0_[p]).norm() + 2 * reach_ * dq.vec().norm() < gap_[p];
}

void OpenPairs::evaluated(std::size_t p, const Bodies& bodies, BodyId a, BodyId b, std::uint32_t contacts,
                          double nearest2, double diameter) {
  const bool apart = contacts == 0 && nearest2 > 0 && std::isfinite(nearest2);
  const double gap = apart ? std::sqrt(nearest2) - diameter * (1 + kMargin) : 0.0;
  gap_[p] = gap > 0 ? gap : 0.0;
  if (gap_[p] == 0) return;
  const Quat qa_inv = bodies.orientation[a].conjugate();
  t0_[p] = qa_inv * (bodies.position[b] - bodies.position[a]);
  q0_[p] = qa_inv * bodies.orientation[b];
}

}  // namespace granulab
