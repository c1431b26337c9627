// The contact kernels' code, compiled once per instruction set: pair_kernel_<isa>.cpp each include it inside a
// namespace of their own after `#pragma GCC target`, so that the same source gives the baseline, AVX2 and AVX-512
// kernels of one binary (pair_kernel.cpp chooses among them at run time). No include guard, on purpose; every header
// it needs is included by the including file before its pragma, so that inline functions shared with the rest of the
// program are compiled for the baseline and never for a wider set (a copy the linker kept could then run, and trap, on
// a CPU without it).
//
// Written for the compiler's vectoriser: plain arrays, no branches in the loops' bodies (selects instead), and nothing
// AVX2 cannot do in a vector: no scatter (the touching candidates are packed first), no conversion of a comparison's
// result to a number, no masked store (see the comments at each).

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

// The offsets' arrays as raw pointers, read before the loops: GCC did not hoist the vectors' data pointers out of a
// loop that stores, and a load of a pointer in the loop body stopped it from vectorising.
struct Offsets {
  const double *x, *y, *z;
  explicit Offsets(const OffsetArrays& o) : x(o.x.data()), y(o.y.data()), z(o.z.data()) {}
};

inline __attribute__((always_inline)) Relative relative(const Frame& f, double oix, double oiy, double oiz, double ojx,
                                                       double ojy, double ojz) {
  Relative r;
  r.ax = f.a00 * oix + f.a01 * oiy + f.a02 * oiz, r.ay = f.a10 * oix + f.a11 * oiy + f.a12 * oiz,
  r.az = f.a20 * oix + f.a21 * oiy + f.a22 * oiz;
  const double bx = f.b00 * ojx + f.b01 * ojy + f.b02 * ojz, by = f.b10 * ojx + f.b11 * ojy + f.b12 * ojz,
               bz = f.b20 * ojx + f.b21 * ojy + f.b22 * ojz;
  r.rx = f.dxx + r.ax - bx, r.ry = f.dxy + r.ay - by, r.rz = f.dxz + r.az - bz;
  return r;
}

inline __attribute__((always_inline)) Relative relative(const Frame& f, const Offsets& o, std::uint32_t key) {
  const std::uint32_t i = key >> 16, j = key & 0xffff;
  return relative(f, o.x[i], o.y[i], o.z[i], o.x[j], o.y[j], o.z[j]);
}

// The counts are doubles, set by selects: a conversion of a comparison's result to a number has no AVX2 form (AVX-512
// has mask registers), and kept GCC 12 from vectorising the loop there; so did integer counts summed beside doubles.
struct Contribution {
  double fx, fy, fz, mx, my, mz, overlap, damping, friction, contact, slip;
};

// One candidate: its geometry, then the law (contact_terms), then the moment about x_a. `Touching`: the caller
// knows the centres are within reach (the packed candidates of the two-pass path), which spares the law's selects.
// `inv_r`: 1 / |r| when the caller computed it (Packed), else computed here.
template <NormalModel N, TangentialModel T, bool Touching = false, bool Packed = false>
inline __attribute__((always_inline)) Contribution contact(const PairKernelConstants& c, const Relative& r,
                                                           double& hx_io, double& hy_io, double& hz_io,
                                                           double& bond_io, double inv_r = 0) {
  const double d = c.diameter, radius = c.radius;
  const double dist2 = r.rx * r.rx + r.ry * r.ry + r.rz * r.rz;
  const bool touching = Touching || dist2 < d * d;
  const double inv = Packed ? inv_r : 1 / std::sqrt(dist2);
  const double delta = d - dist2 * inv;
  const double nx = r.rx * inv, ny = r.ry * inv, nz = r.rz * inv;
  // Contact point relative to x_a, and the relative velocity there.
  const double lever = radius - 0.5 * delta;
  const double px = r.ax - lever * nx, py = r.ay - lever * ny, pz = r.az - lever * nz;
  const double vx = c.v0.x() + c.dw.y() * pz - c.dw.z() * py, vy = c.v0.y() + c.dw.z() * px - c.dw.x() * pz,
               vz = c.v0.z() + c.dw.x() * py - c.dw.y() * px;
  const Vec3 &u0 = c.v0_damping, &du = c.dw_damping;
  const double wx = u0.x() + du.y() * pz - du.z() * py, wy = u0.y() + du.z() * px - du.x() * pz,
               wz = u0.z() + du.x() * py - du.y() * px;
  const ContactTerms t =
      contact_terms<N, T, false>(c.law, delta, touching, nx, ny, nz, vx, vy, vz, wx, wy, wz, hx_io, hy_io, hz_io, bond_io);
  Contribution out;
  out.fx = t.fx, out.fy = t.fy, out.fz = t.fz;
  out.mx = py * out.fz - pz * out.fy, out.my = pz * out.fx - px * out.fz, out.mz = px * out.fy - py * out.fx;
  out.contact = t.contact ? 1.0 : 0.0;
  out.slip = t.slip ? 1.0 : 0.0;
  out.overlap = t.overlap, out.damping = t.damping, out.friction = t.friction;
  return out;
}

