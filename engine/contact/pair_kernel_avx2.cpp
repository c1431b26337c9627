// The AVX2 + FMA contact kernels (Intel Haswell and later, AMD Zen and later), for the dispatcher to choose where the
// CPU has both. Compiled from the x86-64 baseline (engine/CMakeLists.txt) with the sets added by the pragma below,
// after every include (pair_kernel_body.h says why). No FMA contraction: -ffp-contract=off holds here as everywhere.
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/contact/contact_law.h"
#include "engine/contact/pair_kernel.h"
#include "engine/contact/pair_kernel_isa.h"

#if defined(__x86_64__)
#pragma GCC target("avx2,fma")

namespace granulab::kernel_avx2 {

#include "engine/contact/pair_kernel_body.h"

PairKernel kernel(const ContactLaw& law) { return kernel_for(law); }
PairEnergyKernel energy_kernel(const ContactLaw& law) { return energy_kernel_for(law); }

}  // namespace granulab::kernel_avx2

#else
namespace granulab::kernel_avx2 {
PairKernel kernel(const ContactLaw&) { return nullptr; }
PairEnergyKernel energy_kernel(const ContactLaw&) { return nullptr; }
}  // namespace granulab::kernel_avx2
#endif
