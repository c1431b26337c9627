// The AVX-512 contact kernels (Intel Skylake-SP and later, AMD Zen 4 and later) in 512-bit vectors, for the dispatcher
// to choose where the CPU has AVX-512 F, CD, DQ, BW and VL. Compiled from the x86-64 baseline (engine/CMakeLists.txt)
// with the sets added by the pragma below, after every include (pair_kernel_body.h says why).
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/contact/contact_law.h"
#include "engine/contact/pair_kernel.h"
#include "engine/contact/pair_kernel_isa.h"

#if defined(__x86_64__)
#pragma GCC target("avx512f,avx512cd,avx512dq,avx512bw,avx512vl,avx2,fma,prefer-vector-width=512")

namespace granulab::kernel_avx512 {

#include "engine/contact/pair_kernel_body.h"

PairKernel kernel(const ContactLaw& law) { return kernel_for(law); }
PairEnergyKernel energy_kernel(const ContactLaw& law) { return energy_kernel_for(law); }

}  // namespace granulab::kernel_avx512

#else
namespace granulab::kernel_avx512 {
PairKernel kernel(const ContactLaw&) { return nullptr; }
PairEnergyKernel energy_kernel(const ContactLaw&) { return nullptr; }
}  // namespace granulab::kernel_avx512
#endif