template <NormalModel N, TangentialModel T>
PairKernelSums pair_contacts(const PairKernelConstants& c, const OffsetArrays& offset_arrays, const std::uint32_t* keys,
                             std::uint32_t count, double* history_x, double* history_y, double* history_z,
                             double* bond_flags, KernelScratch* scratch) {
  constexpr bool bonds = N == NormalModel::jkr;
  const Frame f(c);
  const Offsets offsets(offset_arrays);
  double fx = 0, fy = 0, fz = 0, mx = 0, my = 0, mz = 0, overlap = 0, damping = 0, friction = 0;
  double contacts = 0, sliding = 0, nearest = 0;
  // A law without bonds gets a scratch flag per candidate that it never reads.
  double unused = 0;

  if (!scratch) {
#pragma omp simd reduction(+ : fx, fy, fz, mx, my, mz, overlap, damping, friction, contacts, sliding)
    for (std::uint32_t k = 0; k < count; ++k) {
      double& bond = bonds ? bond_flags[k] : unused;
      const Contribution q =
          contact<N, T>(c, relative(f, offsets, keys[k]), history_x[k], history_y[k], history_z[k], bond);
      fx += q.fx, fy += q.fy, fz += q.fz, mx += q.mx, my += q.my, mz += q.mz;
      overlap += q.overlap, damping += q.damping, friction += q.friction;
      contacts += q.contact, sliding += q.slip;
    }
  } else {
    // Pass 1, every candidate: its geometry (kept for pass 4) and whether it touches; pairs out of reach forget their
    // history (and bond) here. A bonded jkr pair reaches to d + delta_c; one that broke beyond it leaves its stored
    // energy at break_energy with the losses, as contact_terms counts a bond broken within reach.
    std::uint32_t* flag = scratch->index.data();
    double *rax = scratch->ax.data(), *ray = scratch->ay.data(), *raz = scratch->az.data();
    double *rrx = scratch->rx.data(), *rry = scratch->ry.data(), *rrz = scratch->rz.data();
    const double d2 = f.d2, bonded_reach = c.diameter + c.law.break_depth, bonded_d2 = bonded_reach * bonded_reach;
    // The nearest centres, so that a pair found apart can be skipped while it stays so (engine/world/open_pairs.h).
    double nearest2 = std::numeric_limits<double>::infinity();
#pragma omp simd reduction(+ : damping) reduction(min : nearest2)
    for (std::uint32_t k = 0; k < count; ++k) {
      const Relative r = relative(f, offsets, keys[k]);
      rax[k] = r.ax, ray[k] = r.ay, raz[k] = r.az, rrx[k] = r.rx, rry[k] = r.ry, rrz[k] = r.rz;
      const double reach2 = bonds && bond_flags[k] > 0 ? bonded_d2 : d2;
      const double dist2 = r.rx * r.rx + r.ry * r.ry + r.rz * r.rz;
      nearest2 = dist2 < nearest2 ? dist2 : nearest2;
      const bool touching = dist2 < reach2;
      flag[k] = touching;
      if (bonds) damping += (bond_flags[k] > 0) & !touching ? c.law.break_energy : 0.0;
      // Stored on every lane by arithmetic (x 1 or 0, + 0 turning -0 into 0): written as a condition, GCC makes it a
      // masked store, microcoded on AMD's Zen 2 and 3, where it made this loop 1.5x dearer.
      const double keep = touching ? 1.0 : 0.0;
      history_x[k] = keep * history_x[k] + 0.0, history_y[k] = keep * history_y[k] + 0.0;
      history_z[k] = keep * history_z[k] + 0.0;
      if (bonds) bond_flags[k] = keep * bond_flags[k];
    }
    // Pass 2, the indices of the touching ones (in place: n <= k).
    std::uint32_t* index = flag;
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t t = flag[k];
      index[n] = k;
      n += t;
    }
    // Pass 3, the touching ones' geometry and histories packed together (in place for the geometry: index[m] >= m):
    // the law's loop then reads and writes consecutive elements only. Read through the indices, GCC 12 kept that loop
    // scalar on AVX2 (it has no scatter for the histories, and gave up on the offsets' gathers), 3x slower than
    // vectorised; packing the geometry rather than the template's offsets saves the law's loop recomputing it (6-7 %).
    KernelScratch& p = *scratch;
    for (std::uint32_t m = 0; m < n; ++m) {
      const std::uint32_t k = index[m];
      rax[m] = rax[k], ray[m] = ray[k], raz[m] = raz[k], rrx[m] = rrx[k], rry[m] = rry[k], rrz[m] = rrz[k];
      p.hx[m] = history_x[k], p.hy[m] = history_y[k], p.hz[m] = history_z[k];
      if (bonds) p.bond[m] = bond_flags[k];
    }
    // Pass 4, the law on the packed candidates. They all touch, but a jkr bond's reach differs from d: jkr
    // measures again.
    constexpr bool touching = !bonds;
    if (touching) contacts = n;
    {
      double *hx = p.hx.data(), *hy = p.hy.data(), *hz = p.hz.data(), *bond = p.bond.data(), *rinv = p.inv.data();
      // 1 / |r| in a loop of its own: the law's loop is one long chain of dependent operations per candidate, too
      // long for the CPU to overlap two candidates' (AMD's Zen 3 ran it at 2 instructions a cycle); the first square
      // root and division taken out of it made the two-pass path 8 % faster there (kernel microbench, 600
      // candidates, half touching: 14.6 -> 13.4 ns per candidate). The same operations: no result changes.
#pragma omp simd
      for (std::uint32_t m = 0; m < n; ++m) rinv[m] = 1 / std::sqrt(rrx[m] * rrx[m] + rry[m] * rry[m] + rrz[m] * rrz[m]);
#pragma omp simd reduction(+ : fx, fy, fz, mx, my, mz, overlap, damping, friction, contacts, sliding)
      for (std::uint32_t m = 0; m < n; ++m) {
        double& b = bonds ? bond[m] : unused;
        Relative r;
        r.ax = rax[m], r.ay = ray[m], r.az = raz[m], r.rx = rrx[m], r.ry = rry[m], r.rz = rrz[m];
        const Contribution q = contact<N, T, touching, true>(c, r, hx[m], hy[m], hz[m], b, rinv[m]);
        fx += q.fx, fy += q.fy, fz += q.fz, mx += q.mx, my += q.my, mz += q.mz;
        overlap += q.overlap, damping += q.damping, friction += q.friction;
        if (!touching) contacts += q.contact;
        sliding += q.slip;
      }
    }
    // Pass 5, the histories back to their candidates.
    for (std::uint32_t m = 0; m < n; ++m) {
      const std::uint32_t k = index[m];
      history_x[k] = p.hx[m], history_y[k] = p.hy[m], history_z[k] = p.hz[m];
      if (bonds) bond_flags[k] = p.bond[m];
    }
    nearest = nearest2;
  }
  PairKernelSums s;
  s.nearest2 = nearest;
  s.force = Vec3(fx, fy, fz);
  s.moment = Vec3(mx, my, mz);
  s.contacts = std::uint32_t(contacts), s.sliding = std::uint32_t(sliding), s.overlap = overlap;
  s.damping = damping, s.friction = friction;
  return s;
}

