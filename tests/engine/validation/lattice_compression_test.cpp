// Crystals of every lattice, confined and compressed (docs/model.md, "Lattices and loading axes"):
//  - SC, BCC and HCP crystals confine to p0 on both platens and in the packing, and carry load along [0 0 1];
//  - symmetry-equivalent axes give the same first yield: FCC [2 -1 -1] (the general builder) against the
//    paper's [-1 -1 2] (its own), within 3 %;
//  - the closed form of a simple cubic crystal of cubes: along [1 1 0] its {100} planes lie at 45 degrees to the
//    axis and are flat through the whole crystal, so a slab slides on one when Coulomb's law holds on it:
//    sigma_n = (s1 + p0)/2, tau = (s1 - p0)/2, tau = f sigma_n, s1/p0 = (1 + f)/(1 - f); along [1 1 1] the
//    planes lie at acos(1/sqrt3) = 54.7 degrees (cos^2 = 1/3, sin cos = sqrt2/3), s1/p0 = (sqrt2 + 2f)/(sqrt2 - f).
//    s1 is the axial stress, p0 included. In the default wrapped bag, on crystals 4 grains wide of aspect ratio 2
//    and 4, the measured first yield is within 10 % of these at f = 0.2 and 0.35 (the bound: the walls'
//    friction and the band's ends add a little).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/experiments/crystal_compression/crystal_compression.h"

