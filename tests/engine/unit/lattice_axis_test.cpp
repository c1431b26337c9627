// Crystals of the four lattices along any axis (docs/model.md, "Lattices and loading axes"):
//  - the general builder reproduces the paper's crystal when given a symmetry-equivalent of its axis (FCC
//    [2 -1 -1] with [0 1 -1] is [-1 -1 2] with [1 -1 0] after a cyclic permutation of the cubic axes), and SC
//    [1 1 0] equals SC [0 1 1]: the same sites, ids and box, so the same crystal;
//  - every box cell holds one site for the main directions (the count is the product of the three numbers);
//  - the grains of a built crystal touch their face neighbours and overlap only by the pre-strain: every sphere
//    pair of two grains is at least d - eps0 l apart (l the centre distance), and the in-line pairs exactly so;
//  - the directions the spec accepts: defaults, HCP four-index form, and the refusals that name the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "engine/crystal/crystal_lattice.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/geometry/grain_template.h"

namespace granulab {
namespace {

constexpr double kA = 0.01;       // m
constexpr double kEps0 = 1e-3;    // pre-strain
constexpr double kTol = 1e-12 * kA;

CrystalGeometry geometry(LatticeType lattice, Indices axis, Indices lateral, int gx, int ly, int rz) {
  CrystalGeometry g;
  g.lattice = lattice, g.axis = axis, g.lateral = lateral;
  g.size = kA, g.prestrain = kEps0;
  g.grains_x = gx, g.layers_y = ly, g.rows_z = rz;
  return g;
}

void expect_same_crystal(const CrystalLattice& p, const CrystalLattice& q) {
  ASSERT_EQ(p.sites.size(), q.sites.size());
  EXPECT_LT((p.extent - q.extent).norm(), kTol);
  EXPECT_LT((p.period - q.period).norm(), kTol);
  EXPECT_LT((p.box_lo - q.box_lo).norm(), kTol);  // what the exposed faces are found against
  EXPECT_LT((p.box_hi - q.box_hi).norm(), kTol);
  for (std::size_t k = 0; k < p.sites.size(); ++k) {
    EXPECT_EQ(p.sites[k].id, q.sites[k].id);
    EXPECT_LT((p.sites[k].position - q.sites[k].position).norm(), kTol) << "site " << k;
    EXPECT_EQ(p.sites[k].layer, q.sites[k].layer);
    EXPECT_EQ(p.sites[k].row, q.sites[k].row);
    EXPECT_EQ(p.sites[k].column, q.sites[k].column);
  }
}

TEST(LatticeAxis, GeneralBuilderReproducesThePapersCrystalAlongAnEquivalentAxis) {
  for (const std::array<int, 3>& size : std::vector<std::array<int, 3>>{{8, 6, 18}, {3, 4, 7}, {4, 3, 8}}) {
    const CrystalLattice paper = build_crystal(geometry(LatticeType::fcc, {-1, -1, 2}, {0, 0, 0}, size[0], size[1], size[2]));
    const CrystalLattice general = build_crystal(geometry(LatticeType::fcc, {2, -1, -1}, {0, 0, 0}, size[0], size[1], size[2]));
    expect_same_crystal(paper, general);
    // The two orientations differ by the permutation of the cubic axes (x, y, z) -> (y, z, x).
    Mat3 perm;
    perm << 0, 0, 1, 1, 0, 0, 0, 1, 0;  // crystal [u v w] -> [w u v]
    EXPECT_TRUE((general.orientation.toRotationMatrix() * perm).isApprox(paper.orientation.toRotationMatrix(), 1e-12));
  }
  EXPECT_EQ(default_lateral(LatticeType::fcc, {2, -1, -1}), (Indices{0, 1, -1}));
  EXPECT_EQ(default_lateral(LatticeType::fcc, {-1, -1, 2}), (Indices{1, -1, 0}));
}

TEST(LatticeAxis, SymmetryEquivalentAxesOfTheCubicCrystalGiveTheSameCrystal) {
  const CrystalLattice a = build_crystal(geometry(LatticeType::sc, {1, 1, 0}, {0, 0, 0}, 3, 4, 8));
  const CrystalLattice b = build_crystal(geometry(LatticeType::sc, {0, 1, 1}, {0, 0, 0}, 3, 4, 8));
  expect_same_crystal(a, b);
  EXPECT_EQ(default_lateral(LatticeType::sc, {1, 1, 0}), (Indices{0, 0, 1}));
  EXPECT_EQ(default_lateral(LatticeType::sc, {0, 1, 1}), (Indices{1, 0, 0}));
  const CrystalLattice c = build_crystal(geometry(LatticeType::bcc, {1, 1, 1}, {0, 0, 0}, 3, 4, 6));
  const CrystalLattice d = build_crystal(geometry(LatticeType::bcc, {1, -1, 1}, {0, 0, 0}, 3, 4, 6));
  EXPECT_EQ(c.sites.size(), d.sites.size());
}

// Periods worked out by hand (cell a' = (1 - eps0) a): the repeat along x, the site-plane spacing along y, and
// the grain volume over their product along z.
TEST(LatticeAxis, MainDirectionsFillEveryCellOnce) {
  const double a = (1 - kEps0) * kA, d = a / std::sqrt(2.0), c = std::sqrt(8.0 / 3.0) * d;
  struct Case {
    LatticeType lattice;
    Indices axis;
    Vec3 period;
  };
  const Case cases[] = {
      {LatticeType::sc, {0, 0, 1}, Vec3(a, a, a)},
      // x = [1 0 0] (repeat a), y = [0 1 0]: BCC's (020) planes a/2 apart; z: (a^3/2) / (a a/2) = a.
      {LatticeType::bcc, {0, 0, 1}, Vec3(a, a / 2, a)},
      // x = [1 1 0] (repeat a/sqrt2), y = z x x = [-1 1 0]/sqrt2: FCC's (220) planes a/(2 sqrt2) apart; z = a/2.
      {LatticeType::fcc, {0, 0, 1}, Vec3(a / std::sqrt(2.0), a / (2 * std::sqrt(2.0)), a)},
      // x along a1 + a2 (repeat D), y normal to it in the basal plane: A and B planes at 1/3 and 2/3 of the
      // Bravais spacing sqrt3 D / 2, so layers sqrt3 D / 4 on average; z = grain volume / (w_x w_y) = c.
      {LatticeType::hcp, {0, 0, 1}, Vec3(d, std::sqrt(3.0) * d / 4, c)},
  };
  for (const Case& k : cases) {
    const CrystalLattice l = build_crystal(geometry(k.lattice, k.axis, {0, 0, 0}, 3, 4, 5));
    EXPECT_LT((l.period - k.period).norm(), kTol) << to_string(k.lattice) << " periods " << l.period.transpose() / a;
    EXPECT_EQ(l.sites.size(), 3u * 4 * 5) << to_string(k.lattice);
    std::vector<int> seen(3 * 4 * 5, 0);
    for (const LatticeSite& s : l.sites) {
      ASSERT_TRUE(s.column >= 0 && s.column < 3 && s.layer >= 0 && s.layer < 4 && s.row >= 0 && s.row < 5);
      ++seen[(s.layer * 5 + s.row) * 3 + s.column];
      EXPECT_TRUE(((s.position - l.box_lo).array() > 0).all() && ((l.box_hi - s.position).array() > 0).all());
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; })) << to_string(k.lattice);
  }
}

