// The sphere-sphere contact loop of one grain pair, written for SIMD: plain arrays, no branches in
// the body (selects instead), so the compiler vectorises it across contacts (AVX2/AVX-512 with
// -march=native). It computes exactly the law of contact_law.h (tested against it), with the shear
// history rotation done by the exact rescale sqrt(|xi|^2 / |xi_proj|^2) (a vector sqrt is cheap).
#pragma once

#include <cstdint>

#include "engine/contact/contact_law.h"

namespace granulab {

struct PairKernelConstants {
  double diameter, radius;       ///< m
  double kn, kt, cn, ct;         ///< N/m and N s/m for this grain pair
  double friction, dt;
  Vec3 xa;                       ///< centre of grain a (m)
  Vec3 v0;                       ///< v_a - v_b - w_b x (x_a - x_b): relative velocity at x_a (m/s)
  Vec3 dw;                       ///< w_a - w_b (rad/s)
};

struct PairKernelSums {
  Vec3 force = Vec3::Zero();   ///< on grain a (N)
  Vec3 moment = Vec3::Zero();  ///< sum of (c - x_a) x F (N m)
  std::uint32_t contacts = 0, sliding = 0;
  double overlap = 0, energy = 0;
};

/// Contacts between spheres `sa` of grain a and `sb` of grain b (world positions) for the `count`
/// sphere-pair keys at `keys`, updating their shear histories `history`.
PairKernelSums pair_contacts(const PairKernelConstants& c, const Vec3* sa, const Vec3* sb, const std::uint32_t* keys,
                             std::uint32_t count, Vec3* history);

}  // namespace granulab
