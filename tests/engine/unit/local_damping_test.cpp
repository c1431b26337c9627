// Local (non-viscous) damping of a body as a whole (integrator.h, LocalDamping), against closed forms:
//  - a mass on a linear spring, x'' = -w^2 x - lambda |w^2 x| sgn(v) (per component): moving toward the origin the
//    force is (1 - lambda) w^2 x, moving away (1 + lambda) w^2 x, so from a turning point A the next one is A' with
//    (1 + lambda) A'^2 = (1 - lambda) A^2: each half cycle keeps sqrt((1 - lambda) / (1 + lambda)) of the amplitude,
//    whatever w (0.8165 at lambda = 0.2). The energy the damping reports is the spring-mass energy lost;
//  - steady motion under no force, and a body at rest, lose nothing: the damping acts on forces, not velocities;
//  - the same on a torque: a free rotor spun up by a constant torque gains (1 - lambda) of it;
//  - above the size where its loop runs in parallel, the energy it reports has the same bits on 1 and 2 threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "engine/dynamics/integrator.h"

namespace granulab {
namespace {

struct Oscillator {
  Bodies b;
  double k = 4.0, m = 1.0;  // w = 2 rad/s
  Oscillator() { b.add(Vec3(1, 0, 0), Quat::Identity(), m, Vec3(1, 1, 1), Motion::dynamic); }
  void force() { b.force[0] = -k * b.position[0]; b.torque[0].setZero(); }
  double energy() const { return 0.5 * m * b.velocity[0].squaredNorm() + 0.5 * k * b.position[0].squaredNorm(); }
};

TEST(LocalDamping, EachHalfCycleKeepsTheClosedFormShareOfTheAmplitude) {
  for (double lambda : {0.1, 0.2, 0.5}) {
    Oscillator o;
    const LocalDamping d{lambda, lambda};
    const double dt = 1e-5, e0 = o.energy();
    double taken = 0, previous_v = 0, turning = 1;
    int half_cycles = 0;
    o.force();
    for (int step = 0; step < 2000000 && half_cycles < 4; ++step) {
      taken += kick(o.b, dt / 2, d);
      drift(o.b, dt);
      o.force();
      taken += kick(o.b, dt / 2, d);
      // A turning point: the velocity changed sign within the step (x there to O(v dt)).
      const double v = o.b.velocity[0].x(), x = o.b.position[0].x();
      if (previous_v * v < 0) {
        EXPECT_NEAR(std::abs(x) / std::abs(turning), std::sqrt((1 - lambda) / (1 + lambda)), 1e-4)
            << "lambda " << lambda << ", half cycle " << half_cycles;
        turning = x;
        ++half_cycles;
      }
      previous_v = v;
    }
    EXPECT_EQ(half_cycles, 4) << "lambda " << lambda;
    EXPECT_NEAR(taken, e0 - o.energy(), 1e-6 * e0) << "lambda " << lambda;
  }
}

TEST(LocalDamping, SteadyMotionAndRestLoseNothing) {
  Bodies b;
  b.add(Vec3::Zero(), Quat::Identity(), 2.0, Vec3(1, 2, 3), Motion::dynamic);
  b.add(Vec3(1, 0, 0), Quat::Identity(), 2.0, Vec3(1, 2, 3), Motion::dynamic);
  b.velocity[0] = Vec3(1, -2, 3);
  b.force[0].setZero(), b.force[1] = Vec3(0.5, 0, 0);
  b.torque[0].setZero(), b.torque[1].setZero();
  EXPECT_EQ(kick(b, 1e-3, LocalDamping{0.7, 0.7}), 0.0);
  EXPECT_EQ(b.velocity[0], Vec3(1, -2, 3));
  EXPECT_DOUBLE_EQ(b.velocity[1].x(), 0.5 / 2.0 * 1e-3) << "from rest the first kick is undamped (sgn 0 = 0)";
}

TEST(LocalDamping, ATorqueSpinsAFreeRotorUpAtOneMinusLambdaOfIt) {
  Bodies b;
  b.add(Vec3::Zero(), Quat::Identity(), 1.0, Vec3(2, 2, 2), Motion::dynamic);
  const double tau = 0.3, lambda = 0.25, dt = 1e-4;
  b.force[0].setZero();
  b.torque[0] = Vec3(0, 0, tau);
  double taken = 0;
  for (int step = 0; step < 10000; ++step) {
    taken += kick(b, dt / 2, LocalDamping{0, lambda});
    drift(b, dt);
    taken += kick(b, dt / 2, LocalDamping{0, lambda});
  }
  // After the first half kick the rotor spins along +z, so every later kick gets (1 - lambda) tau.
  const double l = b.angular_momentum[0].z(), expected = tau * dt / 2 + (1 - lambda) * tau * (10000 * dt - dt / 2);
  EXPECT_NEAR(l, expected, 1e-12);
  // The damping torque lambda tau against omega(t) = (1 - lambda) tau t / I: lambda (1 - lambda) tau^2 T^2 / (2 I).
  const double t = 10000 * dt, work = lambda * (1 - lambda) * tau * tau * t * t / (2 * 2.0);
  EXPECT_NEAR(taken, work, 1e-3 * work);
}

// 20,000 bodies (above integrator.cpp's 4,096, where the loop runs in parallel) with forces, torques and velocities of
// mixed signs and magnitudes spread over six decades, so that summing the energies in another order changes the last
// bits: an OpenMP reduction did (the threads' partial sums added in an order of its own).
TEST(LocalDamping, TheEnergyTakenHasTheSameBitsOnOneAndTwoThreads) {
  const auto taken = [](int threads) {
    Bodies b;
    for (int k = 0; k < 20000; ++k) {
      const double s = std::pow(10.0, (k * 7919) % 600 / 100.0);  // 1 to 1e6
      b.add(Vec3(k, 0, 0), Quat::Identity(), 1.0 + k % 13, Vec3(1, 2, 3), Motion::dynamic);
      b.velocity[k] = Vec3(std::sin(k), std::cos(3.0 * k), std::sin(7.0 * k)) * s;
      b.angular_momentum[k] = Vec3(std::cos(k), std::sin(5.0 * k), std::cos(2.0 * k));
      b.force[k] = Vec3(std::cos(11.0 * k), std::sin(13.0 * k), std::cos(17.0 * k)) * s;
      b.torque[k] = Vec3(std::sin(19.0 * k), std::cos(23.0 * k), std::sin(29.0 * k));
    }
    b.angular_velocity = b.angular_momentum;  // any rates: only the signs matter to the damping
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    int ran = 0;
#pragma omp parallel
#pragma omp single
    ran = omp_get_num_threads();
    EXPECT_EQ(ran, threads) << "the OpenMP runtime did not give the threads asked for";
    const double e = kick(b, 1e-4, LocalDamping{0.2, 0.3});
    omp_set_num_threads(before);
    return e;
  };
  const double one = taken(1), two = taken(2);
  EXPECT_GT(one, 0);
  EXPECT_EQ(one, two) << "difference " << one - two;
}

}  // namespace
}  // namespace granulab
