// Properties of the time-step loop itself, on a dense block of RD clumps (outer shell held, inside
// free): no heap allocation in a step that does not rebuild the neighbour list, and the same answer,
// bit for bit, for 1 and 2 threads (contact forces go to per-grain-pair slots reduced in pair order).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "engine/model/model.h"
#include "engine/world/world.h"

namespace {
std::atomic<long> g_allocations{0};
}

// Count every allocation of this test program.
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace granulab {
namespace {

// 3^3 = 27 RD grains (N_e = 6) on the FCC lattice with a 0.5 % pre-strain. With `hold_shell` the 26
// outer ones are held and the centre one is kicked, so contacts load, shear and slide; otherwise all
// are free and the block springs apart (and rotates, hits the wall, rebuilds its neighbour list).
World make_block(bool hold_shell, DampingVelocity dashpots = DampingVelocity::half_step) {
  const GrainTemplate grain({Shape::rhombic_dodecahedron, 0.01, 6, 0.75});
  Material mat;
  mat.friction = 0.1;
  const double dt = 0.2 * contact_time_scale(grain, mat.youngs_modulus, mat.density);
  WorldSettings settings{dt, 0.1 * grain.diameter(), Vec3::Zero()};
  settings.damping_velocity = dashpots;
  World world(grain, contact_law(grain, mat), settings);
  const double cell = 0.01 * 0.995;
  const Vec3 p1(0.5, 0.5, 0), p2(0.5, 0, 0.5), p3(0, 0.5, 0.5);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const bool centre = i == 1 && j == 1 && k == 1;
        const BodyId b = world.add_grain(cell * (i * p1 + j * p2 + k * p3), Quat::Identity(), mat.density,
                                         centre || !hold_shell ? Motion::dynamic : Motion::prescribed);
        if (centre) {
          world.bodies().velocity[b] = Vec3(0.02, -0.01, 0.015);
          world.bodies().angular_momentum[b] = Vec3(1e-9, 2e-9, -1e-9);
        }
      }
  world.add_wall(Wall{Vec3(0, 0, -0.004), Vec3::UnitZ(), Vec3::Zero(), Vec3::Zero()});
  world.compute_forces();
  return world;
}

TEST(Step, NoHeapAllocationBetweenRebuilds) {
  World world = make_block(true);
  for (int k = 0; k < 20; ++k) world.step();  // warm up: OpenMP team, first rebuild buffers
  long steps_without_rebuild = 0;
  for (int k = 0; k < 200; ++k) {
    const std::uint64_t rebuilds = world.rebuilds();
    const long before = g_allocations.load();
    world.step();
    if (world.rebuilds() == rebuilds) {
      EXPECT_EQ(g_allocations.load() - before, 0) << "step " << k;
      ++steps_without_rebuild;
    }
  }
  EXPECT_GT(steps_without_rebuild, 100);
  EXPECT_GT(world.contact_stats().contacts, 0u);
}

// For both dashpot velocities (world.h, DampingVelocity; the crystals' default is the quarter step).
TEST(Step, OneAndTwoThreadsGiveIdenticalResults) {
  for (DampingVelocity dashpots : {DampingVelocity::half_step, DampingVelocity::quarter_step}) {
    auto run = [dashpots](int threads) {
      omp_set_num_threads(threads);
      World world = make_block(false, dashpots);
      std::size_t sliding_steps = 0;  // sum over steps of the sliding contacts
      Vec3 wall_impulse = Vec3::Zero();
      for (int k = 0; k < 3000; ++k) {
        world.step();
        sliding_steps += world.contact_stats().sliding;
        wall_impulse += world.walls()[0].force;
      }
      omp_set_num_threads(omp_get_num_procs());
      const BodyId centre = 13;
      return std::make_tuple(world.bodies().position[centre], world.bodies().orientation[centre].coeffs().eval(),
                             wall_impulse, sliding_steps, world.rebuilds());
    };
    const auto one = run(1), two = run(2);
    SCOPED_TRACE(dashpots == DampingVelocity::half_step ? "half step" : "quarter step");
    // Same operations in the same order: bitwise equal, not merely close.
    EXPECT_EQ(std::get<0>(one), std::get<0>(two));
    EXPECT_EQ(std::get<1>(one), std::get<1>(two));
    EXPECT_EQ(std::get<2>(one), std::get<2>(two));
    EXPECT_EQ(std::get<3>(one), std::get<3>(two));
    EXPECT_EQ(std::get<4>(one), std::get<4>(two));
    EXPECT_GT(std::get<4>(one), 3u) << "the grains must move far enough to force rebuilds";
    EXPECT_GT(std::get<3>(one), 0u) << "some contacts must slide";
    EXPECT_GT(std::get<2>(one).norm(), 0) << "the block must hit the wall";
  }
}

// Above integrator.cpp's 4,096 bodies its per-grain loops run in parallel again (below they run on one thread): 1 and
// 2 threads on 16 x 16 x 17 = 4,352 cubes of 8 spheres, squeezed 0.5 % on a simple cubic lattice so that they spring
// apart and turn, with the quarter-step dashpots (kicked_velocities) and local damping (its kick), give the same bits.
TEST(Step, OneAndTwoThreadsAgreeAboveTheSerialIntegratorsSize) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    const GrainTemplate grain({Shape::cube, 0.01, 2, 0.5});
    Material mat;
    mat.friction = 0.2;
    WorldSettings settings{0.2 * contact_time_scale(grain, mat.youngs_modulus, mat.density), 0.1 * grain.diameter(),
                           Vec3::Zero()};
    settings.damping_velocity = DampingVelocity::quarter_step;
    settings.local_damping = {0.1, 0.1};
    World world(grain, contact_law(grain, mat), settings);
    const double cell = 0.01 * 0.995;
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j)
        for (int k = 0; k < 17; ++k) {
          const BodyId b = world.add_grain(cell * Vec3(i, j, k), Quat::Identity(), mat.density, Motion::dynamic);
          world.bodies().angular_momentum[b] = Vec3(1e-10 * ((i + 2 * j + 3 * k) % 7 - 3), 0, 1e-10 * (i % 3 - 1));
        }
    world.compute_forces();
    for (int s = 0; s < 300; ++s) world.step();
    omp_set_num_threads(omp_get_num_procs());
    return std::make_pair(world.bodies().position, world.bodies().orientation);
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.first.size(), 4352u);
  double moved = 0;
  for (std::size_t b = 0; b < one.first.size(); ++b) {
    EXPECT_EQ(one.first[b], two.first[b]) << "grain " << b;
    EXPECT_EQ(one.second[b].coeffs(), two.second[b].coeffs()) << "grain " << b;
    moved = std::max(moved, (one.first[b] - 0.01 * 0.995 * Vec3(b / (16 * 17), b / 17 % 16, b % 17)).norm());
  }
  EXPECT_GT(moved, 1e-7) << "the squeezed cubes must move";
}

}  // namespace
}  // namespace granulab