// The energy stored in a pair's contacts after its last evaluation: every candidate's geometry again (the poses have
// not moved since), and for those in contact the normal law's potential and the spring's k_t |xi|^2 / 2 of the
// updated history. The contact kernels leave it out (6 % of the one-pass loop, measured on the Zen 3 VM): it is
// read at a curve row or an equilibrium check, not at every step.
template <NormalModel N, TangentialModel T>
double pair_stored_energy(const PairKernelConstants& c, const OffsetArrays& offset_arrays, const std::uint32_t* keys,
                          std::uint32_t count, const double* history_x, const double* history_y,
                          const double* history_z, const double* bond_flags) {
  const Frame f(c);
  const Offsets offsets(offset_arrays);
  double energy = 0;
#pragma omp simd reduction(+ : energy)
  for (std::uint32_t k = 0; k < count; ++k) {
    const Relative r = relative(f, offsets, keys[k]);
    const double dist2 = r.rx * r.rx + r.ry * r.ry + r.rz * r.rz;
    // In contact as the evaluation left it: within reach, or for jkr bonded (the flag it set).
    const bool contact = N == NormalModel::jkr ? bond_flags[k] > 0 : dist2 < f.d2;
    const double delta = c.diameter - dist2 * (1 / std::sqrt(dist2));
    double a = 0, x = 0;
    contact_radius<N, T>(c.law, delta, a, x);
    const double kt = T == TangentialModel::mindlin ? c.law.kt * a : c.law.kt;
    const double hx = history_x[k], hy = history_y[k], hz = history_z[k];
    const double stored = normal_potential<N>(c.law, delta, a, x) + 0.5 * kt * (hx * hx + hy * hy + hz * hz);
    energy += contact ? stored : 0.0;
  }
  return energy;
}

