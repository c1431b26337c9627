// What the server draws of a curve: one job's (crystal: deviator and both platens against strain,
// first yield marked; two cubes: P/P0 and T/P0 against u/l with eq. 1 dashed; anything else: its
// stress columns against its first column), and a sweep's overlaid with a legend of the varied values.
// Inputs are the JSON forms the store serves (curve columns, spec, summary), so a running job's rows
// so far draw the same way as a finished curve.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/pictures/line_plot.h"

namespace granulab::pictures {

/// One job: `curve` is {"columns": [...], name: [values], ...}; `summary` may be null (still running).
LinePlot job_curve_plot(const nlohmann::json& spec, const nlohmann::json& curve, const nlohmann::json& summary);

struct SweepCurve {
  nlohmann::json values;  ///< the varied values, {"dotted.key": value}
  nlohmann::json spec;
  nlohmann::json curve;   ///< as for job_curve_plot; may have no rows yet
  std::string status;
};
/// A sweep's main curves overlaid (the crystal's deviator, the two cubes' T/P0), labelled by their values.
LinePlot sweep_curves_plot(const std::string& title, const std::vector<SweepCurve>& jobs, std::size_t left_out);

}  // namespace granulab::pictures
