// The grains of the four crystals (docs/model.md, "Grains") against the lattices they tile, rebuilt here
// from their textbook definitions rather than from the engine's planes:
//  - every vertex of a grain is a Voronoi vertex of its site: no lattice site is nearer to it than the site
//    itself, and at least three others are as near; with the right vertex count and volume x number
//    density = 1, the grain is the whole Voronoi cell (a convex hull of Voronoi vertices of the cell is
//    inside it, and an equal volume leaves nothing out);
//  - every sphere of a clump touches the face plane it lies under and none pokes out of the grain;
//  - across the face two neighbouring grains share, their spheres sit opposite each other (the contact's
//    in-line pairs), which is what the clump rule is built for;
//  - the sphere counts of the trapezo-rhombic dodecahedron, counted by hand for N_e = 4 and 7.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "engine/geometry/grain_template.h"

namespace granulab {
namespace {

constexpr double kA = 0.01;  // m, the cubic cell
// Vertices come from 3x3 solves on O(a) data: rounding ~1e-16 a, so 1e-12 a leaves a wide margin.
constexpr double kTol = 1e-12 * kA;

struct Lattice {
  Shape shape;
  std::vector<Vec3> sites;  // every site within a few cells of the origin, the origin included
  double number_density;    // sites per m^3
  std::size_t vertices;
};

Lattice lattice(Shape shape) {
  Lattice l{shape, {}, 0, 0};
  std::vector<Vec3> basis;
  if (shape == Shape::cube) basis = {Vec3::Zero()}, l.number_density = 1 / std::pow(kA, 3), l.vertices = 8;
  if (shape == Shape::rhombic_dodecahedron) {
    basis = {Vec3::Zero(), Vec3(0, 0.5, 0.5) * kA, Vec3(0.5, 0, 0.5) * kA, Vec3(0.5, 0.5, 0) * kA};
    l.number_density = 4 / std::pow(kA, 3), l.vertices = 14;
  }
  if (shape == Shape::truncated_octahedron) {
    basis = {Vec3::Zero(), Vec3(0.5, 0.5, 0.5) * kA};
    l.number_density = 2 / std::pow(kA, 3), l.vertices = 24;
  }
  if (shape != Shape::trapezo_rhombic_dodecahedron) {
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j)
        for (int k = -3; k <= 3; ++k)
          for (const Vec3& b : basis) l.sites.push_back(Vec3(i, j, k) * kA + b);
    return l;
  }
  // Ideal HCP of nearest-neighbour distance D = a/sqrt2: hexagonal layers A at z = 0 (mod c), B shifted by
  // (a1 + a2)/3 at z = c/2, c = sqrt(8/3) D. A hexagonal prism cell of volume (sqrt3/2) D^2 c holds two sites.
  const double d = kA / std::sqrt(2.0), c = std::sqrt(8.0 / 3.0) * d;
  const Vec3 a1(d, 0, 0), a2(d / 2, d * std::sqrt(3.0) / 2, 0), a3(0, 0, c), b = (a1 + a2) / 3 + a3 / 2;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -3; k <= 3; ++k) {
        const Vec3 p = i * a1 + j * a2 + k * a3;
        l.sites.push_back(p);
        l.sites.push_back(p + b);
      }
  l.number_density = 2 / (std::sqrt(3.0) / 2 * d * d * c);
  l.vertices = 14;
  return l;
}

class VoronoiGrain : public testing::TestWithParam<Shape> {};

TEST_P(VoronoiGrain, IsTheVoronoiCellOfItsSite) {
  const Lattice l = lattice(GetParam());
  const Polyhedron p = Polyhedron::make(GetParam(), kA);
  ASSERT_EQ(p.vertices().size(), l.vertices);
  for (const Vec3& v : p.vertices()) {
    double nearest = 1e300;
    for (const Vec3& s : l.sites)
      if (s.norm() > 0) nearest = std::min(nearest, (v - s).norm());
    EXPECT_NEAR(nearest, v.norm(), kTol) << "vertex " << v.transpose() / kA << " (in a)";
    const long equidistant = std::count_if(l.sites.begin(), l.sites.end(), [&](const Vec3& s) {
      return s.norm() > 0 && std::abs((v - s).norm() - v.norm()) <= kTol;
    });
    EXPECT_GE(equidistant, 3) << "vertex " << v.transpose() / kA;
  }
  // Every face is the bisector of a site: normal along it, at half its distance.
  for (const Face& f : p.faces()) {
    const bool bisector = std::any_of(l.sites.begin(), l.sites.end(), [&](const Vec3& s) {
      return s.norm() > 0 && (s.normalized() - f.normal).norm() < 1e-12 && std::abs(s.norm() / 2 - f.distance) <= kTol;
    });
    EXPECT_TRUE(bisector) << "face normal " << f.normal.transpose();
  }
  const MassProperties mp = p.mass_properties();
  EXPECT_NEAR(mp.volume * l.number_density, 1, 1e-12);
  EXPECT_LT(mp.centroid.norm(), kTol);
}

