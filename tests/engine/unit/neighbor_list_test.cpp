// Contact detection against a brute-force reference: random, overlapping RD clumps in random
// orientations. The neighbour list must hold exactly the sphere pairs of different grains closer than
// d + skin, never a pair inside one grain, and a rebuild must carry the history of surviving pairs.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <tuple>

#include "engine/contact/neighbor_list.h"
#include "engine/geometry/grain_template.h"

namespace granulab {
namespace {

using PairId = std::tuple<BodyId, BodyId, LocalSphereId, LocalSphereId>;

struct Scene {
  GrainTemplate grain{{Shape::rhombic_dodecahedron, 0.01, 5, 0.6}};
  Bodies bodies;
  std::vector<Vec3> spheres;
  std::vector<Wall> walls;

  Scene(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0, 0.02), unit(-1, 1);
    for (int k = 0; k < n; ++k) {
      const Quat q = Quat(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
      bodies.add(Vec3(pos(rng), pos(rng), pos(rng)), q, 1, Vec3(1, 1, 1), Motion::dynamic);
    }
    walls.push_back(Wall{Vec3(0, 0, 0.004), Vec3::UnitZ(), Vec3::Zero(), Vec3::Zero()});
    update();
  }
  void update() {
    spheres.clear();
    for (std::size_t b = 0; b < bodies.size(); ++b)
      for (const Vec3& o : grain.offsets()) spheres.push_back(bodies.position[b] + bodies.orientation[b] * o);
  }
  std::size_t per_body() const { return grain.sphere_count(); }
};

std::set<PairId> listed_pairs(const NeighborList& list) {
  std::set<PairId> out;
  for (const BodyPairSpan& gp : list.body_pairs())
    for (std::uint32_t k = gp.first; k < gp.first + gp.count; ++k)
      out.insert({gp.a, gp.b, key_first(list.keys()[k]), key_second(list.keys()[k])});
  return out;
}

std::set<PairId> brute_force_pairs(const Scene& s, double cutoff) {
  std::set<PairId> out;
  const std::size_t n = s.per_body();
  for (std::size_t a = 0; a < s.bodies.size(); ++a)
    for (std::size_t b = a + 1; b < s.bodies.size(); ++b)
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
          if ((s.spheres[a * n + i] - s.spheres[b * n + j]).norm() < cutoff)
            out.insert({BodyId(a), BodyId(b), LocalSphereId(i), LocalSphereId(j)});
  return out;
}

TEST(NeighborList, MatchesBruteForceOnRandomClumps) {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    Scene s(12, seed);
    const double skin = 0.1 * s.grain.diameter();
    NeighborList list(s.grain.offsets(), s.grain.diameter(), skin);
    list.rebuild(s.bodies, s.spheres, s.walls);
    const std::set<PairId> expected = brute_force_pairs(s, s.grain.diameter() + skin);
    ASSERT_GT(expected.size(), 100u) << "the scene must have real overlaps to test anything";
    EXPECT_EQ(listed_pairs(list), expected) << "seed " << seed;
    for (const BodyPairSpan& gp : list.body_pairs()) EXPECT_LT(gp.a, gp.b);  // never a pair inside one grain
    // Blocks are sorted, which the history merge relies on.
    for (const BodyPairSpan& gp : list.body_pairs())
      EXPECT_TRUE(std::is_sorted(list.keys().begin() + gp.first, list.keys().begin() + gp.first + gp.count));
  }
}

TEST(NeighborList, WallCandidatesMatchBruteForce) {
  Scene s(12, 7);
  const double skin = 0.1 * s.grain.diameter();
  NeighborList list(s.grain.offsets(), s.grain.diameter(), skin);
  list.rebuild(s.bodies, s.spheres, s.walls);
  std::vector<std::uint64_t> expected;
  for (std::size_t k = 0; k < s.spheres.size(); ++k)
    if (s.walls[0].distance(s.spheres[k]) < s.grain.radius() + skin) expected.push_back(wall_pair_key(0, std::uint32_t(k)));
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(list.wall_keys(), expected);
}

// Tag every pair's history with a value derived from its identity, move the grains, rebuild: pairs
// present before and after keep their tag, new pairs start from zero.
TEST(NeighborList, RebuildCarriesHistoryOfSurvivingPairs) {
  Scene s(12, 5);
  const double skin = 0.1 * s.grain.diameter();
  NeighborList list(s.grain.offsets(), s.grain.diameter(), skin);
  list.rebuild(s.bodies, s.spheres, s.walls);
  auto tag = [](const PairId& p) {
    return Vec3(std::get<0>(p) * 1000.0 + std::get<1>(p), std::get<2>(p), std::get<3>(p) + 0.5);
  };
  const std::set<PairId> before = listed_pairs(list);
  for (const BodyPairSpan& gp : list.body_pairs())
    for (std::uint32_t k = gp.first; k < gp.first + gp.count; ++k)
      list.history().set(k, tag({gp.a, gp.b, key_first(list.keys()[k]), key_second(list.keys()[k])}));

  std::mt19937 rng(11);
  std::normal_distribution<double> jiggle(0, 0.3 * s.grain.diameter());
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    s.bodies.position[b] += Vec3(jiggle(rng), jiggle(rng), jiggle(rng));
    s.bodies.orientation[b] = (s.bodies.orientation[b] * Quat(Eigen::AngleAxisd(0.05, Vec3::UnitY()))).normalized();
  }
  s.update();
  list.rebuild(s.bodies, s.spheres, s.walls);
  std::size_t kept = 0, fresh = 0;
  for (const BodyPairSpan& gp : list.body_pairs())
    for (std::uint32_t k = gp.first; k < gp.first + gp.count; ++k) {
      const PairId id{gp.a, gp.b, key_first(list.keys()[k]), key_second(list.keys()[k])};
      if (before.count(id)) {
        EXPECT_EQ(list.history().get(k), tag(id));
        ++kept;
      } else {
        EXPECT_EQ(list.history().get(k), Vec3::Zero());
        ++fresh;
      }
    }
  EXPECT_GT(kept, 0u);
  EXPECT_GT(fresh, 0u);
}

}  // namespace
}  // namespace granulab
