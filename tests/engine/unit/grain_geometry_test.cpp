// Unit tests for grain geometry (docs/model.md, "Grains"): the solids (Polyhedron: cube, rhombic
// dodecahedron) and the sphere clumps built on them (GrainTemplate).
//
// Independent references used here, so that the tests do not just replay the engine's formulas:
//  - the inner polyhedron (faces recessed by d/2) is rebuilt as a solid of reduced size: the inradius is
//    linear in size (cube h = l/2, RD h = a/(2 sqrt2)), so recessing by d/2 gives l - d or a - sqrt2 d;
//  - face grids are rebuilt from the inner faces with step s = d(1-kappa) (not from N_e subdivisions);
//  - the RD inertia comes from an exact decomposition into a central cube plus 6 square pyramids.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/geometry/grain_template.h"

namespace granulab {
namespace {

const double kSqrt2 = std::sqrt(2.0);
const double kSqrt3 = std::sqrt(3.0);
constexpr double kSize = 0.01;  // m, cube side l or RD cubic cell a; every check below is scale-relative.
// Positions are sums of a few O(size) terms (rounding ~1e-16 size) and size/s <= 40 for every case here,
// so 1e-12 relative to s (or d) leaves a margin of > 100x over rounding.
constexpr double kRel = 1e-12;

struct Case {
  Shape shape;
  int edge_spheres;
  double overlap;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << to_string(c.shape) << " N_e=" << c.edge_spheres << " kappa=" << c.overlap;
}

std::string case_name(const testing::TestParamInfo<Case>& info) {
  const Case& c = info.param;
  return std::string(c.shape == Shape::cube ? "cube" : "rd") + "_Ne" + std::to_string(c.edge_spheres) + "_kappa" +
         std::to_string(int(std::lround(c.overlap * 100)));
}

std::size_t expected_sphere_count(Shape shape, int n_e) {
  const std::size_t m = n_e - 2;
  return shape == Shape::cube ? 6 * m * m + 12 * m + 8 : 12 * m * m + 24 * m + 14;
}

double expected_diameter_ratio(Shape shape, int n_e, double kappa) {
  const double stretch = (n_e - 1) * (1 - kappa);
  return shape == Shape::cube ? 1 / (stretch + 1) : 1 / ((4 / kSqrt3) * stretch + kSqrt2);
}

/// The polyhedron on which sphere centres must lie: the solid with every face recessed by d/2.
Polyhedron inner_solid(Shape shape, double size, double d) {
  return Polyhedron::make(shape, shape == Shape::cube ? size - d : size - kSqrt2 * d);
}

/// Distance from `p` to the plane of face `f` (positive inside).
double depth_below(const Face& f, const Vec3& p) { return (f.corner - p).dot(f.normal); }

double nearest_distance(const std::vector<Vec3>& pts, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& q : pts) best = std::min(best, (q - p).norm());
  return best;
}

struct Segment {
  Vec3 from, to;
};

/// Every edge of the polyhedron once (faces share edges pairwise).
std::vector<Segment> distinct_edges(const Polyhedron& p) {
  const double tol = 1e-9 * p.edge_length();  // only to recognise shared endpoints, which are >= an edge apart
  const auto same = [tol](const Vec3& u, const Vec3& v) { return (u - v).norm() < tol; };
  std::vector<Segment> edges;
  for (const Face& f : p.faces()) {
    const Vec3 a = f.corner, b = f.corner + f.edge_a, c = f.corner + f.edge_b, d = b + f.edge_b;
    for (const Segment& e : {Segment{a, b}, Segment{a, c}, Segment{b, d}, Segment{c, d}}) {
      const bool seen = std::any_of(edges.begin(), edges.end(), [&](const Segment& o) {
        return (same(e.from, o.from) && same(e.to, o.to)) || (same(e.from, o.to) && same(e.to, o.from));
      });
      if (!seen) edges.push_back(e);
    }
  }
  return edges;
}

// ------------------------------------------------------------------------------------------------
// Clump geometry, for both shapes x N_e in {2,3,5,10,15} x kappa in {0, 0.5, 0.75}.

class GrainClumpTest : public testing::TestWithParam<Case> {
 protected:
  const Case c = GetParam();
  const GrainTemplate tpl{GrainGeometry{c.shape, kSize, c.edge_spheres, c.overlap}};
  const double d = tpl.diameter();
  const double s = tpl.spacing();
  const Polyhedron inner = inner_solid(c.shape, kSize, d);
  const std::vector<Vec3>& centres = tpl.offsets();
};

TEST_P(GrainClumpTest, SphereCountMatchesClosedForm) {
  EXPECT_EQ(tpl.sphere_count(), expected_sphere_count(c.shape, c.edge_spheres));
  EXPECT_EQ(tpl.spheres_per_face(), c.edge_spheres * c.edge_spheres);
}

TEST_P(GrainClumpTest, DiameterSatisfiesFormulaAndEdgeTangency) {
  // Closed forms are a handful of flops: 1e-12 relative is rounding plus a wide margin.
  EXPECT_NEAR(d / kSize, expected_diameter_ratio(c.shape, c.edge_spheres, c.overlap),
              kRel * expected_diameter_ratio(c.shape, c.edge_spheres, c.overlap));
  EXPECT_NEAR(s, d * (1 - c.overlap), kRel * d);
  // The geometric meaning of the formula: N_e centres at spacing s span exactly one inner edge.
  EXPECT_NEAR(inner.edge_length(), (c.edge_spheres - 1) * s, kRel * s);  // kRel: see its definition
}

TEST_P(GrainClumpTest, EverySphereIsInsideTheSolidAndTangentToAFace) {
  const Polyhedron& solid = tpl.solid();
  for (std::size_t i = 0; i < centres.size(); ++i) {
    double min_depth = std::numeric_limits<double>::infinity();
    for (const Face& f : solid.faces()) {
      const double depth = depth_below(f, centres[i]);
      EXPECT_GE(depth, d / 2 * (1 - kRel)) << "sphere " << i << " pokes out of a face";  // kRel: see definition
      min_depth = std::min(min_depth, depth);
    }
    EXPECT_NEAR(min_depth, d / 2, kRel * d / 2) << "sphere " << i << " touches no face";  // kRel: see definition
  }
}

// Each face carries exactly the N_e x N_e grid of step s laid on its inner (recessed) face, and the spheres
// on that grid are exactly the ones tangent to the face. (A purely "projects onto the grid" criterion is
// not enough: centres on an adjacent face project onto this face's boundary grid points without touching it.)
TEST_P(GrainClumpTest, EachFaceCarriesItsFullGridOfTangentSpheres) {
  const auto& outer_faces = tpl.solid().faces();
  ASSERT_EQ(inner.faces().size(), outer_faces.size());
  for (std::size_t k = 0; k < outer_faces.size(); ++k) {
    const Face& outer = outer_faces[k];
    const Face& face = inner.faces()[k];
    ASSERT_LT((face.normal - outer.normal).norm(),
              1e-14);  // same construction, so same order: unit vectors agree to rounding

    const auto tangent = std::count_if(centres.begin(), centres.end(), [&](const Vec3& p) {
      return std::abs(depth_below(outer, p) - d / 2) <= kRel * d / 2;  // kRel: see definition
    });
    EXPECT_EQ(tangent, c.edge_spheres * c.edge_spheres) << "face " << k;

    const Vec3 step_a = s * face.edge_a.normalized(), step_b = s * face.edge_b.normalized();
    for (int i = 0; i < c.edge_spheres; ++i) {
      for (int j = 0; j < c.edge_spheres; ++j) {
        const Vec3 node = face.corner + i * step_a + j * step_b;
        // Grid nodes are >= s apart, so a match within kRel*s is a distinct centre for each node.
        EXPECT_LE(nearest_distance(centres, node), kRel * s) << "face " << k << " node " << i << "," << j;
        EXPECT_NEAR(depth_below(outer, node), d / 2, kRel * d / 2);  // kRel: see definition
      }
    }
  }
}

TEST_P(GrainClumpTest, EveryEdgeCarriesNeCentresAtSpacingS) {
  const std::vector<Segment> edges = distinct_edges(inner);
  ASSERT_EQ(edges.size(), c.shape == Shape::cube ? 12u : 24u);
  for (const Segment& e : edges) {
    const double length = (e.to - e.from).norm();
    const Vec3 t = (e.to - e.from) / length;
    std::vector<double> along;
    for (const Vec3& p : centres) {
      const Vec3 r = p - e.from;
      const double u = r.dot(t);
      // Classification only: off-edge centres are >= s sin(70.5 deg) > 0.9 s from the edge line.
      if ((r - u * t).norm() < 1e-6 * s && u > -1e-6 * s && u < length + 1e-6 * s) along.push_back(u);
    }
    ASSERT_EQ(along.size(), std::size_t(c.edge_spheres));
    std::sort(along.begin(), along.end());
    EXPECT_NEAR(along.front(), 0, kRel * s);  // vertices included; kRel: see definition
    EXPECT_NEAR(along.back(), length, kRel * s);
    for (std::size_t i = 1; i < along.size(); ++i) EXPECT_NEAR(along[i] - along[i - 1], s, kRel * s);
  }
}

// Nearest-neighbour distance is exactly s for both shapes. On the rhombic RD grid the face angles are
// arccos(1/3) = 70.5 deg and 109.5 deg, so the short diagonal is s sqrt(2 - 2/3) = 1.155 s > s; across an
// edge (dihedral 120 deg) the closest off-edge pair is s sqrt(8/3) apart. So the minimum is the edge step s,
// and any smaller distance would mean a duplicate or misplaced centre.
TEST_P(GrainClumpTest, NearestNeighbourDistanceIsTheSpacing) {
  double min_dist = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (std::size_t j = i + 1; j < centres.size(); ++j)
      min_dist = std::min(min_dist, (centres[i] - centres[j]).norm());
  EXPECT_NEAR(min_dist, s, kRel * s);  // kRel: see definition
}

TEST_P(GrainClumpTest, BoundingRadiusEnclosesEverySphere) {
  double farthest = 0;
  for (const Vec3& p : centres) {
    EXPECT_GE(tpl.bounding_radius(), p.norm() + d / 2);
    farthest = std::max(farthest, p.norm());
  }
  EXPECT_NEAR(tpl.bounding_radius(), farthest + d / 2, kRel * d);  // kRel: see definition
  // The farthest centre sits on the farthest inner vertex: cube sqrt3 (l-d)/2, RD 4-valent vertex (a - sqrt2 d)/2.
  const double inner_vertex = c.shape == Shape::cube ? kSqrt3 * (kSize - d) / 2 : (kSize - kSqrt2 * d) / 2;
  EXPECT_NEAR(farthest, inner_vertex, kRel * d);
}

TEST_P(GrainClumpTest, MassPropertiesComeFromTheSolidNotTheSpheres) {
  const MassProperties mp = tpl.solid().mass_properties();
  EXPECT_EQ(tpl.volume(), mp.volume);  // copied, not recomputed
  EXPECT_EQ(tpl.principal_inertia_per_density(), Vec3(mp.inertia_per_density.diagonal()));
  EXPECT_LT(mp.centroid.norm(), kRel * kSize);  // centred solid; rounding only
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (Shape shape : {Shape::cube, Shape::rhombic_dodecahedron})
    for (int n_e : {2, 3, 5, 10, 15})
      for (double kappa : {0.0, 0.5, 0.75}) cases.push_back({shape, n_e, kappa});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Clumps, GrainClumpTest, testing::ValuesIn(all_cases()), case_name);

// ------------------------------------------------------------------------------------------------
// The paper's clumps (N_e = 10, kappa = 0.75).

TEST(GrainTemplatePaper, SphereCountsAndRhombicDodecahedronDiameter) {
  const GrainTemplate cube(GrainGeometry{Shape::cube, kSize, 10, 0.75});
  const GrainTemplate rd(GrainGeometry{Shape::rhombic_dodecahedron, kSize, 10, 0.75});
  EXPECT_EQ(cube.sphere_count(), 488u);
  EXPECT_EQ(rd.sphere_count(), 974u);
  EXPECT_NEAR(rd.diameter() / kSize, 0.1513, 0.5e-4);    // the 4-digit value quoted in docs/model.md
  EXPECT_NEAR(cube.diameter() / kSize, 1 / 3.25, kRel);  // 9 * 0.25 + 1 = 3.25
}

TEST(GrainTemplateInput, InvalidGeometryThrows) {
  const auto build = [](double size, int n_e, double kappa) {
    return GrainTemplate(GrainGeometry{Shape::rhombic_dodecahedron, size, n_e, kappa});
  };
  EXPECT_NO_THROW(build(kSize, 2, 0.0));  // smallest valid clump
  for (int n_e : {1, 0, -3}) EXPECT_THROW(build(kSize, n_e, 0.5), std::invalid_argument) << "N_e " << n_e;
  for (double kappa : {1.0, 1.5, -1e-9, -0.5, std::nan("")})
    EXPECT_THROW(build(kSize, 10, kappa), std::invalid_argument) << "kappa " << kappa;
  for (double size : {0.0, -kSize, std::nan("")})
    EXPECT_THROW(build(size, 10, 0.5), std::invalid_argument) << "size " << size;
  EXPECT_THROW(Polyhedron::make(Shape::cube, 0.0), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------------
// The solids.

/// Volume and second moment S = integral of r r^T of a solid stacked along axis k from t0 to t1, whose
/// cross-section is the square |r_i|, |r_j| <= w(t) with w linear from w0 to w1 (prism or pyramid).
struct Moments {
  double volume = 0;
  Mat3 second = Mat3::Zero();
};

Moments square_stack(int k, double t0, double t1, double w0, double w1) {
  // Per slice: area 4w^2, integral of r_k^2 = t^2 4w^2, of r_i^2 = 2w * (2w^3/3). All are polynomials of
  // degree <= 4 in t, so 3-point Gauss-Legendre (exact to degree 5) integrates them exactly.
  const std::array<double, 3> node{-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, weight{5 / 9.0, 8 / 9.0, 5 / 9.0};
  const double mid = (t0 + t1) / 2, half = (t1 - t0) / 2;
  Moments m;
  for (int q = 0; q < 3; ++q) {
    const double t = mid + half * node[q], w = w0 + (w1 - w0) * (t - t0) / (t1 - t0), jw = half * weight[q];
    m.volume += jw * 4 * w * w;
    for (int i = 0; i < 3; ++i) m.second(i, i) += jw * (i == k ? t * t * 4 * w * w : 4 * std::pow(w, 4) / 3);
  }
  return m;
}

Mat3 inertia_from_second_moment(const Mat3& s) { return s.trace() * Mat3::Identity() - s; }

/// The RD of cell a is {|x|+|y|, |y|+|z|, |z|+|x| <= a/2}: the cube |r_i| <= a/4 plus, on each of its 6
/// faces, a pyramid of height a/4 reaching the 4-valent vertex (+-a/2 e_k). (Closed form: V = a^3/4,
/// I = a^5/64 on each axis.)
Moments rhombic_dodecahedron_by_decomposition(double a) {
  std::vector<Moments> parts{square_stack(0, -a / 4, a / 4, a / 4, a / 4)};
  for (int k = 0; k < 3; ++k) {
    parts.push_back(square_stack(k, a / 4, a / 2, a / 4, 0));
    parts.push_back(square_stack(k, -a / 2, -a / 4, 0, a / 4));
  }
  Moments total;
  for (const Moments& p : parts) total.volume += p.volume, total.second += p.second;
  return total;
}

TEST(PolyhedronSolid, CubeMetricsAndMassProperties) {
  const double l = kSize;
  const Polyhedron cube = Polyhedron::make(Shape::cube, l);
  ASSERT_EQ(cube.faces().size(), 6u);
  // Exact tetrahedral sums of ~24 terms: relative rounding ~1e-15, so 1e-12 relative is safe.
  EXPECT_NEAR(cube.inradius(), l / 2, kRel * l);
  EXPECT_NEAR(cube.edge_length(), l, kRel * l);
  EXPECT_NEAR(cube.face_area(), l * l, kRel * l * l);
  EXPECT_NEAR(cube.circumradius(), kSqrt3 * l / 2, kRel * l);
  const MassProperties mp = cube.mass_properties();
  EXPECT_NEAR(mp.volume, std::pow(l, 3), kRel * std::pow(l, 3));
  EXPECT_LT(mp.centroid.norm(), kRel * l);
  const double i0 = std::pow(l, 5) / 6;  // V (l^2 + l^2) / 12
  EXPECT_TRUE(mp.inertia_per_density.isApprox(i0 * Mat3::Identity(), kRel)) << mp.inertia_per_density;
}

TEST(PolyhedronSolid, RhombicDodecahedronMetrics) {
  const double a = kSize;
  const Polyhedron rd = Polyhedron::make(Shape::rhombic_dodecahedron, a);
  ASSERT_EQ(rd.faces().size(), 12u);
  // Closed forms from docs/model.md; a few flops each, so 1e-12 relative is rounding plus margin.
  EXPECT_NEAR(rd.inradius(), a / (2 * kSqrt2), kRel * a);
  EXPECT_NEAR(rd.edge_length(), a * kSqrt3 / 4, kRel * a);
  EXPECT_NEAR(rd.face_area(), kSqrt2 * a * a / 8, kRel * a * a);
  EXPECT_NEAR(rd.circumradius(), a / 2, kRel * a);
  EXPECT_NEAR(rd.mass_properties().volume, std::pow(a, 3) / 4, kRel * std::pow(a, 3));
}

TEST(PolyhedronSolid, RhombicDodecahedronInertiaMatchesDecomposition) {
  const double a = kSize;
  const MassProperties mp = Polyhedron::make(Shape::rhombic_dodecahedron, a).mass_properties();
  const Moments ref = rhombic_dodecahedron_by_decomposition(a);
  const Mat3 ref_inertia = inertia_from_second_moment(ref.second);
  // Both sides are exact up to rounding (closed-form tetrahedra vs exact quadrature): 1e-12 relative.
  EXPECT_NEAR(ref.volume, std::pow(a, 3) / 4, kRel * std::pow(a, 3));
  EXPECT_TRUE(ref_inertia.isApprox(std::pow(a, 5) / 64 * Mat3::Identity(), kRel)) << ref_inertia;
  EXPECT_NEAR(mp.volume, ref.volume, kRel * ref.volume);
  EXPECT_LT(mp.centroid.norm(), kRel * a);
  EXPECT_TRUE(mp.inertia_per_density.isApprox(ref_inertia, kRel)) << mp.inertia_per_density << "\nvs\n" << ref_inertia;
}

class PolyhedronFaces : public testing::TestWithParam<Shape> {};

TEST_P(PolyhedronFaces, AreOutwardRhombiAtTheInradiusAndBoundContains) {
  const Polyhedron p = Polyhedron::make(GetParam(), kSize);
  const double h = p.inradius(), e = p.edge_length();
  for (const Face& f : p.faces()) {
    // Unit-vector and dot-product identities on O(size) data: 1e-12 relative is rounding plus margin.
    EXPECT_NEAR(f.normal.norm(), 1, kRel);
    EXPECT_NEAR(f.edge_a.norm(), e, kRel * e);
    EXPECT_NEAR(f.edge_b.norm(), e, kRel * e);
    EXPECT_NEAR(f.edge_a.dot(f.normal), 0, kRel * e);
    EXPECT_NEAR(f.edge_b.dot(f.normal), 0, kRel * e);
    EXPECT_GT(f.edge_a.cross(f.edge_b).dot(f.normal), 0);  // right-handed, outward
    EXPECT_NEAR(f.corner.dot(f.normal), h, kRel * h);      // every face at distance h
    // The face centre is on the surface; 1e-6 h along the normal is clearly in or out.
    const Vec3 centre = f.corner + (f.edge_a + f.edge_b) / 2;
    EXPECT_TRUE(p.contains(centre - 1e-6 * h * f.normal));
    EXPECT_FALSE(p.contains(centre + 1e-6 * h * f.normal));
  }
  EXPECT_TRUE(p.contains(Vec3::Zero()));
}

INSTANTIATE_TEST_SUITE_P(Shapes, PolyhedronFaces, testing::Values(Shape::cube, Shape::rhombic_dodecahedron),
                         [](const testing::TestParamInfo<Shape>& info) { return to_string(info.param); });

}  // namespace
}  // namespace granulab
