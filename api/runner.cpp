#include "api/runner.h"

#include <cstdio>

#include "api/curve_format.h"
#include "api/snapshot_files.h"
#include "api/summary_json.h"

namespace granulab::api {

void MemorySink::begin(const std::vector<CurveColumn>& columns) {
  columns_ = columns;
  curve_csv_ = curve_csv_header(columns);
}

void MemorySink::curve_row(const std::vector<double>& values) { curve_csv_ += curve_csv_line(columns_, values); }

void MemorySink::snapshot(std::size_t, const GrainSnapshot& s) { snapshots_.emplace_back(s.strain, snapshot_json(s)); }

nlohmann::json run(const Spec& spec, JobSink& sink) {
  sink.begin(spec.experiment->curve_columns());
  const std::unique_ptr<ExperimentResult> result = spec.experiment->run(sink);
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
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the canonical dump (keys sorted by nlohmann)
  for (unsigned char c : normalized_spec.dump()) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace granulab::api
