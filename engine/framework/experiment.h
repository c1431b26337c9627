// The one interface every experiment implements, so that the spec reader, the runner, the CLI, the
// server, the API schema and the docs handle any experiment the same way (docs/architecture.md, "Add
// an experiment"). An Experiment holds its parameters (the paper's defaults until a spec is read into
// them), runs them, streaming its curve and snapshots to a ResultSink, and returns a result that
// writes its own summary.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/analysis/yield_estimate.h"
#include "engine/framework/headline.h"
#include "engine/framework/parameters.h"
#include "engine/framework/result_sink.h"
#include "engine/framework/summary_writer.h"
#include "engine/framework/workload.h"

namespace granulab {

/// A finished run's result, beyond its curve and snapshots.
class ExperimentResult {
 public:
  virtual ~ExperimentResult() = default;
  /// The summary fields: write_run_stats(...) and the experiment's own.
  virtual void write_summary(SummaryWriter& w) const = 0;
};

class Experiment {
 public:
  virtual ~Experiment() = default;
  /// Visits every parameter (see parameters.h): reading a spec fills them.
  virtual void parameters(ParameterVisitor& v) = 0;
  /// The curve's columns; curve rows hold one value per column, in this order.
  virtual const std::vector<CurveColumn>& curve_columns() const = 0;
  /// What it shows first (headline.h): its curve's axes and series, key summary values and tables, and
  /// the closed forms for the parameters as they are.
  virtual Headline headline() const = 0;
  /// The run's size and length from the parameters as they are, without building anything (cheap).
  virtual Workload workload() const = 0;
  /// A rigid-grain estimate of where its curve first yields (yield_estimate.h), from the parameters as they are in
  /// about a millisecond, for dry runs, `granulab estimate` and the curve picture; none by default.
  virtual std::optional<YieldEstimate> yield_estimate() const { return std::nullopt; }
  /// Runs with the parameters as they are, from the start or, with `resume`, from a checkpoint the sink
  /// was given by a run of the same parameters (CheckpointError if it is not one). Throws Cancelled
  /// when the sink asks to stop, std::invalid_argument for parameters the physics cannot run,
  /// std::runtime_error for a failed run.
  virtual std::unique_ptr<ExperimentResult> run(ResultSink& sink, const CheckpointSource* resume) const = 0;
};

}  // namespace granulab
