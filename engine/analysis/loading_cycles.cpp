#include "engine/analysis/loading_cycles.h"

#include <cmath>
#include <limits>

namespace granulab {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

double branch_secant(const std::vector<double>& strain, const std::vector<double>& deviator, std::size_t from,
                     std::size_t last, double change, double fraction) {
  return branch_secant_between(strain, deviator, from, last, change, 0, fraction);
}

double branch_secant_between(const std::vector<double>& strain, const std::vector<double>& deviator, std::size_t from,
                             std::size_t last, double change, double f0, double f1) {
  if (!(std::abs(change) > 0)) return kNaN;
  constexpr std::size_t kNone = std::size_t(-1);
  std::size_t k0 = f0 > 0 ? kNone : from, k1 = kNone;  // f0 = 0: the turning point itself
  for (std::size_t k = from + 1; k <= last && k < strain.size(); ++k) {
    const double f = (deviator[k] - deviator[from]) / change;
    if (k0 == kNone && f >= f0) k0 = k;
    if (f >= f1) {
      k1 = k;
      break;
    }
  }
  if (k0 == kNone || k1 == kNone || strain[k1] == strain[k0]) return kNaN;
  return (deviator[k1] - deviator[k0]) / (strain[k1] - strain[k0]);
}

std::vector<LoadingCycle> loading_cycles(const std::vector<double>& strain, const std::vector<double>& deviator,
                                         const std::vector<CurveSegment>& segments) {
  std::vector<LoadingCycle> cycles;
  // The nearest segment before (step -1) or after (+1) `i` that moves the platen; npos if none.
  const auto moving = [&](std::size_t i, int step) {
    for (std::size_t k = i + step; k < segments.size(); k += step)
      if (segments[k].direction != 0) return k;
    return std::size_t(-1);
  };
  for (std::size_t u = 0; u < segments.size(); ++u) {
    const CurveSegment& down = segments[u];
    const std::size_t l = moving(u, -1);
    if (down.direction >= 0 || l == std::size_t(-1) || segments[l].direction <= 0) continue;
    if (down.last_row >= strain.size()) continue;
    const CurveSegment& up = segments[l];
    LoadingCycle c;
    c.unloading_segment = u;
    c.first_row = down.first_row, c.last_row = down.last_row;
    c.peak_strain = strain[down.first_row], c.peak_deviator = deviator[down.first_row];
    c.residual_strain = strain[down.last_row], c.residual_deviator = deviator[down.last_row];
    c.loading_slope =
        branch_secant(strain, deviator, up.first_row, up.last_row, c.peak_deviator - deviator[up.first_row]);
    c.unloading_slope =
        branch_secant(strain, deviator, down.first_row, down.last_row, c.residual_deviator - c.peak_deviator);
    c.unloading_slope_end = branch_secant_between(strain, deviator, down.first_row, down.last_row,
                                                  c.residual_deviator - c.peak_deviator, 0.8, 1.0);
    c.reloading_slope = c.reloading_slope_end = c.dissipated_energy = kNaN;
    const std::size_t r = moving(u, +1);
    if (r != std::size_t(-1) && segments[r].direction > 0 && segments[r].last_row < strain.size()) {
      const CurveSegment& again = segments[r];
      c.reloading_slope =
          branch_secant(strain, deviator, again.first_row, again.last_row, c.peak_deviator - deviator[again.first_row]);
      c.reloading_slope_end = branch_secant_between(strain, deviator, again.first_row, again.last_row,
                                                    c.peak_deviator - deviator[again.first_row], 0.8, 1.0);
      // Trapezoids down the unloading (rows between it and the reloading hold the strain: they add
      // nothing), then up the reloading until it passes the peak strain, the last one cut there.
      double area = 0;
      for (std::size_t k = down.first_row + 1; k <= down.last_row; ++k)
        area += 0.5 * (deviator[k] + deviator[k - 1]) * (strain[k] - strain[k - 1]);
      for (std::size_t k = again.first_row + 1; k <= again.last_row; ++k) {
        const double e0 = strain[k - 1], e1 = strain[k], s0 = deviator[k - 1], s1 = deviator[k];
        if (e1 < c.peak_strain) {
          area += 0.5 * (s0 + s1) * (e1 - e0);
          continue;
        }
        const double s = e1 > e0 ? s0 + (s1 - s0) * (c.peak_strain - e0) / (e1 - e0) : s1;
        area += 0.5 * (s0 + s) * (c.peak_strain - e0);
        c.dissipated_energy = area;
        c.last_row = k;
        break;
      }
    }
    cycles.push_back(c);
  }
  return cycles;
}

}  // namespace granulab
