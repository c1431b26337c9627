// What the rigid-grain yield estimate costs (engine/analysis/yield_estimate.h): the compression estimate of every
// lattice and axis of docs/results.md ("Lattices and loading axes") and the shear estimates of the main slip
// systems, each timed as the best of `repeats` calls. Dry runs and `granulab estimate` compute one per spec.
//
//   build/bench/bench_yield_estimate [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "bench/machine.h"
#include "engine/analysis/yield_estimate.h"

using namespace granulab;

template <class F>
double best_ms(int repeats, F f) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

int main(int argc, char** argv) {
  granulab::print_machine();
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  struct Axis {
    const char* name;
    LatticeType lattice;
    Indices axis;
  } axes[] = {{"fcc [0 0 1]", LatticeType::fcc, {0, 0, 1}},   {"fcc [1 1 0]", LatticeType::fcc, {1, 1, 0}},
              {"fcc [1 1 1]", LatticeType::fcc, {1, 1, 1}},   {"fcc [-1 -1 2]", LatticeType::fcc, {-1, -1, 2}},
              {"fcc [1 2 3]", LatticeType::fcc, {1, 2, 3}},   {"sc [0 0 1]", LatticeType::sc, {0, 0, 1}},
              {"sc [1 1 0]", LatticeType::sc, {1, 1, 0}},     {"sc [1 1 1]", LatticeType::sc, {1, 1, 1}},
              {"bcc [0 0 1]", LatticeType::bcc, {0, 0, 1}},   {"bcc [1 1 0]", LatticeType::bcc, {1, 1, 0}},
              {"bcc [1 1 1]", LatticeType::bcc, {1, 1, 1}},   {"hcp c", LatticeType::hcp, {0, 0, 1}},
              {"hcp a1", LatticeType::hcp, {1, 0, 0}},        {"hcp [0 1 -1 0]", LatticeType::hcp, {1, 2, 0}}};
  std::printf("%-16s %10s  %s\n", "compression", "ms", "estimate (f = 0.35)");
  for (const Axis& a : axes) {
    YieldEstimate e;
    const double ms = best_ms(repeats, [&] {
      e = compression_yield_estimate(a.lattice, direction_vector(a.lattice, a.axis, 1), 0.35);
    });
    std::printf("%-16s %10.3f  %s\n", a.name, ms, yield_estimate_text(e).c_str());
  }
  struct System {
    const char* name;
    LatticeType lattice;
    Indices plane;
    Vec3 direction;
  } systems[] = {{"fcc (111) [-211]", LatticeType::fcc, {1, 1, 1}, Vec3(-2, 1, 1)},
                 {"bcc (110) [1-11]", LatticeType::bcc, {1, 1, 0}, Vec3(1, -1, 1)},
                 {"hcp (0001) a1", LatticeType::hcp, {0, 0, 1}, Vec3(1, 0, 0)},
                 {"sc (100) [010]", LatticeType::sc, {1, 0, 0}, Vec3(0, 1, 0)}};
  std::printf("%-16s %10s  %s\n", "shear", "ms", "estimate (f = 0.35)");
  for (const System& s : systems) {
    YieldEstimate e;
    const double ms = best_ms(repeats, [&] { e = shear_yield_estimate(s.lattice, s.plane, s.direction, 0.35); });
    std::printf("%-16s %10.3f  %s\n", s.name, ms, yield_estimate_text(e).c_str());
  }
  return 0;
}
