// The registered experiments described from the registry itself: their spec fields (default, allowed
// values, unit, meaning) and curve columns, as JSON (GET /v1/experiments, `granulab experiments`) and as
// the markdown of docs/spec.md (a test keeps that file equal to this output).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace granulab::api {

/// {"experiments": [{"name", "title", "fields": [{"field", "type", "default", "minimum", "maximum",
/// "exclusive_minimum", "unit", "choices", "meaning"}], "curve_columns": [{"name", "unit", "meaning"}]}]}
nlohmann::json experiments_json();
/// docs/spec.md.
std::string experiments_markdown();

}  // namespace granulab::api
