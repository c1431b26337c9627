// A curve row as the daemon stores it: its values as the CSV reads them (a JSON array text, built by
// api::curve_row_values) beside its CSV line. Plain strings, so the store needs neither JSON nor the api.
#pragma once

#include <string>

namespace granulab::api {

struct StoredRow {
  std::string csv;     ///< its CSV line, newline included
  std::string values;  ///< its values, "[...]"; empty for a row stored by an older build (then read from csv)
};

}  // namespace granulab::api
