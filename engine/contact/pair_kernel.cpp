#include "engine/contact/pair_kernel.h"

#include <cstdlib>
#include <stdexcept>

#include "engine/contact/pair_kernel_isa.h"

namespace granulab {

OffsetArrays::OffsetArrays(const std::vector<Vec3>& offsets) {
  for (const Vec3& o : offsets) x.push_back(o.x()), y.push_back(o.y()), z.push_back(o.z());
}

void KernelScratch::reserve(std::size_t n) {
  if (index.size() >= n) return;
  for (std::vector<double>* v : {&ax, &ay, &az, &rx, &ry, &rz, &hx, &hy, &hz, &bond}) v->resize(n);
  index.resize(n);
}

namespace {

// Whether this CPU runs a kernel: what it reports (cpuid, through GCC's builtins), read once.
bool cpu_runs(const std::string& name) {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();  // the tests ask before main(), from static initialisers
  if (name == "avx512")
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (name == "avx2") return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
  return name == kBaselineKernel;
}

PairKernel kernel_named(const std::string& name, const ContactLaw& law) {
  if (name == "avx512") return kernel_avx512::kernel(law);
  if (name == "avx2") return kernel_avx2::kernel(law);
  if (name == kBaselineKernel) return kernel_baseline::kernel(law);
  return nullptr;
}

}  // namespace

std::vector<PairKernelInfo> pair_kernels() {
  std::vector<PairKernelInfo> out;
  for (const char* name : {"avx512", "avx2", kBaselineKernel}) {
    if (!kernel_named(name, ContactLaw{})) continue;  // not in this build (off x86-64)
    out.push_back({name, cpu_runs(name)});
  }
  return out;
}

const char* best_pair_kernel() {
  static const char* best = [] {
    for (const PairKernelInfo& k : pair_kernels())
      if (k.runs_here) return k.name;
    return kBaselineKernel;
  }();
  return best;
}

std::string resolve_pair_kernel(const std::string& asked) {
  // The environment's choice stands in for the automatic one (benchmarks, tests).
  const char* env = std::getenv("GRANULAB_KERNEL");
  const bool automatic = asked.empty() || asked == "auto";
  const std::string requested = automatic && env && *env ? env : asked;
  if (requested.empty() || requested == "auto") return best_pair_kernel();
  std::string names;
  for (const PairKernelInfo& k : pair_kernels()) {
    if (k.name == requested) {
      if (k.runs_here) return requested;
      throw std::invalid_argument("kernel '" + requested + "' needs instructions this CPU lacks; it runs " +
                                  best_pair_kernel() + " and below");
    }
    names += std::string(names.empty() ? "" : ", ") + k.name;
  }
  throw std::invalid_argument("unknown kernel '" + requested + "': one of auto, " + names);
}

PairKernel pair_kernel(const ContactLaw& law, const std::string& kernel) {
  return kernel_named(resolve_pair_kernel(kernel), law);
}

}  // namespace granulab