// The instantiation of a kernel template for `law`'s normal and tangential models, both kernels' one dispatch:
// Kernel<N, T>::get is the function for models N, T.
template <template <NormalModel, TangentialModel> class Kernel, NormalModel N>
auto of_tangential(TangentialModel t) {
  return t == TangentialModel::mindlin ? Kernel<N, TangentialModel::mindlin>::get
                                       : Kernel<N, TangentialModel::linear_history>::get;
}

template <template <NormalModel, TangentialModel> class Kernel>
auto of_law(const ContactLaw& law) -> decltype(of_tangential<Kernel, NormalModel::hooke>(law.tangential)) {
  switch (law.normal) {
    case NormalModel::hooke: return of_tangential<Kernel, NormalModel::hooke>(law.tangential);
    case NormalModel::hertz: return of_tangential<Kernel, NormalModel::hertz>(law.tangential);
    case NormalModel::hertz_material: return of_tangential<Kernel, NormalModel::hertz_material>(law.tangential);
    case NormalModel::dmt: return of_tangential<Kernel, NormalModel::dmt>(law.tangential);
    case NormalModel::jkr: return of_tangential<Kernel, NormalModel::jkr>(law.tangential);
  }
  return nullptr;
}

template <NormalModel N, TangentialModel T>
struct ForcesOf {
  static constexpr PairKernel get = &pair_contacts<N, T>;
};
template <NormalModel N, TangentialModel T>
struct StoredEnergyOf {
  static constexpr PairEnergyKernel get = &pair_stored_energy<N, T>;
};

/// This instruction set's kernel of `law`'s normal and tangential models.
inline PairKernel kernel_for(const ContactLaw& law) { return of_law<ForcesOf>(law); }
/// This instruction set's stored-energy kernel of `law`'s models.
inline PairEnergyKernel energy_kernel_for(const ContactLaw& law) { return of_law<StoredEnergyOf>(law); }
