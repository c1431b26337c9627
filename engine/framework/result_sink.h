// Where a running experiment puts what it makes, as it makes it: curve rows, grain snapshots and its
// progress. The experiment knows nothing of files, databases or terminals; the CLI's sink writes the
// files of `granulab run`, the server's writes rows and snapshots into its store in batches, tests
// keep them in memory. The summary, written when the run ends, is the api's part (api/job_sink.h).
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/analysis/grain_snapshot.h"
#include "engine/core/checkpoint.h"

namespace granulab {

/// One column of an experiment's curve.
struct CurveColumn {
  const char* name;     ///< CSV header and JSON key
  const char* unit;     ///< SI unit, "-" for a ratio
  const char* meaning;  ///< for the docs
  int digits = 9;       ///< significant digits written; 0 = an integer count
};

/// Thrown by an experiment whose sink asked it to stop.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

class ResultSink {
 public:
  virtual ~ResultSink() = default;
  /// One curve row, in the order of the experiment's columns(), when it is recorded.
  virtual void curve_row(const std::vector<double>& values) { (void)values; }
  /// Snapshot `index` (0, 1, ... in the order taken) when it is taken.
  virtual void snapshot(std::size_t index, const GrainSnapshot& snapshot) { (void)index, (void)snapshot; }
  /// The completed fraction in [0, 1], at least every few hundred steps; return false to stop the run
  /// (the experiment then throws Cancelled). May throw to abandon the run.
  virtual bool progress(double fraction) {
    (void)fraction;
    return true;
  }
  /// Checkpoints (docs/architecture.md, "Checkpoints"): asked at the experiment's safe points, at least
  /// every few hundred steps; true when one should be written now.
  virtual bool checkpoint_due() { return false; }
  /// The run's full state after `rows` curve rows and `snapshots` snapshots went to this sink, written by
  /// `content` into a CheckpointWriter the sink makes (its chunks go where the sink keeps them, so the
  /// state is never whole in memory): a run resumed from it (Experiment::run) continues bit for bit,
  /// starting with row `rows` and snapshot `snapshots`. Keep it with those counts, atomically; a sink
  /// that keeps none need not call `content` at all.
  virtual void checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) {
    (void)content, (void)rows, (void)snapshots;
  }
};

/// The progress callback of the physics classes, for callers that want nothing else.
using ProgressFn = std::function<bool(double fraction)>;

}  // namespace granulab
