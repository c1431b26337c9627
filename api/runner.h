// Runs a validated spec in-process and returns its results in the shapes users get: the summary
// JSON, the curve as CSV and as JSON columns, and each snapshot's compact JSON. Shared by the CLI and
// the server so that both give the same answer for the same spec.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/spec.h"

namespace granulab::api {

struct RunOutput {
  nlohmann::json summary;
  std::string curve_csv;
  std::vector<std::pair<double, nlohmann::json>> snapshots;  ///< strain, compact JSON
};

/// `progress` may stop the run (Cancelled is thrown). Uses the calling thread's OpenMP thread count.
RunOutput run_spec(const Spec& spec, const ProgressFn& progress = nullptr);

/// CSV text (header row first, numeric cells) as {"columns": [names], "<name>": [values], ...}.
nlohmann::json curve_csv_to_json(const std::string& csv);

/// A stable 64-bit FNV-1a hash of the normalised spec, as 16 hex digits: identical specs, same hash.
std::string spec_hash(const nlohmann::json& normalized_spec);

}  // namespace granulab::api
