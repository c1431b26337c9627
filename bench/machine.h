// What a benchmark ran on: the CPU's model and vector instruction sets (as /proc/cpuinfo reports them, what
// `lscpu` shows) and the contact kernel the program runs (GRANULAB_KERNEL chooses another). Every speed figure in
// bench/README.md names its machine; the programs print this line first so a pasted result carries it.
#pragma once

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "engine/contact/pair_kernel.h"

namespace granulab {

/// To `out`: stdout for the tables people read, stderr for a program whose stdout is data (bench_interface_laws).
inline void print_machine(std::FILE* out = stdout) {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU", family, number, flags;
  while (std::getline(in, line)) {
    if (line.find(':') == std::string::npos) continue;
    const std::string value = line.find(": ") != std::string::npos ? line.substr(line.find(": ") + 2) : "";
    if (model == "unknown CPU" && line.rfind("model name", 0) == 0) model = value;
    // A VM may name the CPU "AMD EPYC" alone: family and model tell its generation (25, 1: Zen 3).
    if (family.empty() && line.rfind("cpu family", 0) == 0) family = value;
    if (number.empty() && line.rfind("model\t", 0) == 0) number = value;
    if (flags.empty() && line.rfind("flags", 0) == 0) flags = " " + value + " ";
  }
  if (!family.empty()) model += " (family " + family + ", model " + number + ")";
  std::string sets;
  for (const char* f : {"sse2", "avx", "avx2", "fma", "avx512f", "avx512vl"})
    if (flags.find(std::string(" ") + f + " ") != std::string::npos) sets += std::string(sets.empty() ? "" : " ") + f;
  std::string kernels;
  for (const PairKernelInfo& k : pair_kernels())
    kernels += std::string(kernels.empty() ? "" : ", ") + k.name + (k.runs_here ? "" : " (not on this CPU)");
  std::string kernel;
  try {
    kernel = resolve_pair_kernel("");
  } catch (const std::invalid_argument& e) {  // a GRANULAB_KERNEL this CPU lacks: the run will say so too
    kernel = e.what();
  }
  std::fprintf(out, "machine: %s; vector sets: %s; contact kernel %s (this binary has %s)\n", model.c_str(),
               sets.empty() ? "none reported" : sets.c_str(), kernel.c_str(), kernels.c_str());
}

}  // namespace granulab
