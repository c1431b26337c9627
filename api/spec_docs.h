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
/// JSON Schemas (2020-12, as OpenAPI 3.1 uses them) of the spec of every experiment, with ranges, defaults
/// and units: {"Spec": {"oneOf": [...]}, "Spec_<experiment>": {...}}; docs/openapi.json holds them (a test
/// keeps the file equal to this output).
nlohmann::json spec_schemas_json();
/// docs/spec.md.
std::string experiments_markdown();

}  // namespace granulab::api
