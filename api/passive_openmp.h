// OpenMP threads that spin while waiting turn a shared core into a 6x slowdown (measured: a small
// crystal took 14 s instead of 2.2 s next to another job). libgomp reads the wait policy once, when it
// loads, so a program that wants passive waiting must have it in its environment from the start:
// unless the user chose a policy, set it and re-execute this program. Call first thing in main().
#pragma once

#include <cstdlib>
#include <unistd.h>

namespace granulab::api {

inline void reexec_with_passive_openmp(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY")) return;
  setenv("OMP_WAIT_POLICY", "passive", 1);
  // The binary's own path, not /proc/self/exe: the process is named after the file executed, and
  // "exe" in top and pgrep named nothing.
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return;
  path[n] = '\0';
  execv(path, argv);  // returns only on failure: then carry on with the default policy
}

}  // namespace granulab::api