namespace granulab {
namespace {

CrystalParams crystal(LatticeType lattice, Indices axis, int gx, int ly, int rz, double p0 = 30e3) {
  CrystalParams p;
  p.lattice = lattice, p.axis = axis;
  p.grain.shape = grain_shape(lattice);
  p.grain.edge_spheres = 4;
  p.grains_x = gx, p.layers_y = ly, p.rows_z = rz;
  p.confining_pressure = p0;
  p.max_strain = 2e-3;
  p.curve_points = 100;
  p.snapshot_strains = {};
  return p;
}

TEST(LatticeCompression, EveryLatticeConfinesToP0AndCarriesLoad) {
  const double p0 = 30e3;
  for (LatticeType lattice : {LatticeType::sc, LatticeType::bcc, LatticeType::hcp}) {
    CrystalCompression experiment(crystal(lattice, default_axis(lattice), 4, 4, 8, p0));
    const CrystalResult r = experiment.run();
    const ConfinementReport& c = r.confinement;
    EXPECT_TRUE(c.converged) << to_string(lattice) << ": " << c.steps << " steps";
    EXPECT_NEAR(c.stress_top, p0, 0.01 * p0) << to_string(lattice);
    EXPECT_NEAR(c.stress_bottom, p0, 0.01 * p0) << to_string(lattice);
    // The wrapped bag holds the lattice as built, which carries p0 in every direction (measured: within 1e-5 p0; a
    // virial that left out the bag's lever from face to grain centre read 0.75 p0 here, (n - 1)/n for n = 4).
    EXPECT_NEAR(c.lateral_stress_x, p0, 0.01 * p0) << to_string(lattice);
    EXPECT_NEAR(c.lateral_stress_y, p0, 0.01 * p0) << to_string(lattice);
    // Along these axes no close-packed or cube plane is inclined to the load, so the crystals stiffen rather than
    // yield early: they carry a deviator well above p0 by 0.2 % strain, with the top and bottom platens agreeing once
    // the loading has settled. The platen accelerates over ten wave transits, 5 R of strain (7.5e-5 at the default
    // R = 1.5 p0/E), and in the wrapped bag it starts at bare contact, where a Hertzian contact has no stiffness: the
    // stiff bcc crystal rings as the platens engage, top and bottom alternately ahead (measured: 28 % of the axial
    // stress at 1.4e-5 strain, 9 % at 1.1e-4, 4.7 % at 1.9e-4, at most 2.6 % from 2e-4 on; the taut bag, which
    // leaves the platens pressed at p0, 6 % at 4e-5 and 1.3 % after the ramp). So the check starts at 3 ramps.
    const double settled_strain = 15 * default_compression_rate_number(p0, Material().youngs_modulus);
    double peak = 0, gap = 0;
    for (const CrystalRow& row : r.curve) {
      peak = std::max(peak, row.deviator);
      if (row.deviator > p0 && row.strain > settled_strain)
        gap = std::max(gap, std::abs(row.stress_top - row.stress_bottom) / (row.deviator + p0));
    }
    EXPECT_GT(peak, p0) << to_string(lattice);
    EXPECT_LT(gap, 0.05) << to_string(lattice);
    std::printf("%s [0 0 1]: confined in %llu steps, deviator up to %.2f p0 by 0.2 %% strain\n",
                to_string(lattice).c_str(), (unsigned long long)c.steps, peak / p0);
  }
}

TEST(LatticeCompression, EquivalentAxesGiveTheSameFirstYield) {
  const CrystalResult paper = CrystalCompression(crystal(LatticeType::fcc, {-1, -1, 2}, 4, 3, 8)).run();
  const CrystalResult general = CrystalCompression(crystal(LatticeType::fcc, {2, -1, -1}, 4, 3, 8)).run();
  const double a = first_yield_peak(paper.curve, 30e3).second, b = first_yield_peak(general.curve, 30e3).second;
  EXPECT_NEAR(b / a, 1.0, 0.03) << a << " vs " << b;
}

double axial_first_yield(const CrystalParams& p) {
  const CrystalResult r = CrystalCompression(p).run();
  return p.confining_pressure + first_yield_peak(r.curve, p.confining_pressure).second;
}

// The closed form assumes a uniform lateral stress p0: a pressure, which the default wrapped bag is (p0 on every
// exposed face). Issue 51's sizes: 4 grains wide (x), aspect ratios about 2 and 4, f = 0.2 and 0.35. (The taut bag,
// `taut_membrane`, the default until 2026-12-07, gave no deviator at all on 4 x 6 x 6 at f = 0.2, docs/model.md "Why the taut bag fails on staircase
// faces"; 10 grains wide, 10 x 14 x 14 and 7 x 24 x 12, came within 4 % in the wrapped bag, docs/results.md.)
TEST(LatticeCompression, SimpleCubicSlidesOnItsCubeFacesAtCoulombsStress) {
  const double p0 = 30e3;
  struct Case {
    Indices axis;
    int gx, ly, rz;
  };
  // [1 1 0]: x = [0 0 1] (period a), y = [1 -1 0] (layers a / sqrt2), z period sqrt2 a: 4a x 4.2a x 8.5a and 15.6a.
  // [1 1 1]: x = [1 0 -1] (period sqrt2 a), y = [-1 2 -1] (layers a / sqrt6), z period sqrt3 a: 5.7a x 5.7a x 12.1a
  // and 24.2a.
  const Case cases[] = {{{1, 1, 0}, 4, 6, 6}, {{1, 1, 0}, 4, 6, 11}, {{1, 1, 1}, 4, 14, 7}, {{1, 1, 1}, 4, 14, 14}};
  for (double f : {0.2, 0.35})
    for (const Case& c : cases) {
      CrystalParams p = crystal(LatticeType::sc, c.axis, c.gx, c.ly, c.rz, p0);
      EXPECT_EQ(p.confinement, Confinement::membrane);  // the default, the wrapped bag
      p.material.friction = f, p.wall_friction = f;
      p.max_strain = 8e-4;
      const double s1 = axial_first_yield(p) / p0;
      const double coulomb = c.axis[2] == 0 ? (1 + f) / (1 - f) : (std::sqrt(2.0) + 2 * f) / (std::sqrt(2.0) - f);
      EXPECT_NEAR(s1 / coulomb, 1.0, 0.10) << "f " << f << " [" << c.axis[0] << c.axis[1] << c.axis[2] << "] "
                                            << c.gx << " x " << c.ly << " x " << c.rz << ": " << s1 << " vs " << coulomb;
      std::printf("sc f = %.2f [%d %d %d] %d x %d x %d: first yield s1/p0 %.3f (Coulomb %.3f)\n", f, c.axis[0],
                  c.axis[1], c.axis[2], c.gx, c.ly, c.rz, s1, coulomb);
    }
}

}  // namespace
}  // namespace granulab
