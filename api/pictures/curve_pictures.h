// What the server draws of a curve, as its experiment's headline says (engine/framework/headline.h):
// one job's series against its x column, its key values marked and named in the legend, its closed forms
// dashed; a sweep's first series overlaid with a legend of the varied values. In the experiment's natural
// units (p0 for a crystal) or SI, and any one column instead of the headline's series (?y=).
// Inputs are the JSON forms the store serves (curve columns, spec, summary), so a running job's rows
// so far draw the same way as a finished curve.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/pictures/line_plot.h"
#include "engine/framework/headline.h"

namespace granulab::pictures {

enum class Units { natural, si };

/// What the reader asked for: the units, and one column to draw instead of the headline's series.
struct CurveChoice {
  Units units = Units::natural;
  std::string y;  ///< a curve column; empty = the headline's series
};

/// The headline of a job's experiment for its (normalised) spec: with the closed forms for its
/// parameters, or, for a spec this build cannot read, the registered experiment's without them; a first
/// column against the second for an experiment it does not know.
Headline headline_for(const nlohmann::json& spec);
/// The curve columns of the job's experiment (empty for one this build does not know).
std::vector<std::string> curve_column_names(const nlohmann::json& spec);

/// One job: `curve` is {"columns": [...], name: [values], ...}; `summary` may be null (still running).
LinePlot job_curve_plot(const nlohmann::json& spec, const nlohmann::json& curve, const nlohmann::json& summary,
                        const CurveChoice& choice = {});

struct SweepCurve {
  nlohmann::json values;  ///< the varied values, {"dotted.key": value}
  nlohmann::json spec;
  nlohmann::json curve;  ///< as for job_curve_plot; may have no rows yet
  std::string status;
};
/// A sweep's curves overlaid (each job's first headline series, or the chosen column), labelled by their values.
LinePlot sweep_curves_plot(const std::string& title, const std::vector<SweepCurve>& jobs, std::size_t left_out,
                           const CurveChoice& choice = {});

}  // namespace granulab::pictures
