#include "engine/analysis/curve_peak.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granulab {

CurvePeak first_peak(const std::vector<double>& values, double floor, double drop) {
  CurvePeak p;
  bool started = false;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double v = values[k];
    p.highest = std::max(p.highest, v);
    if (p.found) continue;
    if (!started) {
      if (v < floor) continue;  // still in the noise around zero
      started = true;
      p.value = v, p.row = k;
    } else if (v > p.value) {
      p.value = v, p.row = k;
    } else if (v < p.value - drop * p.value) {
      p.found = true;
    }
  }
  return p;
}

CurvePeak highest_peak(const std::vector<double>& values, double floor, double drop) {
  CurvePeak p;
  for (std::size_t k = 0; k < values.size(); ++k)
    if (values[k] > p.highest) p.highest = values[k], p.row = k;
  p.value = p.highest;
  if (!(p.highest >= floor)) return p;
  for (std::size_t k = p.row + 1; k < values.size() && !p.found; ++k)
    if (values[k] < p.highest - drop * p.highest) p.found = true;
  return p;
}

std::string missing_peak_reason(const std::string& what_end, const std::string& highest) {
  return "none to " + what_end + " (no drop after its largest, " + highest + ")";
}

bool begin_curve_peak(SummaryWriter& w, const char* key, const CurvePeak& p, const std::string& reason) {
  w.begin_group(key);
  w.flag("found", p.found);
  if (!p.found) w.text("reason", reason);
  return p.found;
}

std::string percent_text(double strain) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g %%", 100 * strain);
  return text;
}

}  // namespace granulab
