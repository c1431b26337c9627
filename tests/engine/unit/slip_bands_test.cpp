// Slip bands found and named (docs/model.md, "Slip bands"), on synthetic snapshots of an FCC block of sites (cubic
// axes, 5 x 5 x 5 cells, 500 grains):
//  - half the crystal shifted rigidly across one (1 1 1) plane, along [1 -1 0]: exactly one band, on (1 1 1) (the
//    fitted plane within 1 degree of it), with the imposed slip (to 1e-9 m), direction [1 -1 0] and no dilation;
//  - two crossing shifts, across (1 1 1) along [1 -1 0] and across (1 1 -1) along [1 0 1]: two bands, those two
//    planes, each with its own slip direction;
//  - nothing shifted: no band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/analysis/grain_kinematics.h"
#include "engine/analysis/slip_bands.h"

namespace granulab {
namespace {

constexpr double kA = 0.01;

struct Shift {
  Vec3 normal;   // the plane's normal (crystal = lab frame here)
  double cut;    // the grains with normal . x / a above it move
  Vec3 by;       // (m)
};

GrainSnapshot shifted_block(const std::vector<Shift>& shifts) {
  const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<Vec3> ref;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k)
        for (const Vec3& b : basis) ref.push_back(kA * (Vec3(i, j, k) + b));
  GrainSnapshot s;
  s.grain_shape = Shape::rhombic_dodecahedron;
  s.grain_size = kA;
  s.crystal_orientation = Quat::Identity();
  const std::vector<BodyPair> pairs = neighbour_pairs(ref, 1.1 * kA / std::sqrt(2.0));
  std::vector<Quat> q(ref.size(), Quat::Identity());
  for (std::size_t i = 0; i < ref.size(); ++i) {
    Vec3 d = Vec3::Zero();
    for (const Shift& f : shifts)
      if (f.normal.dot(ref[i]) / kA > f.cut) d += f.by;
    s.id.push_back(GrainId(std::uint32_t(i)));
    s.displacement.push_back(d);
    s.position.push_back(ref[i] + d);
    s.orientation.push_back(q[i]);
  }
  std::vector<Vec3> cur = s.position;
  for (const auto& [a, b] : pairs) s.interfaces.push_back({GrainId(std::uint32_t(a)), GrainId(std::uint32_t(b))});
  s.sliding = interface_sliding(ref, q, cur, q, pairs);
  return s;
}

bool same_plane(const SlipBand& b, Indices want) {
  const Indices got{b.plane[0], b.plane[1], b.plane[2]};
  const Indices minus{-want[0], -want[1], -want[2]};
  return got == want || got == minus;
}

bool same_direction(const SlipBand& b, Indices want) {
  const Indices got{b.direction[0], b.direction[1], b.direction[2]};
  return got == want;
}

TEST(SlipBands, OneRigidShiftIsOneBandOnItsPlane) {
  const Vec3 n = Vec3(1, 1, 1).normalized(), along = Vec3(1, -1, 0).normalized();
  const double slip = 2e-4;
  const GrainSnapshot s = shifted_block({{n, 5.5 / std::sqrt(3.0), slip * along}});
  const std::vector<SlipBand> bands = find_slip_bands(s, LatticeType::fcc);
  ASSERT_EQ(bands.size(), 1u);
  const SlipBand& b = bands[0];
  EXPECT_TRUE(same_plane(b, {1, 1, 1})) << band_plane_text(b, LatticeType::fcc);
  EXPECT_LT(b.angle_to_plane, 1.0);
  EXPECT_NEAR(b.slip, slip, 1e-9);
  // The side the fitted normal points to moved: along +[1 -1 0] or, seen from the other side, -[1 -1 0].
  const Vec3 normal(b.normal[0], b.normal[1], b.normal[2]);
  const Indices expected = normal.dot(n) > 0 ? Indices{1, -1, 0} : Indices{-1, 1, 0};
  EXPECT_TRUE(same_direction(b, expected)) << b.direction[0] << " " << b.direction[1] << " " << b.direction[2];
  EXPECT_LT(b.direction_angle, 1e-6);
  EXPECT_NEAR(b.dilation_angle, 0, 1e-6);
  EXPECT_GT(b.interfaces, 30u);
  EXPECT_GT(b.extent, 3 * kA);
}

TEST(SlipBands, TwoCrossingShiftsAreTwoBands) {
  const Vec3 n1 = Vec3(1, 1, 1).normalized(), n2 = Vec3(1, 1, -1).normalized();
  const GrainSnapshot s = shifted_block({{n1, 5.5 / std::sqrt(3.0), 2e-4 * Vec3(1, -1, 0).normalized()},
                                         {n2, 2.5 / std::sqrt(3.0), 1.5e-4 * Vec3(1, 0, 1).normalized()}});
  const std::vector<SlipBand> bands = find_slip_bands(s, LatticeType::fcc);
  ASSERT_EQ(bands.size(), 2u);
  const bool first_is_111 = same_plane(bands[0], {1, 1, 1});
  const SlipBand& b111 = first_is_111 ? bands[0] : bands[1];
  const SlipBand& b11m = first_is_111 ? bands[1] : bands[0];
  EXPECT_TRUE(same_plane(b111, {1, 1, 1}));
  EXPECT_TRUE(same_plane(b11m, {1, 1, -1}));
  for (const SlipBand* b : {&b111, &b11m}) EXPECT_LT(b->angle_to_plane, 1.0);
  EXPECT_NEAR(b111.slip, 2e-4, 2e-5);  // the interfaces where the bands cross carry both shifts
  EXPECT_NEAR(b11m.slip, 1.5e-4, 2e-5);
  EXPECT_LT(b111.direction_angle, 10.0);
  EXPECT_LT(b11m.direction_angle, 10.0);
}

TEST(SlipBands, NothingShiftedIsNoBand) {
  EXPECT_TRUE(find_slip_bands(shifted_block({}), LatticeType::fcc).empty());
}

}  // namespace
}  // namespace granulab
