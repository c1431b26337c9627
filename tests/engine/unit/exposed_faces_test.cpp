// exposed_face_areas (engine/crystal/exposed_faces.h): which faces of a crystal's grains its surface exposes,
// checked against a brute-force neighbour search and against the closed surface's zero vector area.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/crystal/exposed_faces.h"
#include "engine/crystal/sample_parameters.h"

namespace granulab {
namespace {

constexpr double kSize = 0.01, kPrestrain = 3e-5;

CrystalLattice lattice(int x, int z, int y, std::vector<GrainId> knockouts = {}) {
  CrystalGeometry g;
  g.size = kSize, g.prestrain = kPrestrain;
  g.grains_x = x, g.rows_z = z, g.layers_y = y;
  g.knockout_ids = std::move(knockouts);
  return build_crystal(g);
}

const Polyhedron& rd() {
  static const Polyhedron p = Polyhedron::make(Shape::rhombic_dodecahedron, kSize);
  return p;
}

TEST(ExposedFaces, AgreeWithABruteForceSearchForMissingNeighbours) {
  const CrystalLattice c = lattice(3, 7, 4);
  const std::vector<ExposedArea> exposed = exposed_face_areas(c, rd(), (1 - kPrestrain) * kSize);
  const Mat3 r = c.orientation.toRotationMatrix();
  const double spacing = (1 - kPrestrain) * kSize / std::sqrt(2.0);
  int surface = 0;
  for (std::size_t i = 0; i < c.sites.size(); ++i) {
    // Without knock-outs a face is exposed exactly when no grain sits across it.
    Vec3 expected = Vec3::Zero();
    for (const Face& f : rd().faces()) {
      const Vec3 there = c.sites[i].position + spacing * (r * f.normal);
      bool present = false;
      for (const LatticeSite& s : c.sites) present |= (s.position - there).norm() < spacing / 4;
      if (!present) expected += f.edge_a.cross(f.edge_b).norm() * (r * f.normal);
    }
    const Vec3 got = exposed[i].lateral + exposed[i].end;
    EXPECT_LT((got - expected).norm(), 1e-12 * rd().face_area()) << "site " << i;
    surface += expected.norm() > 0 || got.norm() > 0;
  }
  EXPECT_GT(surface, 0);
  EXPECT_LT(surface, int(c.sites.size()));  // 3 x 7 x 4 has interior grains
}

TEST(ExposedFaces, AddUpToZeroOverTheClosedSurfaceWithEndsOnTheEnds) {
  for (const CrystalLattice& c : {lattice(3, 7, 4), lattice(8, 18, 6), lattice(1, 1, 1)}) {
    const std::vector<ExposedArea> exposed = exposed_face_areas(c, rd(), (1 - kPrestrain) * kSize);
    Vec3 total = Vec3::Zero();
    double top = 0, bottom = 0;
    for (std::size_t i = 0; i < exposed.size(); ++i) {
      total += exposed[i].lateral + exposed[i].end;
      (exposed[i].end.z() > 0 ? top : bottom) += std::abs(exposed[i].end.z());
    }
    EXPECT_LT(total.norm(), 1e-12 * rd().face_area() * c.sites.size());
    // Each end's axial area is that of the lattice's cross-section within the grains' overhang at its rim.
    const double cross_section = c.extent.x() * c.extent.y();
    if (c.sites.size() > 1) {
      EXPECT_NEAR(top / cross_section, 1, 0.3);
      EXPECT_NEAR(bottom / cross_section, 1, 0.3);
    }
  }
}

TEST(ExposedFaces, AHoleExposesNothing) {
  // Knocking out an interior grain leaves every other grain's exposed faces as they were: the bag spans holes.
  const CrystalLattice full = lattice(4, 8, 3), holed = lattice(4, 8, 3, {GrainId((1 * 8 + 4) * 4 + 1)});
  ASSERT_EQ(holed.sites.size() + 1, full.sites.size());
  const std::vector<ExposedArea> a = exposed_face_areas(full, rd(), (1 - kPrestrain) * kSize);
  const std::vector<ExposedArea> b = exposed_face_areas(holed, rd(), (1 - kPrestrain) * kSize);
  std::size_t j = 0;
  for (std::size_t i = 0; i < full.sites.size(); ++i) {
    if (j < holed.sites.size() && holed.sites[j].id == full.sites[i].id) {
      EXPECT_LT((a[i].lateral - b[j].lateral).norm() + (a[i].end - b[j].end).norm(), 1e-15) << "site " << i;
      ++j;
    } else {
      EXPECT_EQ((a[i].lateral + a[i].end).norm(), 0) << "the knocked-out grain was an interior one";
    }
  }
}

}  // namespace
}  // namespace granulab
