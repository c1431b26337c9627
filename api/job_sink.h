// The sink a whole job writes to: what an experiment streams while it runs (curve rows, snapshots,
// progress: engine/framework/result_sink.h), plus the curve's columns before it starts and the
// summary when it ends. The CLI writes files through one, the server its store, tests memory.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/framework/result_sink.h"

namespace granulab::api {

/// A checkpoint as a job keeps it: the engine's state (ResultSink::checkpoint), read from wherever the
/// sink put it, and how many curve rows and snapshots the job's results held when it was taken.
struct Resume {
  CheckpointSource state;
  std::size_t rows = 0, snapshots = 0;
};

class JobSink : public ResultSink {
 public:
  /// Before the run: the experiment's curve columns (what its rows will hold). With `resume`, the run
  /// continues from that checkpoint: the sink keeps the first resume->rows rows and resume->snapshots
  /// snapshots it already holds and drops any later ones (made after the checkpoint, made again now).
  virtual void begin(const std::vector<CurveColumn>& columns, const Resume* resume) { (void)columns, (void)resume; }
  /// After a successful run: summary.json.
  virtual void summary(const nlohmann::json& summary) = 0;
};

/// Keeps everything in memory, in the shapes users get (tests, and callers that want it all at once).
class MemorySink : public JobSink {
 public:
  explicit MemorySink(ProgressFn progress = nullptr) : progress_(std::move(progress)) {}
  void begin(const std::vector<CurveColumn>& columns, const Resume* resume) override;
  void curve_row(const std::vector<double>& values) override;
  void snapshot(std::size_t index, const GrainSnapshot& s) override;
  bool progress(double fraction) override { return !progress_ || progress_(fraction); }
  void summary(const nlohmann::json& s) override { summary_ = s; }

  nlohmann::json summary_;
  std::string curve_csv_;                                     ///< header row first
  std::vector<std::pair<double, nlohmann::json>> snapshots_;  ///< strain, compact JSON

 private:
  ProgressFn progress_;
  std::vector<CurveColumn> columns_;
};

}  // namespace granulab::api
