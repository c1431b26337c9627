#include "engine/contact/pair_kernel.h"

#include <cmath>

namespace granulab {

OffsetArrays::OffsetArrays(const std::vector<Vec3>& offsets) {
  for (const Vec3& o : offsets) x.push_back(o.x()), y.push_back(o.y()), z.push_back(o.z());
}

PairKernelSums pair_contacts(const PairKernelConstants& c, const OffsetArrays& offsets, const std::uint32_t* keys,
                             std::uint32_t count, double* history_x, double* history_y, double* history_z) {
  const double *ox = offsets.x.data(), *oy = offsets.y.data(), *oz = offsets.z.data();
  const double a00 = c.ra(0, 0), a01 = c.ra(0, 1), a02 = c.ra(0, 2), a10 = c.ra(1, 0), a11 = c.ra(1, 1),
               a12 = c.ra(1, 2), a20 = c.ra(2, 0), a21 = c.ra(2, 1), a22 = c.ra(2, 2);
  const double b00 = c.rb(0, 0), b01 = c.rb(0, 1), b02 = c.rb(0, 2), b10 = c.rb(1, 0), b11 = c.rb(1, 1),
               b12 = c.rb(1, 2), b20 = c.rb(2, 0), b21 = c.rb(2, 1), b22 = c.rb(2, 2);
  const double dxx = c.xa.x() - c.xb.x(), dxy = c.xa.y() - c.xb.y(), dxz = c.xa.z() - c.xb.z();
  const double d = c.diameter, d2 = d * d, radius = c.radius, kn = c.kn, kt = c.kt, cn = c.cn, ct = c.ct;
  const double mu = c.friction, dt = c.dt, inv_kt = kt > 0 ? 1 / kt : 0;
  const double v0x = c.v0.x(), v0y = c.v0.y(), v0z = c.v0.z();
  const double dwx = c.dw.x(), dwy = c.dw.y(), dwz = c.dw.z();
  double fx = 0, fy = 0, fz = 0, mx = 0, my = 0, mz = 0, overlap = 0, energy = 0;
  std::uint32_t contacts = 0, sliding = 0;

#pragma omp simd reduction(+ : fx, fy, fz, mx, my, mz, overlap, energy, contacts, sliding)
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t i = keys[k] >> 16, j = keys[k] & 0xffff;
    // Sphere i of a relative to x_a, sphere j of b relative to x_b, both in the world frame.
    const double oix = ox[i], oiy = oy[i], oiz = oz[i], ojx = ox[j], ojy = oy[j], ojz = oz[j];
    const double ax = a00 * oix + a01 * oiy + a02 * oiz, ay = a10 * oix + a11 * oiy + a12 * oiz,
                 az = a20 * oix + a21 * oiy + a22 * oiz;
    const double bx = b00 * ojx + b01 * ojy + b02 * ojz, by = b10 * ojx + b11 * ojy + b12 * ojz,
                 bz = b20 * ojx + b21 * ojy + b22 * ojz;
    const double rx = dxx + ax - bx, ry = dxy + ay - by, rz = dxz + az - bz;
    const double dist2 = rx * rx + ry * ry + rz * rz;
    const bool touching = dist2 < d2;
    const double inv = 1 / std::sqrt(dist2);
    const double delta = d - dist2 * inv;
    const double nx = rx * inv, ny = ry * inv, nz = rz * inv;
    // Contact point relative to x_a, and the relative velocity there.
    const double lever = radius - 0.5 * delta;
    const double px = ax - lever * nx, py = ay - lever * ny, pz = az - lever * nz;
    const double vx = v0x + dwy * pz - dwz * py, vy = v0y + dwz * px - dwx * pz, vz = v0z + dwx * py - dwy * px;
    const double vn = vx * nx + vy * ny + vz * nz;
    const double tx = vx - vn * nx, ty = vy - vn * ny, tz = vz - vn * nz;
    const double fn = kn * delta - cn * vn;

    // Shear history: into the current tangent plane, length kept, then the tangential increment.
    double hx = history_x[k], hy = history_y[k], hz = history_z[k];
    const double len2 = hx * hx + hy * hy + hz * hz;
    const double along = hx * nx + hy * ny + hz * nz;
    hx -= along * nx, hy -= along * ny, hz -= along * nz;
    const double proj2 = hx * hx + hy * hy + hz * hz;
    const double keep = proj2 > 0 ? std::sqrt(len2 / proj2) : 1.0;
    hx = hx * keep + tx * dt, hy = hy * keep + ty * dt, hz = hz * keep + tz * dt;

    // Tangential force with the Coulomb cap; on slip the spring is reset to match the cap.
    double gx = -kt * hx - ct * tx, gy = -kt * hy - ct * ty, gz = -kt * hz - ct * tz;
    const double cap = mu * std::abs(fn);
    const double g2 = gx * gx + gy * gy + gz * gz;
    const bool slip = g2 > cap * cap;
    const double scale = slip ? cap / std::sqrt(g2) : 1.0;
    gx *= scale, gy *= scale, gz *= scale;
    hx = slip ? -(gx + ct * tx) * inv_kt : hx;
    hy = slip ? -(gy + ct * ty) * inv_kt : hy;
    hz = slip ? -(gz + ct * tz) * inv_kt : hz;

    // Separated pairs forget their history and exert nothing.
    history_x[k] = touching ? hx : 0.0, history_y[k] = touching ? hy : 0.0, history_z[k] = touching ? hz : 0.0;
    const double Fx = touching ? fn * nx + gx : 0.0, Fy = touching ? fn * ny + gy : 0.0, Fz = touching ? fn * nz + gz : 0.0;
    fx += Fx, fy += Fy, fz += Fz;
    mx += py * Fz - pz * Fy, my += pz * Fx - px * Fz, mz += px * Fy - py * Fx;
    contacts += touching;
    sliding += touching && slip;
    overlap += touching ? delta : 0.0;
    energy += touching ? 0.5 * kn * delta * delta + 0.5 * kt * (hx * hx + hy * hy + hz * hz) : 0.0;
  }
  PairKernelSums s;
  s.force = Vec3(fx, fy, fz);
  s.moment = Vec3(mx, my, mz);
  s.contacts = contacts, s.sliding = sliding, s.overlap = overlap, s.energy = energy;
  return s;
}

}  // namespace granulab
