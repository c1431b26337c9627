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
  for (std::vector<double>* v : {&ax, &ay, &az, &rx, &ry, &rz, &inv, &hx, &hy, &hz, &bond}) v->resize(n);
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

// The kernels of this build, widest first: known at compile time, so that no function of a wider set's translation
// unit is ever called on a CPU without that set (resolve_pair_kernel() checks the CPU before pair_kernel() calls one).
#if defined(__x86_64__)
constexpr const char* kKernels[] = {"avx512", "avx2", kBaselineKernel};
#else
constexpr const char* kKernels[] = {kBaselineKernel};
#endif

PairKernel kernel_named(const std::string& name, const ContactLaw& law) {
  if (name == "avx512") return kernel_avx512::kernel(law);
  if (name == "avx2") return kernel_avx2::kernel(law);
  if (name == kBaselineKernel) return kernel_baseline::kernel(law);
  return nullptr;
}

PairEnergyKernel energy_kernel_named(const std::string& name, const ContactLaw& law) {
  if (name == "avx512") return kernel_avx512::energy_kernel(law);
  if (name == "avx2") return kernel_avx2::energy_kernel(law);
  if (name == kBaselineKernel) return kernel_baseline::energy_kernel(law);
  return nullptr;
}

}  // namespace

std::vector<PairKernelInfo> pair_kernels() {
  std::vector<PairKernelInfo> out;
  for (const char* name : kKernels) out.push_back({name, cpu_runs(name)});
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
  const bool from_env = automatic && env && *env;
  const std::string requested = from_env ? env : asked;
  if (requested.empty() || requested == "auto") return best_pair_kernel();
  // Named as the user gave it: the environment, or the spec's field.
  const std::string what = from_env ? "GRANULAB_KERNEL" : "run.kernel";
  std::string names;
  for (const PairKernelInfo& k : pair_kernels()) {
    if (k.name == requested) {
      if (k.runs_here) return requested;
      throw std::invalid_argument(what + " '" + requested + "' needs instructions this CPU lacks; it runs " +
                                  best_pair_kernel() + " and below");
    }
    names += std::string(names.empty() ? "" : ", ") + k.name;
  }
  throw std::invalid_argument(what + ": unknown kernel '" + requested + "': one of auto, " + names);
}

PairKernel pair_kernel(const ContactLaw& law, const std::string& kernel) {
  return kernel_named(resolve_pair_kernel(kernel), law);
}

PairEnergyKernel pair_energy_kernel(const ContactLaw& law, const std::string& kernel) {
  return energy_kernel_named(resolve_pair_kernel(kernel), law);
}

}  // namespace granulab
