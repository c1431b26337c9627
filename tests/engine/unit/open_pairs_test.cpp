// Grain pairs skipped while apart (engine/world/open_pairs.h) must never miss a contact: a grain closing in on
// another while it spins is stepped across the gap, and at every step the world's contacts are compared with a
// brute-force count over the spheres' positions. The pair must also have been skipped on the way (the skipping is
// what is tested), and the contacts found must begin at the step the geometry says.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {
namespace {

struct Nearest {
  double distance = 1e300;  // nearest centres of a sphere of body 0 and one of body 1 (m)
  std::size_t touching = 0;  // sphere pairs closer than d
};

Nearest brute_force(const World& w, std::size_t per_body, double d) {
  const std::vector<Vec3>& x = w.sphere_positions();
  Nearest out;
  for (std::size_t i = 0; i < per_body; ++i)
    for (std::size_t j = per_body; j < 2 * per_body; ++j) {
      const double r2 = (x[i] - x[j]).squaredNorm();
      out.distance = std::min(out.distance, std::sqrt(r2));
      out.touching += r2 < d * d;
    }
  return out;
}

// Grain b starts `gap` (m) beyond touching along `dir` from grain a (fixed) and moves back along it at `speed`
// (m/s) while spinning at `spin` (rad/s); both are prescribed, so their motion is known whatever the contacts do.
void close_in(const Vec3& dir, const Quat& qb, double gap_share, const Vec3& spin, bool approach = true) {
  const GrainTemplate grain({Shape::rhombic_dodecahedron, 0.01, 5, 0.6});
  Material mat;
  const double d = grain.diameter();
  const double dt = 0.2 * contact_time_scale(grain, mat.youngs_modulus, mat.density);
  WorldSettings settings;
  settings.time_step = dt, settings.skin = 0.1 * d;
  World world(grain, contact_law(grain, mat), settings);
  const Vec3 u = dir.normalized();
  world.add_grain(Vec3::Zero(), Quat::Identity(), mat.density, Motion::prescribed);
  const BodyId b = world.add_grain(u * 0.012, qb, mat.density, Motion::prescribed);
  const std::size_t per_body = grain.sphere_count();
  // Place b so that its nearest spheres are d (1 + gap_share) apart: the nearest pair's distance changes with the
  // centre distance at a rate of about 1 near contact.
  for (int it = 0; it < 50; ++it) {
    const double miss = brute_force(world, per_body, d).distance - d * (1 + gap_share);
    if (std::abs(miss) < 1e-9 * d) break;
    world.bodies().position[b] -= u * miss;
    world.step();  // refreshes the sphere positions (no velocity yet: nothing moves)
  }
  // Closing the gap in about 300 steps, the spin moving b's outer spheres about as fast.
  const double speed = gap_share * d / (300 * dt);
  world.bodies().velocity[b] = approach ? Vec3(-u * speed) : Vec3::Zero();
  world.bodies().angular_velocity[b] = spin * speed / (grain.bounding_radius() - grain.radius());
  std::size_t skipped_steps = 0, first_contact = 0;
  for (std::size_t step = 1; step <= 500; ++step) {
    world.step();
    const Nearest truth = brute_force(world, per_body, d);
    ASSERT_EQ(world.contact_stats().contacts, truth.touching)
        << "step " << step << ": nearest centres " << truth.distance / d << " d apart";
    skipped_steps += world.contact_stats().skipped > 0;
    if (truth.touching > 0 && first_contact == 0) first_contact = step;
  }
  EXPECT_GT(first_contact, 0u) << "the grains must meet within the run";
  // While apart, the pair is evaluated only when it may have closed its last measured gap: at least half the steps
  // before contact are skipped.
  EXPECT_GT(skipped_steps, first_contact / 2) << "first contact at step " << first_contact;
}

TEST(OpenPairs, AGrainClosingInIsFoundAtTheStepItTouches) { close_in(Vec3(1, 0.3, 0.2), Quat::Identity(), 0.05, Vec3::Zero()); }

TEST(OpenPairs, ASpinningGrainClosingInIsFoundAtTheStepItTouches) {
  close_in(Vec3(0.2, 1, -0.4), Quat(Eigen::AngleAxisd(0.9, Vec3(1, 2, 3).normalized())), 0.05,
           Vec3(0.3, -1, 2).normalized());
}

// Spinning on the spot, no approach: only the rotation brings b's corner spheres onto a's.
TEST(OpenPairs, AGrainTurningOntoAnotherIsFoundAtTheStepItTouches) {
  close_in(Vec3(1, 1, 0), Quat(Eigen::AngleAxisd(0.4, Vec3(0, 0, 1))), 0.03, Vec3(0, 0, 3), false);
}

}  // namespace
}  // namespace granulab
