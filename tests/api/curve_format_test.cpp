// A curve's JSON is built from its rows' values, never from its CSV, and still reads exactly as the CSV
// does: the same rounding per column, integer counts as integers, and rows stored without values (by an
// older build) read from their line. The resumed-curve rule keeps the header and the first n rows.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/curve_format.h"

namespace granulab::api {
namespace {

const std::vector<CurveColumn> kColumns = {
    {"strain", "-", "axial strain"}, {"stress", "Pa", "a stress", 4}, {"contacts", "-", "a count", 0}};

TEST(CurveFormat, RowValuesReadAsTheCsvLineDoesAndOldRowsFallBackToTheirLine) {
  const std::vector<std::vector<double>> values = {
      {0, 29996.4757, 1863}, {2.577380723722822e-05, 42467.0244, 1844.9}, {1.0 / 3, -3.5242745, 7}};
  std::string csv = curve_csv_header(kColumns);
  std::vector<StoredRow> rows;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const std::string line = curve_csv_line(kColumns, values[k]);
    csv += line;
    // The middle row as an older build stored it: its line only.
    rows.push_back({line, k == 1 ? "" : curve_row_values(kColumns, values[k])});
  }
  const nlohmann::json from_rows = curve_rows_to_json(curve_csv_header(kColumns), rows);
  EXPECT_EQ(from_rows, curve_csv_to_json(csv));
  EXPECT_EQ(from_rows.dump(), curve_csv_to_json(csv).dump());  // byte for byte, as served
  EXPECT_EQ(from_rows["stress"][0], 3e4);       // 4 significant digits, as the CSV cell "3e+04"; 9 by default
  EXPECT_EQ(from_rows["contacts"][1], 1844.0);  // a count, truncated as the CSV writes it
  EXPECT_EQ(nlohmann::json::parse(curve_row_values(kColumns, values[2])),
            nlohmann::json::parse("[0.333333333,-3.524,7.0]"));
}

TEST(CurveFormat, AResumedCurveKeepsTheHeaderAndTheRowsItsCheckpointFollows) {
  const std::string csv = "a,b\n1,2\n3,4\n5,6\n";
  EXPECT_EQ(resumed_curve(csv, 0), "a,b\n");
  EXPECT_EQ(resumed_curve(csv, 2), "a,b\n1,2\n3,4\n");
  EXPECT_EQ(resumed_curve(csv, 3), csv);
  EXPECT_FALSE(resumed_curve(csv, 4));  // fewer rows than the checkpoint follows: not that run's curve
}

}  // namespace
}  // namespace granulab::api
