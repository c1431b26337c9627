// Load-unload cycles of a curve (a loading program's, Fig. 1c of the paper): for each unloading that
// follows a loading, where it turned and where it ended, the slopes of the branches around it and the
// energy the loop dissipates. From curve rows alone (strain, deviator), so that any code's curve with
// the same segments can be compared.
#pragma once

#include <cstddef>
#include <vector>

namespace granulab {

/// A segment of a curve: rows first_row..last_row (first_row: the row it started from, the previous
/// segment's last), and whether the strain rose (+1), fell (-1) or stayed (0).
struct CurveSegment {
  int direction = 0;
  std::size_t first_row = 0, last_row = 0;
};

struct LoadingCycle {
  std::size_t unloading_segment = 0;  ///< index of the unloading segment (-)
  /// The cycle's rows: from the peak (the unloading's first row) to the reloading's first row at or past
  /// the peak strain; without one, to the unloading's last row.
  std::size_t first_row = 0, last_row = 0;
  double peak_strain = 0;             ///< where the unloading began (-)
  double peak_deviator = 0;           ///< (Pa)
  double residual_strain = 0;         ///< where it ended (-)
  double residual_deviator = 0;       ///< (Pa)
  /// Secants (Pa), each over the first 20 % of a branch's deviator change from its turning point:
  double loading_slope = 0;    ///< the loading before the peak, over 20 % of its rise to the peak
  double unloading_slope = 0;  ///< the unloading, over 20 % of its drop
  double reloading_slope = 0;  ///< the next loading, over 20 % of its rise back to the peak deviator; NaN without one
  /// ... and over the last 20 % (from 80 % to all of the change; NaN if the branch does not get there):
  double unloading_slope_end = 0;  ///< the unloading's tail, where it reaches its residual deviator
  double reloading_slope_end = 0;  ///< the reloading where it comes back to the peak deviator
  /// The loop's area, the integral of deviator d(strain) down the unloading and back up the reloading
  /// to the peak strain (J/m^3): the work per unit volume the crystal dissipated over the cycle. NaN
  /// when no reloading reaches the peak strain.
  double dissipated_energy = 0;
};

/// The secant slope (Pa) from row `from` to the first row up to `last` whose deviator has changed by
/// `fraction` of `change` (signed: the way the branch goes); NaN if no row gets there with a strain change.
double branch_secant(const std::vector<double>& strain, const std::vector<double>& deviator, std::size_t from,
                     std::size_t last, double change, double fraction = 0.2);

/// The secant (Pa) between the first rows, from `from` up to `last`, at which the deviator has changed by
/// `f0` and by `f1` of `change` (f0 = 0: row `from` itself); NaN if it gets to neither with a strain change.
double branch_secant_between(const std::vector<double>& strain, const std::vector<double>& deviator, std::size_t from,
                             std::size_t last, double change, double f0, double f1);

std::vector<LoadingCycle> loading_cycles(const std::vector<double>& strain, const std::vector<double>& deviator,
                                         const std::vector<CurveSegment>& segments);

}  // namespace granulab
