// The baseline contact kernels: the x86-64 baseline (SSE2), which every x86-64 CPU runs; engine/CMakeLists.txt compiles
// this file for it whatever the build's -march (off x86-64: the build's own flags).
// Everything the kernels' code needs is included here, before any target pragma (pair_kernel_body.h says why).
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/contact/contact_law.h"
#include "engine/contact/pair_kernel.h"
#include "engine/contact/pair_kernel_isa.h"

namespace granulab::kernel_baseline {

#include "engine/contact/pair_kernel_body.h"

PairKernel kernel(const ContactLaw& law) { return kernel_for(law); }
PairEnergyKernel energy_kernel(const ContactLaw& law) { return energy_kernel_for(law); }

}  // namespace granulab::kernel_baseline
