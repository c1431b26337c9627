// The one runner: drives any registered experiment of a validated spec and writes everything it makes
// through a JobSink. The CLI (`granulab run`, files), the server's workers (the store) and the tests
// (memory) all run jobs through here, so they give the same answer for the same spec.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/job_sink.h"
#include "api/spec.h"

namespace granulab::api {

/// Runs the spec with the calling thread's OpenMP thread count. Throws Cancelled when the sink asks to
/// stop, std::invalid_argument / std::runtime_error when the run cannot be made or fails. Returns the
/// summary it gave the sink.
/// With `resume`, continues a checkpointed run of the same spec (the sink trims its results to the
/// checkpoint's counts first); the answer is bit for bit that of an uninterrupted run.
nlohmann::json run(const Spec& spec, JobSink& sink, const Resume* resume = nullptr);

/// Everything a run made, in memory.
struct RunOutput {
  nlohmann::json summary;
  std::string curve_csv;
  std::vector<std::pair<double, nlohmann::json>> snapshots;  ///< strain, compact JSON
};
/// run() into a MemorySink; `progress` may stop the run.
RunOutput run_spec(const Spec& spec, const ProgressFn& progress = nullptr);

/// A stable 64-bit FNV-1a hash of the normalised spec without its label, as 16 hex digits: specs that
/// differ only in their label (or in key order, or in defaults left out) have the same hash.
std::string spec_hash(const nlohmann::json& normalized_spec);

}  // namespace granulab::api
