#include "api/curve_format.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace granulab::api {

std::string curve_csv_header(const std::vector<CurveColumn>& columns) {
  std::string out;
  for (const CurveColumn& c : columns) out += (out.empty() ? "" : ",") + std::string(c.name);
  return out + "\n";
}

namespace {

// One cell: an integer count as an integer, anything else with its column's significant digits.
void format_cell(const CurveColumn& column, double value, char (&cell)[64]) {
  if (column.digits == 0) std::snprintf(cell, sizeof cell, "%lld", static_cast<long long>(value));
  else std::snprintf(cell, sizeof cell, "%.*g", column.digits, value);
}

std::vector<std::string> header_names(const std::string& header) {
  std::vector<std::string> names;
  std::istringstream in(header.substr(0, header.find('\n')));
  for (std::string name; std::getline(in, name, ',');) names.push_back(name);
  return names;
}

}  // namespace

std::string curve_csv_line(const std::vector<CurveColumn>& columns, const std::vector<double>& values) {
  std::string out;
  char cell[64];
  for (std::size_t k = 0; k < columns.size() && k < values.size(); ++k) {
    format_cell(columns[k], values[k], cell);
    if (k) out += ',';
    out += cell;
  }
  return out + "\n";
}

std::string curve_row_values(const std::vector<CurveColumn>& columns, const std::vector<double>& values) {
  nlohmann::json row = nlohmann::json::array();
  char cell[64];
  for (std::size_t k = 0; k < columns.size() && k < values.size(); ++k) {
    format_cell(columns[k], values[k], cell);
    row.push_back(std::strtod(cell, nullptr));  // the value the CSV cell reads as: JSON and CSV agree
  }
  return row.dump();
}

nlohmann::json curve_rows_to_json(const std::string& header, const std::vector<StoredRow>& rows) {
  const std::vector<std::string> names = header_names(header);
  nlohmann::json out = nlohmann::json::object();
  for (const std::string& name : names) out[name] = nlohmann::json::array();
  for (const StoredRow& row : rows) {
    nlohmann::json values = row.values.empty() ? nlohmann::json() : nlohmann::json::parse(row.values, nullptr, false);
    if (!values.is_array()) {  // stored without its values: its line, read as the CSV reader does
      const nlohmann::json one = curve_csv_to_json(header.substr(0, header.find('\n') + 1) + row.csv);
      values = nlohmann::json::array();
      for (const std::string& name : names)
        if (one.contains(name) && !one[name].empty()) values.push_back(one[name][0]);
    }
    for (std::size_t k = 0; k < names.size() && k < values.size(); ++k) out[names[k]].push_back(values[k]);
  }
  out["columns"] = names;
  return out;
}

nlohmann::json curve_csv_to_json(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> names;
  nlohmann::json out = nlohmann::json::object();
  if (std::getline(in, line)) {
    std::istringstream header(line);
    for (std::string name; std::getline(header, name, ',');) {
      names.push_back(name);
      out[name] = nlohmann::json::array();
    }
  }
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::size_t k = 0;
    // strtod, not stod: a cell that is not a number becomes 0 instead of an exception in a handler.
    for (std::string cell; std::getline(row, cell, ',') && k < names.size(); ++k)
      out[names[k]].push_back(std::strtod(cell.c_str(), nullptr));
  }
  out["columns"] = names;
  return out;
}

std::optional<std::string> resumed_curve(const std::string& csv, std::size_t rows) {
  std::size_t end = 0;
  for (std::size_t line = 0; line <= rows; ++line) {  // the header, then `rows` rows
    const auto newline = csv.find('\n', end);
    if (newline == std::string::npos) return std::nullopt;
    end = newline + 1;
  }
  return csv.substr(0, end);
}

}  // namespace granulab::api
