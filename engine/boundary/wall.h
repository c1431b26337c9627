// A rigid plane wall with prescribed motion (docs/model.md, "Contact law": walls use the sphere contact law and friction;
// their motion is prescribed; the force on a wall is the sum of the contact forces it receives).
#pragma once

#include <cstddef>

#include "engine/core/types.h"

namespace granulab {

struct Wall {
  Vec3 point = Vec3::Zero();     ///< a point of the plane (m)
  Vec3 normal = Vec3::UnitZ();   ///< unit normal pointing into the granular domain
  Vec3 velocity = Vec3::Zero();  ///< prescribed (m/s)
  Vec3 force = Vec3::Zero();     ///< force received from the spheres in the last step (N)
  std::size_t contacts = 0;      ///< spheres touching it in the last step
  double friction = -1;          ///< Coulomb coefficient on this wall; negative: the contact law's

  /// Signed distance of p from the plane, positive on the domain side (m).
  double distance(const Vec3& p) const { return (p - point).dot(normal); }
};

}  // namespace granulab
