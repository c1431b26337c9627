// The sphere-sphere contact loop of one grain pair, written for SIMD: plain arrays, no branches in
// the body (selects instead), so the compiler vectorises it across contacts. Per candidate it measures the geometry
// and calls contact_law.h's contact_terms, the one evaluator of the law, compiled once per pair of normal and
// tangential models and once per instruction set (baseline, AVX2, AVX-512; pair_kernel_body.h): one binary runs the
// widest its CPU has, chosen at start (pair_kernel()).
// Sphere positions are computed from the two grains' poses and the shared template offsets, which
// stay in cache, rather than loaded from a per-sphere array that does not (at 841,536 spheres the
// loads missed the cache and cost 4x the arithmetic).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/contact/contact_law.h"

namespace granulab {

struct PairKernelConstants {
  double diameter, radius;  ///< contact distance and sphere a's radius (m)
  PairLaw law;              ///< the law's constants for this grain pair (pair_law())
  Vec3 xa, xb;              ///< centres of grains a and b (m)
  Mat3 ra, rb;              ///< their orientations (body -> world)
  Vec3 v0;                  ///< v_a - v_b - w_b x (x_a - x_b): relative velocity at x_a (m/s)
  Vec3 dw;                  ///< w_a - w_b (rad/s)
  Vec3 v0_damping, dw_damping;  ///< v0 and dw of the velocities the dashpots see (World::damping_velocity) (m/s, rad/s)
};

struct PairKernelSums {
  Vec3 force = Vec3::Zero();   ///< on grain a (N)
  Vec3 moment = Vec3::Zero();  ///< sum of (c - x_a) x F (N m)
  std::uint32_t contacts = 0, sliding = 0;
  double overlap = 0;   ///< sum of the overlaps (m)
  double damping = 0;   ///< energy the dashpots took in this step (J)
  double friction = 0;  ///< energy lost to sliding in this step (J)
  double nearest2 = 0;  ///< the two-pass path: the smallest squared distance of two candidates' centres (m^2); else 0
};

/// The template's body-frame sphere offsets (m), one array per component, indexed by local sphere id:
/// the contact loop gathers them per sphere pair, which vectorises on the component arrays (an array of
/// Vec3 was read with scalar loads).
struct OffsetArrays {
  std::vector<double> x, y, z;
  explicit OffsetArrays(const std::vector<Vec3>& offsets);
};

/// Room for the two-pass path (PairKernel), per thread: the touching candidates' indices, and their geometry (sphere i
/// relative to x_a, a, and the centre-to-centre vector r, m; 1 / |r|, 1/m), histories (m) and bond flags packed
/// together, so the law's loop reads and writes consecutive elements.
struct KernelScratch {
  std::vector<std::uint32_t> index;
  std::vector<double> ax, ay, az, rx, ry, rz, inv, hx, hy, hz, bond;

  /// Room for n candidates (grows only).
  void reserve(std::size_t n);
};

/// Contacts between the spheres of grains a and b (template body-frame `offsets`) for the `count`
/// sphere-pair keys at `keys`, updating their shear histories (components at hx, hy, hz) and, for a law that keeps
/// bonds (jkr), their bond flags at `bond` (nullptr otherwise).
/// With `scratch` (room for `count` candidates), the distances are computed first and the law only
/// for the touching pairs: cheaper when most candidates do not touch (sliding faces, loose packings),
/// dearer when nearly all do. The physics is the same; the sums' rounding differs.
using PairKernel = PairKernelSums (*)(const PairKernelConstants& c, const OffsetArrays& offsets,
                                      const std::uint32_t* keys, std::uint32_t count, double* hx, double* hy,
                                      double* hz, double* bond, KernelScratch* scratch);

/// The elastic energy stored in a grain pair's candidates as its last PairKernel call left them (J): the normal law's
/// potential and the spring's of those in contact. Kept out of PairKernel, which runs every step, as it is read
/// rarely (a curve row, an equilibrium check).
using PairEnergyKernel = double (*)(const PairKernelConstants& c, const OffsetArrays& offsets,
                                    const std::uint32_t* keys, std::uint32_t count, const double* hx,
                                    const double* hy, const double* hz, const double* bond);

/// The baseline kernel's name: the x86-64 baseline (SSE2) on x86-64; "generic" elsewhere.
#if defined(__x86_64__)
inline constexpr const char* kBaselineKernel = "sse2";
#else
inline constexpr const char* kBaselineKernel = "generic";
#endif

/// A contact kernel of this binary: "avx512" (AVX-512 F/CD/DQ/BW/VL, 512-bit vectors), "avx2" (AVX2 + FMA) or the
/// baseline, each compiled from the same source (pair_kernel_body.h) whatever the build's -march.
struct PairKernelInfo {
  const char* name;
  bool runs_here;  ///< whether this CPU has its instructions
};
/// Every kernel of this binary, widest first.
std::vector<PairKernelInfo> pair_kernels();
/// The widest kernel this CPU runs: what `auto` chooses.
const char* best_pair_kernel();
/// The kernel a run asks for by name: "auto" (or "") gives best_pair_kernel(), unless the environment's
/// GRANULAB_KERNEL names one (for benchmarks and tests); an unknown name, or one the CPU cannot run, throws
/// std::invalid_argument saying which kernels there are.
std::string resolve_pair_kernel(const std::string& requested);

/// The kernel of `law`'s normal and tangential models in the instruction set `kernel` names (resolve_pair_kernel()):
/// chosen once per run, each compiled for its law. Kernels may differ in their results' last bits (the sums reduce in
/// as many lanes as the vectors have; docs/model.md).
PairKernel pair_kernel(const ContactLaw& law, const std::string& kernel = "");
/// The stored-energy kernel of the same law and instruction set.
PairEnergyKernel pair_energy_kernel(const ContactLaw& law, const std::string& kernel = "");

}  // namespace granulab
