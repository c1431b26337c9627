// How quasi-static a crystal compression was, measured on its own curve and predicted from its rate
// (docs/results.md, "Quasi-static rate"): a curve run too fast is stronger than the material's, and nothing
// else in a job would tell its user. Written to the summary as "quasi_static"; a likely bias over 2 %
// becomes a warning, which the CLI, the page and the summary show.
#pragma once

#include <string>
#include <vector>

#include "engine/experiments/crystal_compression/crystal_compression.h"

namespace granulab {

struct QuasiStaticQuality {
  double rate_over_quasi_static = 0;  ///< R / (p0 / E): 1.5 at the default rate (-)
  /// The calibration's expected bias of the curve at that rate (first yield and strain-window means,
  /// the largest, relative to a converged rate) (-).
  double expected_bias = 0;
  /// |top - bottom| / their mean over the rows past 0.05 % strain: root mean square and largest (-).
  double platen_imbalance_rms = 0, platen_imbalance_max = 0;
  /// Kinetic over elastic energy over the same rows: mean and largest (-).
  double kinetic_elastic_mean = 0, kinetic_elastic_max = 0;
  /// The rise of an inclined {111} slip plane across the crystal's width over its length, 2 grains_x /
  /// rows_z: at 1 or more every inclined slip plane meets a platen (-).
  double slip_plane_span = 0;
  std::vector<std::string> warnings;  ///< likely bias over 2 %, or a measured sign of dynamics
  std::vector<std::string> hints;     ///< structural facts that set the curve apart from the paper's crystal
};

/// The calibration (docs/results.md, "Quasi-static rate"): the largest bias measured at R = ratio x p0/E,
/// interpolated linearly between measured ratios (-).
double expected_rate_bias(double ratio);

QuasiStaticQuality assess_quasi_static(const CrystalParams& p, const CrystalResult& r);

}  // namespace granulab