INSTANTIATE_TEST_SUITE_P(Lattices, VoronoiGrain,
                         testing::Values(Shape::cube, Shape::rhombic_dodecahedron, Shape::truncated_octahedron,
                                         Shape::trapezo_rhombic_dodecahedron),
                         [](const testing::TestParamInfo<Shape>& info) { return to_string(info.param); });

struct ClumpCase {
  Shape shape;
  int edge_spheres;
  double overlap;
};

class VoronoiClump : public testing::TestWithParam<ClumpCase> {};

TEST_P(VoronoiClump, SpheresTouchTheirFacesAndNonePokesOut) {
  const ClumpCase c = GetParam();
  const GrainTemplate t(GrainGeometry{c.shape, kA, c.edge_spheres, c.overlap});
  const double r = t.radius();
  ASSERT_GT(t.sphere_count(), 0u);
  for (const Vec3& o : t.offsets()) {
    double worst = -1e300;
    for (const Face& f : t.solid().faces()) worst = std::max(worst, o.dot(f.normal) + r - f.distance);
    EXPECT_NEAR(worst, 0, kTol) << "sphere at " << o.transpose() / kA;
  }
  // The spacing: no two spheres closer than 0.4 s (a hexagon's lattice nodes keep sqrt3 s / 4 from its edges'
  // spheres), the reference edges cut exactly in s.
  double closest = 1e300;
  for (std::size_t i = 0; i < t.offsets().size(); ++i)
    for (std::size_t j = i + 1; j < t.offsets().size(); ++j)
      closest = std::min(closest, (t.offsets()[i] - t.offsets()[j]).norm());
  EXPECT_GT(closest, 0.4 * t.spacing());
  EXPECT_NEAR(t.spacing(), t.diameter() * (1 - c.overlap), kTol);
}

