#include "engine/contact/pair_kernel.h"

#include <cmath>

namespace granulab {

OffsetArrays::OffsetArrays(const std::vector<Vec3>& offsets) {
  for (const Vec3& o : offsets) x.push_back(o.x()), y.push_back(o.y()), z.push_back(o.z());
}

namespace {

// The constants of one grain pair, unpacked into scalars for the vector loops.
struct Frame {
  double a00, a01, a02, a10, a11, a12, a20, a21, a22;
  double b00, b01, b02, b10, b11, b12, b20, b21, b22;
  double dxx, dxy, dxz, d2;
  explicit Frame(const PairKernelConstants& c)
      : a00(c.ra(0, 0)),
        a01(c.ra(0, 1)),
        a02(c.ra(0, 2)),
        a10(c.ra(1, 0)),
        a11(c.ra(1, 1)),
        a12(c.ra(1, 2)),
        a20(c.ra(2, 0)),
        a21(c.ra(2, 1)),
        a22(c.ra(2, 2)),
        b00(c.rb(0, 0)),
        b01(c.rb(0, 1)),
        b02(c.rb(0, 2)),
        b10(c.rb(1, 0)),
        b11(c.rb(1, 1)),
        b12(c.rb(1, 2)),
        b20(c.rb(2, 0)),
        b21(c.rb(2, 1)),
        b22(c.rb(2, 2)),
        dxx(c.xa.x() - c.xb.x()),
        dxy(c.xa.y() - c.xb.y()),
        dxz(c.xa.z() - c.xb.z()),
        d2(c.diameter * c.diameter) {}
};

// Sphere i of a relative to x_a (a*) and the centre-to-centre vector r = c_i - c_j, both in the world frame.
struct Relative {
  double ax, ay, az, rx, ry, rz;
};

inline __attribute__((always_inline)) Relative relative(const Frame& f, const OffsetArrays& o, std::uint32_t key) {
  const std::uint32_t i = key >> 16, j = key & 0xffff;
  const double oix = o.x[i], oiy = o.y[i], oiz = o.z[i], ojx = o.x[j], ojy = o.y[j], ojz = o.z[j];
  Relative r;
  r.ax = f.a00 * oix + f.a01 * oiy + f.a02 * oiz, r.ay = f.a10 * oix + f.a11 * oiy + f.a12 * oiz,
  r.az = f.a20 * oix + f.a21 * oiy + f.a22 * oiz;
  const double bx = f.b00 * ojx + f.b01 * ojy + f.b02 * ojz, by = f.b10 * ojx + f.b11 * ojy + f.b12 * ojz,
               bz = f.b20 * ojx + f.b21 * ojy + f.b22 * ojz;
  r.rx = f.dxx + r.ax - bx, r.ry = f.dxy + r.ay - by, r.rz = f.dxz + r.az - bz;
  return r;
}

struct Contribution {
  double fx, fy, fz, mx, my, mz, overlap, energy, damping, friction;
  std::uint32_t contact, slip;
};

// The law of contact_law.h for one candidate, updating its shear history (hx, hy, hz) in place.
inline __attribute__((always_inline)) Contribution contact(const PairKernelConstants& c, const Relative& r,
                                                           double& hx_io, double& hy_io, double& hz_io) {
  const double d = c.diameter, radius = c.radius, kn = c.kn, kt = c.kt, cn = c.cn, ct = c.ct;
  const double mu = c.friction, dt = c.dt, inv_kt = kt > 0 ? 1 / kt : 0;
  // The sliding loss is cap x slip: s (1 - s) |g|^2 / k_t with a spring; without one (k_t = 0, g = -c_t v_t) all of
  // v_t dt slips, cap |v_t| dt = s |g|^2 dt / c_t. Constants of the pair, so no branch in the loop.
  const double spring = kt > 0 ? 1.0 : 0.0, loss = kt > 0 ? inv_kt : (ct > 0 ? dt / ct : 0.0);
  const double dist2 = r.rx * r.rx + r.ry * r.ry + r.rz * r.rz;
  const bool touching = dist2 < d * d;
  const double inv = 1 / std::sqrt(dist2);
  const double delta = d - dist2 * inv;
  const double nx = r.rx * inv, ny = r.ry * inv, nz = r.rz * inv;
  // Contact point relative to x_a, and the relative velocity there.
  const double lever = radius - 0.5 * delta;
  const double px = r.ax - lever * nx, py = r.ay - lever * ny, pz = r.az - lever * nz;
  const double vx = c.v0.x() + c.dw.y() * pz - c.dw.z() * py, vy = c.v0.y() + c.dw.z() * px - c.dw.x() * pz,
               vz = c.v0.z() + c.dw.x() * py - c.dw.y() * px;
  const double vn = vx * nx + vy * ny + vz * nz;
  const double tx = vx - vn * nx, ty = vy - vn * ny, tz = vz - vn * nz;
  const double fn = kn * delta - cn * vn;

  // Shear history: into the current tangent plane, length kept, then the tangential increment.
  double hx = hx_io, hy = hy_io, hz = hz_io;
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
  hx_io = touching ? hx : 0.0, hy_io = touching ? hy : 0.0, hz_io = touching ? hz : 0.0;
  Contribution out;
  out.fx = touching ? fn * nx + gx : 0.0, out.fy = touching ? fn * ny + gy : 0.0,
  out.fz = touching ? fn * nz + gz : 0.0;
  out.mx = py * out.fz - pz * out.fy, out.my = pz * out.fx - px * out.fz, out.mz = px * out.fy - py * out.fx;
  out.contact = touching;
  out.slip = touching && slip;
  out.overlap = touching ? delta : 0.0;
  out.energy = touching ? 0.5 * kn * delta * delta + 0.5 * kt * (hx * hx + hy * hy + hz * hz) : 0.0;
  // This step's losses (contact_law.h): the dashpots' work, the tangential one only while sticking, and
  // on slip the Coulomb force times the slip, cap (1 - scale) |g| / k_t.
  out.damping = touching ? dt * (cn * vn * vn + (slip ? 0.0 : ct * (tx * tx + ty * ty + tz * tz))) : 0.0;
  out.friction = touching && slip ? scale * (1 - spring * scale) * g2 * loss : 0.0;
  return out;
}

}  // namespace

PairKernelSums pair_contacts(const PairKernelConstants& c, const OffsetArrays& offsets, const std::uint32_t* keys,
                             std::uint32_t count, double* history_x, double* history_y, double* history_z,
                             std::uint32_t* touching_scratch) {
  const Frame f(c);
  double fx = 0, fy = 0, fz = 0, mx = 0, my = 0, mz = 0, overlap = 0, energy = 0, damping = 0, friction = 0;
  std::uint32_t contacts = 0, sliding = 0;

  if (!touching_scratch) {
#pragma omp simd reduction(+ : fx, fy, fz, mx, my, mz, overlap, energy, damping, friction, contacts, sliding)
    for (std::uint32_t k = 0; k < count; ++k) {
      const Contribution q = contact(c, relative(f, offsets, keys[k]), history_x[k], history_y[k], history_z[k]);
      fx += q.fx, fy += q.fy, fz += q.fz, mx += q.mx, my += q.my, mz += q.mz;
      overlap += q.overlap, energy += q.energy, damping += q.damping, friction += q.friction;
      contacts += q.contact, sliding += q.slip;
    }
  } else {
    // Pass 1, every candidate: the distance only; separated pairs forget their history here.
    std::uint32_t* flag = touching_scratch;
#pragma omp simd
    for (std::uint32_t k = 0; k < count; ++k) {
      const Relative r = relative(f, offsets, keys[k]);
      const bool touching = r.rx * r.rx + r.ry * r.ry + r.rz * r.rz < f.d2;
      flag[k] = touching;
      if (!touching) history_x[k] = 0.0, history_y[k] = 0.0, history_z[k] = 0.0;
    }
    // Pass 2, the indices of the touching ones (in place: n <= k), then the law on them only.
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t t = flag[k];
      flag[n] = k;
      n += t;
    }
    const std::uint32_t* index = flag;
#pragma omp simd reduction(+ : fx, fy, fz, mx, my, mz, overlap, energy, damping, friction, contacts, sliding)
    for (std::uint32_t m = 0; m < n; ++m) {
      const std::uint32_t k = index[m];
      const Contribution q = contact(c, relative(f, offsets, keys[k]), history_x[k], history_y[k], history_z[k]);
      fx += q.fx, fy += q.fy, fz += q.fz, mx += q.mx, my += q.my, mz += q.mz;
      overlap += q.overlap, energy += q.energy, damping += q.damping, friction += q.friction;
      contacts += q.contact, sliding += q.slip;
    }
  }
  PairKernelSums s;
  s.force = Vec3(fx, fy, fz);
  s.moment = Vec3(mx, my, mz);
  s.contacts = contacts, s.sliding = sliding, s.overlap = overlap, s.energy = energy;
  s.damping = damping, s.friction = friction;
  return s;
}

}  // namespace granulab
