// Convex polyhedra: the space-filling grains of the crystals (docs/model.md, "Grains"), each the Voronoi cell
// of its lattice site: the cube (simple cubic), the rhombic dodecahedron (FCC), the truncated octahedron (BCC)
// and the trapezo-rhombic dodecahedron (ideal HCP). A face is any convex polygon; the cube and the rhombic
// dodecahedron keep their parallelogram description, from which today's clumps are built bit for bit.
#pragma once

#include <string>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

enum class Shape { cube, rhombic_dodecahedron, truncated_octahedron, trapezo_rhombic_dodecahedron };

std::string to_string(Shape shape);
/// The shape named `name` (as to_string writes it); false when there is none.
bool shape_from_string(const std::string& name, Shape& shape);

/// A convex polygonal face. Its vertices run counter-clockwise seen from outside; corner, edge_a and edge_b
/// are vertices[0], vertices[1] - vertices[0] and vertices.back() - vertices[0] (for a parallelogram the
/// face is corner, corner + edge_a, corner + edge_a + edge_b, corner + edge_b).
struct Face {
  Vec3 corner;
  Vec3 edge_a;
  Vec3 edge_b;
  Vec3 normal;                ///< outward unit normal
  double distance = 0;        ///< normal . x of every point of the face (m)
  std::vector<Vec3> vertices; ///< m
  bool parallelogram = false;
  double area() const;        ///< m^2
  Vec3 centre() const;        ///< the mean of the vertices (m)
  /// The area centroid (m): where a uniform pressure on the face acts (the mean of the vertices is not, on a
  /// trapezoid).
  Vec3 centroid() const;
};

/// Mass properties of the homogeneous solid (density 1 unless scaled by the caller).
struct MassProperties {
  double volume = 0;                        ///< m^3
  Vec3 centroid = Vec3::Zero();             ///< m
  Mat3 inertia_per_density = Mat3::Zero();  ///< kg m^2 per (kg/m^3), about the centroid
};

class Polyhedron {
 public:
  /// The grain of `shape` whose cubic cell is `size` (m), centred on its site, in the crystal's frame: the
  /// cube of side a; the rhombic dodecahedron of FCC cell a; the truncated octahedron of BCC cell a; the
  /// trapezo-rhombic dodecahedron of ideal HCP with nearest-neighbour distance D = a / sqrt2 (the FCC
  /// grain's, so that the two close-packed crystals share their grains), c axis along z, a1 along x.
  static Polyhedron make(Shape shape, double size);
  /// The convex polyhedron {x : n_k . x <= h_k}, its faces in the order of the planes that bound one
  /// (planes that touch it in an edge or vertex only are dropped). Throws std::invalid_argument when the
  /// planes do not bound a solid around the origin.
  static Polyhedron from_planes(Shape shape, double size, const std::vector<Vec3>& normals,
                                const std::vector<double>& distances);

  Shape shape() const { return shape_; }
  double size() const { return size_; }
  const std::vector<Face>& faces() const { return faces_; }
  /// Every face plane moved in by `depth` (m), face k of the result lying under face k of this one. The inner
  /// polyhedron of a clump (depth d/2). Throws std::invalid_argument when a face vanishes.
  Polyhedron recessed(double depth) const;
  /// Smallest distance from the centre to a face plane (m).
  double inradius() const { return inradius_; }
  /// Length of the first face's first edge (m): every edge for the cube and the rhombic dodecahedron.
  double edge_length() const { return faces_.front().edge_a.norm(); }
  /// The face whose stiffness sets the contact law (model.h): the first face for the cube and the rhombic
  /// dodecahedron, the first hexagon of the truncated octahedron (nearest neighbours), the first rhombus of
  /// the trapezo-rhombic dodecahedron (the rhombic dodecahedron's own face).
  const Face& reference_face() const { return faces_[reference_]; }
  double face_area() const { return reference_face().area(); }
  /// The distinct vertices (m).
  const std::vector<Vec3>& vertices() const { return vertices_; }
  /// Largest distance from the centre to a vertex (m).
  double circumradius() const;
  /// True when `p` is inside or on the surface, with tolerance `tol` (m).
  bool contains(const Vec3& p, double tol = 0) const;
  /// Volume, centroid and inertia tensor, exact (tetrahedral decomposition about the centre).
  MassProperties mass_properties() const;

 private:
  void finish();
  Shape shape_ = Shape::cube;
  double size_ = 0;
  double inradius_ = 0;
  std::size_t reference_ = 0;
  std::vector<Face> faces_;
  std::vector<Vec3> vertices_;
};

}  // namespace granulab