// Two neighbours across each kind of face: the spheres under the shared face, seen from both grains, pair up
// one to one at distance d (in-line, touching). For the truncated octahedron's hexagons, whose inner faces are
// recessed unequally, the lattice nodes do (the ring along the edges is each grain's own): every node of one
// grain has its partner, and both grains hold as many.
TEST_P(VoronoiClump, NeighboursSpheresFaceEachOtherAcrossASharedFace) {
  const ClumpCase c = GetParam();
  const GrainTemplate t(GrainGeometry{c.shape, kA, c.edge_spheres, c.overlap});
  const Lattice l = lattice(c.shape);
  const double d = t.diameter();
  const Polyhedron inner = t.solid().recessed(d / 2);
  for (std::size_t k = 0; k < t.solid().faces().size(); ++k) {
    const Face& f = t.solid().faces()[k];
    const Vec3 neighbour = 2 * f.distance * f.normal;
    ASSERT_TRUE(std::any_of(l.sites.begin(), l.sites.end(), [&](const Vec3& s) { return (s - neighbour).norm() < kTol; }));
    // HCP: a neighbour in another layer is a B site, the template turned half a turn about c.
    const bool b_site = c.shape == Shape::trapezo_rhombic_dodecahedron && std::abs(f.normal.z()) > 1e-9;
    const Quat turn = b_site ? Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitZ())) : Quat::Identity();
    const auto under = [&](const Vec3& x, const Vec3& n) { return std::abs(x.dot(n) - (f.distance - d / 2)) < kTol; };
    std::vector<Vec3> mine, theirs;
    for (const Vec3& o : t.offsets()) {
      if (under(o, f.normal)) mine.push_back(o);
      if (under(turn * o, -f.normal)) theirs.push_back(neighbour + turn * o);
    }
    ASSERT_EQ(mine.size(), theirs.size()) << "face " << k;
    ASSERT_GT(mine.size(), 0u);
    // A quadrilateral's spheres all pair up; a hexagon's lattice nodes do (those off its inner edges).
    const Face& fi = inner.faces()[k];
    const std::size_t n = fi.vertices.size();
    std::size_t required = 0, paired = 0;
    for (const Vec3& m : mine) {
      bool on_edge = false;
      for (std::size_t i = 0; i < n && !on_edge; ++i) {
        const Vec3 a = fi.vertices[i], e = (fi.vertices[(i + 1) % n] - a).normalized();
        on_edge = ((m - a) - (m - a).dot(e) * e).norm() < kTol;
      }
      if (n > 4 && on_edge) continue;
      ++required;
      paired += std::any_of(theirs.begin(), theirs.end(), [&](const Vec3& x) { return std::abs((x - m).norm() - d) < 1e-9 * d; });
    }
    EXPECT_EQ(paired, required) << to_string(c.shape) << " face " << k << " of " << n << " vertices";
    if (n > 4) EXPECT_GT(required, 0u) << "a hexagon with no lattice node";
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, VoronoiClump,
                         testing::Values(ClumpCase{Shape::cube, 4, 0.75}, ClumpCase{Shape::rhombic_dodecahedron, 4, 0.75},
                                         ClumpCase{Shape::trapezo_rhombic_dodecahedron, 4, 0.75},
                                         ClumpCase{Shape::trapezo_rhombic_dodecahedron, 7, 0.75},
                                         ClumpCase{Shape::trapezo_rhombic_dodecahedron, 5, 0.5},
                                         ClumpCase{Shape::truncated_octahedron, 4, 0.75},
                                         ClumpCase{Shape::truncated_octahedron, 8, 0.75},
                                         ClumpCase{Shape::truncated_octahedron, 6, 0.5}),
                         [](const testing::TestParamInfo<ClumpCase>& info) {
                           return to_string(info.param.shape) + "_Ne" + std::to_string(info.param.edge_spheres) +
                                  "_kappa" + std::to_string(int(std::lround(info.param.overlap * 100)));
                         });

// Counted by hand (docs/model.md, "Grains"): with m = N_e - 1 segments on the 18 rhombus-type edges, the 3 long
// and 3 short trapezoid bases (4/3 and 2/3 of a rhombus edge) take 4m/3 and 2m/3; 14 vertices; 6 rhombi of
// (m-1)^2 inner spheres; each trapezoid's inner rows k = 1..m-1 of round((4m - 2k)/3) segments.
// N_e = 4: 14 + 18*2 + 3*3 + 3*1 + 6*4 + 6*(2+2) = 110. N_e = 7: 14 + 90 + 21 + 9 + 150 + 6*(6+6+5+4+4) = 434.
// (Both equal the RD's 12m'^2 + 24m' + 14, m' = N_e - 2: the two close-packed grains carry the same spheres.)
TEST(VoronoiClumpCount, TrapezoRhombicDodecahedronByHand) {
  for (const auto& [n_e, count] : std::vector<std::pair<int, std::size_t>>{{4, 110}, {7, 434}}) {
    const GrainGeometry g{Shape::trapezo_rhombic_dodecahedron, kA, n_e, 0.75};
    EXPECT_EQ(GrainTemplate(g).sphere_count(), count) << "N_e = " << n_e;
    EXPECT_EQ(sphere_count(g), long(count));
    EXPECT_EQ(GrainTemplate(g).spheres_per_face(), n_e * n_e);
  }
}

TEST(VoronoiClumpCount, TruncatedOctahedronNeedsSpheresSmallerThanItsSquares) {
  // N_e = 2 at kappa 0.75: d = 0.80 a, deeper than the squares' inner edges allow (d < 0.68 a).
  EXPECT_THROW(GrainTemplate(GrainGeometry{Shape::truncated_octahedron, kA, 2, 0.75}), std::invalid_argument);
  EXPECT_EQ(sphere_count(GrainGeometry{Shape::truncated_octahedron, kA, 2, 0.75}), 0);
  EXPECT_NO_THROW(GrainTemplate(GrainGeometry{Shape::truncated_octahedron, kA, 3, 0.75}));
}

}  // namespace
}  // namespace granulab
