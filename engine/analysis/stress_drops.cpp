#include "engine/analysis/stress_drops.h"

#include <algorithm>
#include <cmath>

namespace granulab {

namespace {

StressDrop drop_between(const StressSample& peak, const StressSample& trough) {
  StressDrop d;
  d.strain = peak.strain, d.end_strain = trough.strain, d.peak = peak.value, d.size = peak.value - trough.value;
  d.duration = trough.time - peak.time, d.steps = trough.step - peak.step;
  return d;
}

}  // namespace

bool StressDropTracker::add(const StressSample& s, StressDrop& out) {
  if (!has_peak) {
    has_peak = true, in_drop = false, peak = s;
    return false;
  }
  if (!in_drop) {
    if (s.value >= peak.value) peak = s;
    else if (peak.value - s.value >= threshold) in_drop = true, trough = s;
    return false;
  }
  if (s.value <= trough.value) {
    trough = s;
    return false;
  }
  if (s.value - trough.value < threshold) return false;
  out = drop_between(peak, trough);
  in_drop = false, peak = s;
  return true;
}

bool StressDropTracker::close(StressDrop& out) {
  const bool ended = has_peak && in_drop;
  if (ended) out = drop_between(peak, trough);
  has_peak = in_drop = false;
  return ended;
}

void write_stress_drops(SummaryWriter& w, const std::vector<StressDrop>& drops, double threshold,
                        double loading_strain, std::size_t max_listed) {
  double largest = 0, total = 0;
  for (const StressDrop& d : drops) largest = std::max(largest, d.size), total += d.size;
  w.begin_group("stress_drops");
  w.number("threshold", threshold, "Pa");
  w.count("count", drops.size());
  w.number("largest", largest, "Pa");
  w.number("mean", drops.empty() ? 0.0 : total / double(drops.size()), "Pa");
  w.number("total", total, "Pa");
  w.number("rate", loading_strain > 0 ? double(drops.size()) / loading_strain : 0.0, "-");
  w.begin_list("size_distribution");
  if (threshold > 0)
    for (double from = threshold; from <= largest; from *= 2) {
      const auto n = std::count_if(drops.begin(), drops.end(), [&](const StressDrop& d) {
        return d.size >= from && d.size < 2 * from;
      });
      w.begin_group(nullptr);
      w.number("from", from, "Pa");
      w.number("to", 2 * from, "Pa");
      w.count("count", std::uint64_t(n));
      w.end_group();
    }
  w.end_list();
  w.begin_list("events");
  for (std::size_t k = 0; k < drops.size() && k < max_listed; ++k) {
    const StressDrop& d = drops[k];
    w.begin_group(nullptr);
    w.number("strain", d.strain, "-");
    w.number("end_strain", d.end_strain, "-");
    w.number("peak", d.peak, "Pa");
    w.number("size", d.size, "Pa");
    w.number("duration", d.duration, "s");
    w.count("steps", d.steps);
    w.end_group();
  }
  w.end_list();
  w.end_group();
}

}  // namespace granulab