// Grains as built touch and overlap by the pre-strain only: for each pair of neighbouring grains, the closest
// spheres are d - eps0 l apart (l their centre distance, eps0 l the lattice's shrinkage along it), never closer.
TEST(LatticeAxis, BuiltGrainsOverlapOnlyByThePrestrain) {
  struct Case {
    LatticeType lattice;
    Indices axis;
    int edge_spheres;
  };
  for (const Case& k : {Case{LatticeType::sc, {1, 1, 0}, 4}, Case{LatticeType::fcc, {1, 2, 3}, 4},
                        Case{LatticeType::bcc, {1, 1, 1}, 4}, Case{LatticeType::hcp, {0, 0, 1}, 4},
                        Case{LatticeType::hcp, {1, 0, 0}, 4}}) {
    const CrystalLattice l = build_crystal(geometry(k.lattice, k.axis, {0, 0, 0}, 3, 3, 3));
    const GrainTemplate t(GrainGeometry{grain_shape(k.lattice), kA, k.edge_spheres, 0.75});
    double h_max = 0;
    for (const Face& f : t.solid().faces()) h_max = std::max(h_max, f.distance);
    const double reach = 2 * h_max * 1.01, d = t.diameter();
    std::size_t neighbour_pairs = 0;
    for (std::size_t i = 0; i < l.sites.size(); ++i)
      for (std::size_t j = i + 1; j < l.sites.size(); ++j) {
        const Vec3 branch = l.sites[j].position - l.sites[i].position;
        if (branch.norm() > reach) continue;
        const Mat3 ri = l.basis_orientation[l.sites[i].basis].toRotationMatrix();
        const Mat3 rj = l.basis_orientation[l.sites[j].basis].toRotationMatrix();
        double closest = 1e300;
        for (const Vec3& oi : t.offsets())
          for (const Vec3& oj : t.offsets()) closest = std::min(closest, (branch + rj * oj - ri * oi).norm());
        const double shrink = kEps0 * branch.norm() / (1 - kEps0);  // the unstrained centre distance times eps0
        EXPECT_NEAR(closest, d - shrink, 1e-9 * d) << to_string(k.lattice) << " grains " << i << ", " << j;
        ++neighbour_pairs;
      }
    EXPECT_GT(2 * neighbour_pairs, l.sites.size()) << to_string(k.lattice);  // a high-index cut is sparse
  }
}

