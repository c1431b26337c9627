// Convex polyhedra whose faces are parallelograms, each face at the same distance from the centre:
// the cube and the rhombic dodecahedron (docs/model.md, "Grains"). Because every face is at distance h,
// the "inner" polyhedron on which sphere centres lie (every face recessed by d/2) is the outer one
// scaled by (h - d/2)/h about the centre.
#pragma once

#include <string>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

enum class Shape { cube, rhombic_dodecahedron };

std::string to_string(Shape shape);

/// A parallelogram face: corner, corner + edge_a, corner + edge_a + edge_b, corner + edge_b.
struct Face {
  Vec3 corner;
  Vec3 edge_a;
  Vec3 edge_b;
  Vec3 normal;  ///< outward unit normal
};

/// Mass properties of the homogeneous solid (density 1 unless scaled by the caller).
struct MassProperties {
  double volume = 0;                        ///< m^3
  Vec3 centroid = Vec3::Zero();             ///< m
  Mat3 inertia_per_density = Mat3::Zero();  ///< kg m^2 per (kg/m^3), about the centroid
};

class Polyhedron {
 public:
  /// Cube of side `size` or rhombic dodecahedron whose FCC cubic cell is `size` (m), centred at the origin.
  static Polyhedron make(Shape shape, double size);

  Shape shape() const { return shape_; }
  double size() const { return size_; }
  const std::vector<Face>& faces() const { return faces_; }
  /// Distance from the centre to every face plane (m).
  double inradius() const { return inradius_; }
  /// Length of every edge (m).
  double edge_length() const { return faces_.front().edge_a.norm(); }
  double face_area() const;
  /// Largest distance from the centre to a vertex (m).
  double circumradius() const;
  /// True when `p` is inside or on the surface, with tolerance `tol` (m).
  bool contains(const Vec3& p, double tol = 0) const;
  /// Volume, centroid and inertia tensor, exact (tetrahedral decomposition about the centre).
  MassProperties mass_properties() const;

 private:
  Shape shape_ = Shape::cube;
  double size_ = 0;
  double inradius_ = 0;
  std::vector<Face> faces_;
};

}  // namespace granulab
