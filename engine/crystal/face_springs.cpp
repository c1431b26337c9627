#include "engine/crystal/face_springs.h"

#include <cmath>

namespace granulab {

std::vector<FaceSpring> face_springs(const GrainTemplate& grain) {
  std::vector<FaceSpring> out;
  for (const Face& f : grain.solid().faces()) {
    FaceSpring s{f.normal, 2 * f.distance, 0};
    // Under the face: the sphere's surface reaches the face's plane (to round-off of the template's grid).
    for (const Vec3& o : grain.offsets())
      if (std::abs(o.dot(f.normal) + grain.radius() - f.distance) <= 1e-6 * grain.spacing()) ++s.pairs;
    out.push_back(s);
  }
  return out;
}

long touching_pairs(const GrainTemplate& grain, const Quat& turn_a, const Quat& turn_b, const Vec3& branch) {
  const Vec3 n = branch.normalized();
  const double h = branch.norm() / 2, d = grain.diameter(), near = h - d;
  // Only the spheres next to the faces can touch: within a diameter of the mid-plane.
  std::vector<Vec3> a, b;
  for (const Vec3& o : grain.offsets()) {
    const Vec3 x = turn_a * o, y = branch + turn_b * o;
    if (x.dot(n) > near) a.push_back(x);
    if ((branch - y).dot(n) > near) b.push_back(y);
  }
  long touching = 0;
  for (const Vec3& x : a)
    for (const Vec3& y : b) touching += (y - x).norm() < d * (1 + 1e-6);
  return touching;
}

}  // namespace granulab
