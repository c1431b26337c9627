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

}  // namespace granulab
