// A grain template: the body-frame sphere clump of one grain shape, shared (flyweight) by every grain
// of that shape in a simulation. Sphere centres lie on the inner polyhedron (faces recessed by d/2),
// N_e on every edge of the reference family with spacing s = d(1-kappa), spaced about s on every other edge
// and face (docs/model.md, "Grains").
#pragma once

#include <vector>

#include "engine/core/types.h"
#include "engine/geometry/polyhedron.h"

namespace granulab {

struct GrainGeometry {
  Shape shape = Shape::rhombic_dodecahedron;
  double size = 0.01;     ///< the cubic cell a (m): cube side, FCC, BCC, or the FCC cell of HCP's grains
  int edge_spheres = 10;  ///< N_e >= 2 on the reference edges: every edge (cube, RD), rhombus edges (TRD),
                          ///< hexagon-hexagon edges (truncated octahedron)
  double overlap = 0.75;  ///< kappa in [0, 1)
};

/// Sphere diameter d (m): cube eq. 2, d = l/((N_e-1)(1-kappa)+1); RD (docs/model.md, "Grains": our reading of eq. 7)
/// and TRD, d = a/((4/sqrt3)(N_e-1)(1-kappa) + sqrt2); truncated octahedron,
/// d = (sqrt2 a/4) / ((N_e-1)(1-kappa) + sqrt2 (1 - sqrt3/2)).
double sphere_diameter(const GrainGeometry& g);
/// Spheres in one clump. Closed form for the cube, 6m^2 + 12m + 8, and the RD, 12m^2 + 24m + 14, with
/// m = N_e - 2 (each vertex and edge sphere counted once), without building it; the other grains' clumps are
/// built and counted. 0 for parameters the template refuses.
long sphere_count(const GrainGeometry& g);

class GrainTemplate {
 public:
  /// Builds the clump; throws std::invalid_argument on N_e < 2, kappa outside [0,1) or size <= 0.
  explicit GrainTemplate(const GrainGeometry& g);

  const GrainGeometry& geometry() const { return geometry_; }
  const Polyhedron& solid() const { return solid_; }
  /// Body-frame sphere centres relative to the centroid (m). Index = LocalSphereId.
  const std::vector<Vec3>& offsets() const { return offsets_; }
  std::size_t sphere_count() const { return offsets_.size(); }
  double diameter() const { return diameter_; }
  double radius() const { return diameter_ / 2; }
  /// Centre spacing along edges and face grids, s = d(1-kappa) (m).
  double spacing() const { return spacing_; }
  /// N_f: spheres whose centres lie under the reference face (Polyhedron::reference_face): N_e^2 on a
  /// parallelogram of N_e per edge.
  int spheres_per_face() const { return spheres_per_face_; }
  /// Largest |offset| + d/2 (m): a sphere bounding the whole clump.
  double bounding_radius() const { return bounding_radius_; }
  double volume() const { return volume_; }
  /// Principal moments of inertia per unit density (m^5); the body frame is principal.
  const Vec3& principal_inertia_per_density() const { return principal_inertia_; }

 private:
  void build_parallelogram_clump();  // the cube's and the RD's, as they always were built
  void finish();                     // mass properties and bounding radius
  GrainGeometry geometry_;
  Polyhedron solid_;
  int spheres_per_face_ = 0;
  double diameter_ = 0, spacing_ = 0, bounding_radius_ = 0, volume_ = 0;
  Vec3 principal_inertia_ = Vec3::Zero();
  std::vector<Vec3> offsets_;
};

}  // namespace granulab
