#include "api/runner.h"

#include <cstdio>
#include <cstring>

#include "engine/core/checkpoint.h"

#include "api/curve_format.h"
#include "api/snapshot_files.h"
#include "api/summary_json.h"

namespace granulab::api {

void MemorySink::begin(const std::vector<CurveColumn>& columns, const Resume* resume) {
  columns_ = columns;
  if (!resume || curve_csv_.empty()) curve_csv_ = curve_csv_header(columns);
  if (!resume) return snapshots_.clear();
  curve_csv_.resize(curve_csv_prefix(curve_csv_, resume->rows));
  if (snapshots_.size() > resume->snapshots) snapshots_.resize(resume->snapshots);
}

void MemorySink::curve_row(const std::vector<double>& values) { curve_csv_ += curve_csv_line(columns_, values); }

void MemorySink::snapshot(std::size_t, const GrainSnapshot& s) { snapshots_.emplace_back(s.strain, snapshot_json(s)); }

std::string pack_resume(const Resume& resume) {
  const std::uint64_t counts[2] = {resume.rows, resume.snapshots};
  return std::string(reinterpret_cast<const char*>(counts), sizeof counts) + resume.state;
}

Resume unpack_resume(const std::string& bytes) {
  std::uint64_t counts[2] = {0, 0};
  if (bytes.size() < sizeof counts) throw CheckpointError("checkpoint truncated");
  std::memcpy(counts, bytes.data(), sizeof counts);
  Resume r{bytes.substr(sizeof counts), std::size_t(counts[0]), std::size_t(counts[1])};
  CheckpointReader check(r.state);  // the frame and checksum, before anything is trimmed
  return r;
}

nlohmann::json run(const Spec& spec, JobSink& sink, const Resume* resume) {
  sink.begin(spec.experiment->curve_columns(), resume);
  const std::unique_ptr<ExperimentResult> result = spec.experiment->run(sink, resume ? resume->state : std::string());
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
