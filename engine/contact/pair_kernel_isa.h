// Internal to the contact kernels: what each instruction set's translation unit (pair_kernel_<isa>.cpp) provides to
// the dispatcher (pair_kernel.cpp). Each compiles pair_kernel_body.h for its set; a set the compiler cannot target
// (off x86-64) gives nullptr.
#pragma once

#include "engine/contact/pair_kernel.h"

namespace granulab {

namespace kernel_baseline {
PairKernel kernel(const ContactLaw& law);
PairEnergyKernel energy_kernel(const ContactLaw& law);
}
namespace kernel_avx2 {
PairKernel kernel(const ContactLaw& law);
PairEnergyKernel energy_kernel(const ContactLaw& law);
}
namespace kernel_avx512 {
PairKernel kernel(const ContactLaw& law);
PairEnergyKernel energy_kernel(const ContactLaw& law);
}

}  // namespace granulab