// The layers a section picture offers, named by their Miller indices (worked by hand: y = z x x in crystal
// coordinates; HCP's (h, k, l) = (a1 . y, a2 . y, c . y) scaled, i = -(h + k)).
TEST(LatticeAxis, LayersAreNamedByTheirPlanes) {
  EXPECT_EQ(layer_planes(build_crystal(geometry(LatticeType::fcc, {-1, -1, 2}, {0, 0, 0}, 2, 2, 2))), "{111}");
  // sc [1 1 0], x = [0 0 1]: y = [1 1 0] x [0 0 1] / sqrt2 = [1 -1 0] / sqrt2.
  EXPECT_EQ(layer_planes(build_crystal(geometry(LatticeType::sc, {1, 1, 0}, {0, 0, 0}, 2, 2, 2))), "(1 -1 0)");
  // bcc [0 0 1], x = [1 0 0]: y = [0 1 0].
  EXPECT_EQ(layer_planes(build_crystal(geometry(LatticeType::bcc, {0, 0, 1}, {0, 0, 0}, 2, 2, 2))), "(0 1 0)");
  // hcp along a1 with x along a1 + 2 a2 (lab y of the crystal frame): y = c, the basal planes.
  EXPECT_EQ(layer_planes(build_crystal(geometry(LatticeType::hcp, {1, 0, 0}, {1, 2, 0}, 2, 2, 2))), "(0 0 0 1)");
  // hcp along c with x along a1 + a2 (60 degrees): y = (-sqrt3/2, 1/2, 0), a1 . y < 0 < a2 . y: a prism plane.
  EXPECT_EQ(layer_planes(build_crystal(geometry(LatticeType::hcp, {0, 0, 1}, {0, 0, 0}, 2, 2, 2))), "(1 -1 0 0)");
}

TEST(LatticeAxis, RefusesDirectionsThatAreNoSample) {
  EXPECT_THROW(build_crystal(geometry(LatticeType::sc, {0, 0, 0}, {0, 0, 0}, 2, 2, 2)), std::invalid_argument);
  try {
    build_crystal(geometry(LatticeType::sc, {0, 0, 1}, {1, 0, 1}, 2, 2, 2));
    FAIL() << "a lateral direction along the axis was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("loading.lateral"), std::string::npos) << e.what();
  }
}

// The sample's parameters: the lattice picks its grain and its pre-strain; p0 / E for cubes, sqrt2 p0 / E for
// FCC (its faces all at D / 2, Love-Weber E eps0 l / size with l = D = a / sqrt2). HCP's faces lie at D / 2 too,
// and its trapezoids hold N_e^2 spheres as its rhombi do (rows k and n - k add to 2n + 2), so its factor is sqrt2
// up to the round-off of the general sum.
TEST(LatticeAxis, PrestrainCarriesTheConfiningPressure) {
  CrystalSampleParams p;
  p.confining_pressure = 30e3, p.grain.edge_spheres = 4;
  const double e = p.material.youngs_modulus;
  for (LatticeType lattice : {LatticeType::fcc, LatticeType::sc, LatticeType::bcc, LatticeType::hcp}) {
    p.lattice = lattice;
    p.grain.shape = grain_shape(lattice);
    const double eps0 = hydrostatic_prestrain(p);
    if (lattice == LatticeType::sc) {
      EXPECT_DOUBLE_EQ(eps0, 30e3 / e);
    } else if (lattice == LatticeType::fcc) {
      EXPECT_DOUBLE_EQ(eps0, std::sqrt(2.0) * 30e3 / e);
    } else if (lattice == LatticeType::hcp) {
      EXPECT_NEAR(eps0 * e / 30e3, std::sqrt(2.0), 1e-12) << eps0 * e / 30e3;
    } else {
      // BCC: between the cube's and FCC's factor; with uniform sphere density it would be 6 V / sum A l^2 = 1.11.
      EXPECT_TRUE(eps0 > 0.8 * 30e3 / e && eps0 < 1.4 * 30e3 / e) << eps0 * e / 30e3;
    }
  }
  // The general formula gives FCC's sqrt2 too (computed, not the closed form).
  const GrainTemplate rd(GrainGeometry{Shape::rhombic_dodecahedron, kA, 4, 0.75});
  double sum = 0;
  for (const Face& f : rd.solid().faces()) sum += normal_stiffness(rd, e) * 16 * 4 * f.distance * f.distance;
  EXPECT_NEAR(6 * rd.volume() * 30e3 / sum, std::sqrt(2.0) * 30e3 / e, 1e-12 * 30e3 / e);
}

}  // namespace
}  // namespace granulab
