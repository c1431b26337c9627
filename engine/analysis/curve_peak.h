// A peak of a loading curve, or the honest statement that there was none. A crystal that locks and stiffens to the
// end of its run has no first yield, and the curve's last row is not one: a study ranked by "first yield" would take
// "still rising" for a yield (issue 51). Every experiment that reports a yield, a peak or a strength finds it here
// and writes it with write_curve_peak(): `found` always, the numbers only when found, a `reason` when not.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/framework/summary_writer.h"

namespace granulab {

struct CurvePeak {
  bool found = false;   ///< the signal fell `drop` below its running maximum after it
  std::size_t row = 0;  ///< where the maximum is (the last row above `floor` when not found) (-)
  double value = 0;     ///< the signal there (its unit)
  double highest = 0;   ///< the largest value over the whole curve (its unit)
};

/// The first peak of `values`: once a value reaches `floor` (the noise around zero below it), the largest value
/// before the signal first falls `drop` (relative, e.g. 0.02) below its running maximum. Not found when it never
/// falls so: still rising or level at the end, or never above `floor`.
CurvePeak first_peak(const std::vector<double>& values, double floor, double drop);

/// The largest value of the whole curve, found when the signal falls `drop` below it afterwards (a true peak, not
/// the end of a rise).
CurvePeak highest_peak(const std::vector<double>& values, double floor, double drop);

/// The sentence that says why a peak was not found, e.g. "none to 1 % strain (no drop after its largest, 38.1 p0)":
/// `what_end` the run's end ("1 % strain"), `highest` the largest value in the reading's words ("38.1 p0").
std::string missing_peak_reason(const std::string& what_end, const std::string& highest);

/// Opens the summary group `key` with `found` and, when not found, `reason`; the caller writes the numbers when
/// found and closes the group (end_group()). Returns p.found.
bool begin_curve_peak(SummaryWriter& w, const char* key, const CurvePeak& p, const std::string& reason);

/// "1 %", "0.25 %", "12 %": a strain as a researcher reads it (two significant digits at most).
std::string percent_text(double strain);

}  // namespace granulab
