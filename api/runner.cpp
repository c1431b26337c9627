#include "api/runner.h"

#include <algorithm>
#include <cstdio>

#include "engine/core/checkpoint.h"

#include "api/curve_format.h"
#include "api/snapshot_files.h"
#include "api/summary_json.h"

namespace granulab::api {

void MemorySink::begin(const std::vector<CurveColumn>& columns, const Resume* resume) {
  columns_ = columns;
  if (!resume || curve_csv_.empty()) curve_csv_ = curve_csv_header(columns);
  if (!resume) return snapshots_.clear();
  auto kept = resumed_curve(curve_csv_, resume->rows);
  if (!kept) throw CheckpointError("the sink holds fewer curve rows than the checkpoint follows");
  curve_csv_ = std::move(*kept);
  if (snapshots_.size() > resume->snapshots) snapshots_.resize(resume->snapshots);
}

void MemorySink::curve_row(const std::vector<double>& values) { curve_csv_ += curve_csv_line(columns_, values); }

void MemorySink::snapshot(std::size_t, const GrainSnapshot& s) { snapshots_.emplace_back(s.strain, snapshot_json(s)); }

nlohmann::json run(const Spec& spec, JobSink& sink, const Resume* resume) {
  sink.begin(spec.experiment->curve_columns(), resume);
  const std::unique_ptr<ExperimentResult> result = spec.experiment->run(sink, resume ? &resume->state : nullptr);
  nlohmann::json summary = summary_json(spec, *result);
  sink.summary(summary);
  return summary;
}

RunOutput run_spec(const Spec& spec, const ProgressFn& progress) {
  MemorySink sink(progress);
  run(spec, sink);
  return {std::move(sink.summary_), std::move(sink.curve_csv_), std::move(sink.snapshots_)};
}

std::string spec_hash(const nlohmann::json& normalized_spec) {
  // The label is a name, not physics: two runs that differ only in it are the same run (reuse finds it).
  nlohmann::json physics = normalized_spec;
  if (physics.is_object()) physics.erase("label");
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the canonical dump (keys sorted by nlohmann)
  for (unsigned char c : physics.dump()) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace granulab::api
