#include "engine/dynamics/integrator.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace granulab {

namespace {

// Up to this many bodies the loops here run on one thread. Entering a parallel region wakes the sleeping
// threads (passive waiting, the shared server's setting), which costs tens of microseconds, more than these
// loops' work at the reference crystal's 864 grains: serial, the integration stage fell from 0.32 to 0.12 ms
// per step (4 regions a step; the drift alone, 5 sin/cos per grain, still ran faster serial: 0.16 ms parallel).
constexpr long kParallelBodies = 4096;

// sin and cos of x (rad). A grain turns by about 1e-6 rad a step under quasi-static loading, and libm's sin and cos,
// ten calls per grain per step (the angle and its half, five rotations), were most of the integration stage on the
// reference crystal. Below |x| = 1e-2 their Taylor polynomials are exact to rounding: the first terms left out,
// x^9/9! and x^10/10!, are below 3e-22 of the result. (Horner's form with the coefficients as products: divisions
// by 6, 20, ... cost as much as the calls they replace.)
void sin_cos(double x, double& s, double& c) {
  if (std::abs(x) < 1e-2) {
    const double x2 = x * x;
    s = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040)));
    c = 1 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320))));
  } else {
    s = std::sin(x), c = std::cos(x);
  }
}

// Rotate the body about its own principal axis k for time h: angle phi = L_k/I_k h. The body frame
// turns by phi, so the body-frame momentum turns by -phi about the same axis.
void rotate_about_axis(int k, double h, const Vec3& inertia, Quat& q, Vec3& lb) {
  const double phi = lb[k] / inertia[k] * h;
  double c, s, half_c, half_s;
  sin_cos(phi, s, c);
  sin_cos(0.5 * phi, half_s, half_c);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const double li = lb[i], lj = lb[j];
  lb[i] = c * li + s * lj;
  lb[j] = -s * li + c * lj;
  Quat turn(half_c, 0, 0, 0);  // the rotation by phi about axis k
  turn.vec()[k] = half_s;
  q = q * turn;
}

// omega = R I^-1 R^T L: the world-frame angular velocity of a body of orientation q and principal inertia `inertia`.
Vec3 angular_velocity_of(const Quat& q, const Vec3& momentum, const Vec3& inertia) {
  return q * (q.conjugate() * momentum).cwiseQuotient(inertia);
}

}  // namespace

void kick(Bodies& b, double h) {
  const long n = long(b.size());
#pragma omp parallel for schedule(static) if (n > kParallelBodies)
  for (long k = 0; k < n; ++k) {
    if (b.motion[k] != Motion::dynamic) continue;
    b.velocity[k] += b.force[k] / b.mass[k] * h;
    b.angular_momentum[k] += b.torque[k] * h;
  }
}

namespace {

// The damping force of one vector quantity f against the rate u, component-wise: -lambda |f_c| sgn(u_c).
Vec3 local_damping_force(const Vec3& f, const Vec3& u, double lambda) {
  Vec3 d;
  for (int c = 0; c < 3; ++c) d[c] = u[c] > 0 ? -lambda * std::abs(f[c]) : u[c] < 0 ? lambda * std::abs(f[c]) : 0.0;
  return d;
}

}  // namespace

double kick(Bodies& b, double h, const LocalDamping& damping) {
  // The energy the damping took, summed in fixed blocks of kParallelBodies bodies and then block by block, so that
  // the sum is the same whatever the threads (an OpenMP reduction adds the threads' partial sums in an order of its
  // own). Up to kParallelBodies bodies this is the plain running sum.
  const long n = long(b.size()), blocks = (n + kParallelBodies - 1) / kParallelBodies;
  // The calling thread's buffer, kept between steps (no allocation once it has grown); the threads of the loop
  // below share it through this reference (each of them has a thread_local of its own).
  thread_local std::vector<double> buffer;
  std::vector<double>& taken_in = buffer;
  taken_in.assign(std::size_t(blocks), 0.0);
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (long block = 0; block < blocks; ++block) {
    double taken = 0;
    for (long k = block * kParallelBodies; k < std::min(n, (block + 1) * kParallelBodies); ++k) {
      if (b.motion[k] != Motion::dynamic) continue;
      const Vec3 v0 = b.velocity[k];
      const Vec3 fd = local_damping_force(b.force[k], v0, damping.translational);
      b.velocity[k] += (b.force[k] + fd) / b.mass[k] * h;
      const Vec3 td = local_damping_force(b.torque[k], b.angular_velocity[k], damping.rotational);
      b.angular_momentum[k] += (b.torque[k] + td) * h;
      taken -= fd.dot(v0 + b.velocity[k]) / 2 * h + td.dot(b.angular_velocity[k]) * h;
    }
    taken_in[std::size_t(block)] = taken;
  }
  double taken = 0;
  for (double t : taken_in) taken += t;
  return taken;
}

void drift(Bodies& b, double dt) {
  const long n = long(b.size());
#pragma omp parallel for schedule(static) if (n > kParallelBodies)
  for (long k = 0; k < n; ++k) {
    b.position[k] += b.velocity[k] * dt;
    Quat& q = b.orientation[k];
    if (b.motion[k] == Motion::dynamic) {
      Vec3 lb = q.conjugate() * b.angular_momentum[k];
      const Vec3& in = b.inertia[k];
      rotate_about_axis(0, dt / 2, in, q, lb);
      rotate_about_axis(1, dt / 2, in, q, lb);
      rotate_about_axis(2, dt, in, q, lb);
      rotate_about_axis(1, dt / 2, in, q, lb);
      rotate_about_axis(0, dt / 2, in, q, lb);
      q.normalize();
      b.angular_velocity[k] = q * lb.cwiseQuotient(in);
    } else {
      const Vec3& w = b.angular_velocity[k];
      const double angle = w.norm() * dt;
      if (angle > 0) q = (Quat(Eigen::AngleAxisd(angle, w.normalized())) * q).normalized();
    }
  }
}

void kicked_velocities(const Bodies& b, double h, std::vector<Vec3>& velocity, std::vector<Vec3>& angular_velocity) {
  const long n = long(b.size());
  velocity.resize(n), angular_velocity.resize(n);
#pragma omp parallel for schedule(static) if (n > kParallelBodies)
  for (long k = 0; k < n; ++k) {
    if (b.motion[k] != Motion::dynamic) {
      velocity[k] = b.velocity[k], angular_velocity[k] = b.angular_velocity[k];
      continue;
    }
    velocity[k] = b.velocity[k] + b.force[k] / b.mass[k] * h;
    angular_velocity[k] = angular_velocity_of(b.orientation[k], b.angular_momentum[k] + b.torque[k] * h, b.inertia[k]);
  }
}

void update_angular_velocity(Bodies& b) {
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (b.motion[k] != Motion::dynamic) continue;
    b.angular_velocity[k] = angular_velocity_of(b.orientation[k], b.angular_momentum[k], b.inertia[k]);
  }
}

}  // namespace granulab
