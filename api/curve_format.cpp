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

std::string curve_csv_line(const std::vector<CurveColumn>& columns, const std::vector<double>& values) {
  std::string out;
  char cell[64];
  for (std::size_t k = 0; k < columns.size() && k < values.size(); ++k) {
    if (columns[k].digits == 0) std::snprintf(cell, sizeof cell, "%lld", static_cast<long long>(values[k]));
    else std::snprintf(cell, sizeof cell, "%.*g", columns[k].digits, values[k]);
    if (k) out += ',';
    out += cell;
  }
  return out + "\n";
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
