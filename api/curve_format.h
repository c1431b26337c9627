// Curves as text: CSV (header row first, docs/api.md) written one row at a time from an experiment's
// columns, and the JSON columns form that GET /v1/jobs/{id}/curve serves.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/stored_row.h"
#include "engine/framework/result_sink.h"

namespace granulab::api {

/// "name1,name2,...\n"
std::string curve_csv_header(const std::vector<CurveColumn>& columns);
/// One row, newline included: each value with its column's significant digits (integers as integers).
std::string curve_csv_line(const std::vector<CurveColumn>& columns, const std::vector<double>& values);
/// One row's values as its CSV line reads them (each rounded to its column's digits), as a JSON array
/// text: what the store keeps beside the line, so that a curve's JSON is built from numbers, not CSV.
std::string curve_row_values(const std::vector<CurveColumn>& columns, const std::vector<double>& values);
/// The columns form ({"columns": [names], "<name>": [values], ...}) of a header line and stored rows.
nlohmann::json curve_rows_to_json(const std::string& header, const std::vector<StoredRow>& rows);
/// CSV text (header row first, numeric cells) as {"columns": [names], "<name>": [values], ...}.
nlohmann::json curve_csv_to_json(const std::string& csv);

/// The rule of every resumed run: the header and the first `rows` rows of the curve it had written, which
/// the run continues after its checkpoint; nullopt when `csv` holds fewer rows (it is not that run's curve).
std::optional<std::string> resumed_curve(const std::string& csv, std::size_t rows);

}  // namespace granulab::api
