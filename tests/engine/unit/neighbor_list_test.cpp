// Contact detection against a brute-force reference: random, overlapping RD clumps in random
// orientations. The neighbour list must hold exactly the sphere pairs of different grains closer than
// d + skin when built, never a pair inside one grain, carry the history of surviving pairs, and, as the
// grains move, search again only the grain pairs whose relative pose drifted, never missing a pair
// that comes within d.
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
    list.update(s.bodies, s.walls);
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
  list.update(s.bodies, s.walls);
  std::vector<std::uint64_t> expected;
  for (std::size_t k = 0; k < s.spheres.size(); ++k)
    if (s.walls[0].distance(s.spheres[k]) < s.grain.radius() + skin)
      expected.push_back(wall_pair_key(0, std::uint32_t(k)));
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(list.wall_keys(), expected);
}

// Tag every pair's history with a value derived from its identity, move the grains, rebuild: pairs
// present before and after keep their tag, new pairs start from zero.
TEST(NeighborList, RebuildCarriesHistoryOfSurvivingPairs) {
  Scene s(12, 5);
  const double skin = 0.1 * s.grain.diameter();
  NeighborList list(s.grain.offsets(), s.grain.diameter(), skin);
  list.update(s.bodies, s.walls);
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
  list.update(s.bodies, s.walls);
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

// Grains jiggle a little at every update, like a dynamic run: after each update() every sphere pair
// closer than d (a contact) must be listed, while most grain pairs keep their lists.
TEST(NeighborList, DriftingGrainsNeverLoseAContact) {
  Scene s(12, 3);
  const double d = s.grain.diameter(), skin = 0.05 * d;
  NeighborList list(s.grain.offsets(), d, skin);
  list.update(s.bodies, s.walls);
  std::mt19937 rng(5);
  std::normal_distribution<double> jiggle(0, 0.004 * d), turn(0, 0.0004);
  std::size_t searched = 0, watched = 0, updates = 0;
  for (int step = 0; step < 60; ++step) {
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      s.bodies.position[b] += Vec3(jiggle(rng), jiggle(rng), jiggle(rng));
      s.bodies.orientation[b] =
          (s.bodies.orientation[b] * Quat(Eigen::AngleAxisd(turn(rng), Vec3(1, 2, 3).normalized()))).normalized();
    }
    s.update();
    const NeighborUpdate u = list.update(s.bodies, s.walls);
    ASSERT_FALSE(u.broad) << "the grains moved far less than the margin";
    searched += u.pairs_searched;
    watched += list.body_pairs().size();
    updates += u.pairs_searched > 0;
    const std::set<PairId> listed = listed_pairs(list);
    for (const PairId& p : brute_force_pairs(s, d)) ASSERT_TRUE(listed.count(p)) << "step " << step;
  }
  EXPECT_GT(updates, 0u) << "the grains must drift far enough to need searches";
  EXPECT_LT(searched, watched / 2) << "most grain pairs keep their lists from one update to the next";
}

// A rigid motion of the whole scene changes no relative pose: nothing is searched again (the old rule,
// any sphere moved half a skin, searched everything once the scene had moved that far).
TEST(NeighborList, RigidMotionOfTheWholeSceneSearchesNothing) {
  Scene s(12, 4);
  const double d = s.grain.diameter(), skin = 0.05 * d;
  s.walls.clear();
  NeighborList list(s.grain.offsets(), d, skin);
  list.update(s.bodies, s.walls);
  const std::set<PairId> before = listed_pairs(list);
  const Quat turn(Eigen::AngleAxisd(0.02, Vec3(0, 1, 1).normalized()));
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    s.bodies.position[b] = turn * s.bodies.position[b] + Vec3(0.3 * d, 0, 0);
    s.bodies.orientation[b] = (turn * s.bodies.orientation[b]).normalized();
  }
  const NeighborUpdate u = list.update(s.bodies, s.walls);
  EXPECT_FALSE(u.any());
  EXPECT_EQ(listed_pairs(list), before);
}

}  // namespace
}  // namespace granulab
